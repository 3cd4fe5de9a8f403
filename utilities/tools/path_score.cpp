#include "path_score.hpp"

#include <algorithm>
#include <cmath>
#include <map>

namespace roam {

double MatchedPosition::error_m() const {
  return std::hypot(estimate_x_m - truth_x_m, estimate_y_m - truth_y_m);
}

std::vector<MatchedPosition> matchToGroundTruth(const Path& estimate, const Path& ground_truth) {
  Path sorted = estimate;
  std::stable_sort(sorted.begin(), sorted.end(),
                   [](const Pose& a, const Pose& b) { return a.utime < b.utime; });
  Path path;  // strictly increasing times; the last of equal times wins
  for (const Pose& p : sorted) {
    if (!path.empty() && path.back().utime == p.utime) path.back() = p;
    else path.push_back(p);
  }
  std::vector<MatchedPosition> matched;
  if (path.empty()) return matched;
  for (const Pose& truth : ground_truth) {
    const int64_t t = truth.utime;
    if (t < path.front().utime || t > path.back().utime) continue;
    // First estimate pose with time >= t.
    const auto upper = std::lower_bound(path.begin(), path.end(), t,
                                        [](const Pose& p, int64_t time) { return p.utime < time; });
    MatchedPosition m;
    m.utime = t;
    m.truth_x_m = truth.x_m;
    m.truth_y_m = truth.y_m;
    if (upper->utime == t) {
      m.estimate_x_m = upper->x_m;
      m.estimate_y_m = upper->y_m;
    } else {
      const Pose& a = *(upper - 1);
      const Pose& b = *upper;
      const double w = static_cast<double>(t - a.utime) / static_cast<double>(b.utime - a.utime);
      m.estimate_x_m = a.x_m + w * (b.x_m - a.x_m);
      m.estimate_y_m = a.y_m + w * (b.y_m - a.y_m);
    }
    matched.push_back(m);
  }
  return matched;
}

void Rigid2D::apply(double* x_m, double* y_m) const {
  const double c = std::cos(angle_rad), s = std::sin(angle_rad);
  const double x = *x_m, y = *y_m;
  *x_m = c * x - s * y + tx_m;
  *y_m = s * x + c * y + ty_m;
}

Rigid2D fitRigid2D(const std::vector<MatchedPosition>& matched) {
  Rigid2D fit;
  if (matched.empty()) return fit;
  const double n = static_cast<double>(matched.size());
  double ex = 0, ey = 0, gx = 0, gy = 0;
  for (const auto& m : matched) {
    ex += m.estimate_x_m; ey += m.estimate_y_m; gx += m.truth_x_m; gy += m.truth_y_m;
  }
  ex /= n; ey /= n; gx /= n; gy /= n;
  // 2-D Kabsch: the angle maximising sum of dot(R e', g') is atan2(sum cross, sum dot).
  double dot = 0, cross = 0;
  for (const auto& m : matched) {
    const double ax = m.estimate_x_m - ex, ay = m.estimate_y_m - ey;
    const double bx = m.truth_x_m - gx, by = m.truth_y_m - gy;
    dot += ax * bx + ay * by;
    cross += ax * by - ay * bx;
  }
  fit.angle_rad = (dot == 0.0 && cross == 0.0) ? 0.0 : std::atan2(cross, dot);
  const double c = std::cos(fit.angle_rad), s = std::sin(fit.angle_rad);
  fit.tx_m = gx - (c * ex - s * ey);
  fit.ty_m = gy - (s * ex + c * ey);
  return fit;
}

Rigid2D fitRigid2D(const std::vector<std::vector<MatchedPosition>>& paths) {
  std::vector<MatchedPosition> all;
  for (const auto& path : paths) all.insert(all.end(), path.begin(), path.end());
  return fitRigid2D(all);
}

double beaconError(const Map& estimated_map, const Map& true_map, const std::optional<Rigid2D>& fit,
                   size_t* compared) {
  std::map<int, const Beacon*> truth;
  for (const Beacon& b : true_map) truth[b.id] = &b;
  double sum = 0;
  size_t n = 0;
  for (const Beacon& b : estimated_map) {
    const auto it = truth.find(b.id);
    if (it == truth.end()) continue;
    double x = b.x_m, y = b.y_m;
    if (fit) fit->apply(&x, &y);
    sum += std::hypot(x - it->second->x_m, y - it->second->y_m);
    ++n;
  }
  if (compared) *compared = n;
  return n > 0 ? sum / static_cast<double>(n) : kNaN;
}

ErrorStats errorStats(const std::vector<double>& errors_m, size_t begin, size_t end) {
  ErrorStats stats;
  if (end <= begin) return stats;
  double sum = 0, sum_sq = 0;
  for (size_t i = begin; i < end; ++i) {
    sum += errors_m[i];
    sum_sq += errors_m[i] * errors_m[i];
  }
  stats.count = end - begin;
  stats.mean_m = sum / static_cast<double>(stats.count);
  stats.rmse_m = std::sqrt(sum_sq / static_cast<double>(stats.count));
  return stats;
}

PathScore scorePath(const Path& estimate, const Path& ground_truth, bool aligned,
                    const std::optional<Map>& estimated_map, const std::optional<Map>& true_map) {
  PathScore score;
  std::vector<MatchedPosition> matched = matchToGroundTruth(estimate, ground_truth);
  std::optional<Rigid2D> fit;
  if (aligned && !matched.empty()) {
    fit = fitRigid2D(matched);
    for (auto& m : matched) fit->apply(&m.estimate_x_m, &m.estimate_y_m);
    score.alignment = fit;
  }
  const size_t n = matched.size();
  score.matched = n;
  std::vector<double> errors(n);
  for (size_t i = 0; i < n; ++i) errors[i] = matched[i].error_m();
  if (n > 0) {
    score.full = errorStats(errors, 0, n);
    score.max_m = *std::max_element(errors.begin(), errors.end());
    for (int c = 0; c < 10; ++c) {
      const ErrorStats chunk = errorStats(errors, c * n / 10, (c + 1) * n / 10);
      if (chunk.count == 0) continue;
      if (c == 9) score.last10 = chunk;
      if (score.best10.count == 0 || chunk.mean_m < score.best10.mean_m) score.best10 = chunk;
      if (score.worst10.count == 0 || chunk.mean_m > score.worst10.mean_m) score.worst10 = chunk;
    }
  }
  if (estimated_map && true_map)
    score.beacon_error_m = beaconError(*estimated_map, *true_map, fit, &score.beacons_compared);
  return score;
}

}  // namespace roam
