#include "roam/range_fit.hpp"

#include <algorithm>
#include <cmath>
#include <map>

namespace roam {
namespace {

struct Point {
  double x_m = 0.0, y_m = 0.0;
};

// p(t): linear in time between the poses either side of t (clamped at the ends).
Point positionAt(const Path& path, int64_t utime) {
  const auto after = std::lower_bound(path.begin(), path.end(), utime,
                                      [](const Pose& pose, int64_t t) { return pose.utime < t; });
  if (after == path.begin()) return {path.front().x_m, path.front().y_m};
  if (after == path.end()) return {path.back().x_m, path.back().y_m};
  const Pose& b = *after;
  const Pose& a = *(after - 1);
  const double span = static_cast<double>(b.utime - a.utime);
  const double f = span > 0.0 ? static_cast<double>(utime - a.utime) / span : 1.0;
  return {a.x_m + f * (b.x_m - a.x_m), a.y_m + f * (b.y_m - a.y_m)};
}

struct Observation {
  Point from;
  double range_m;
};

double absCost(const std::vector<Observation>& obs, const Point& beacon) {
  double cost = 0.0;
  for (const auto& o : obs) cost += std::abs(std::hypot(beacon.x_m - o.from.x_m, beacon.y_m - o.from.y_m) - o.range_m);
  return cost;
}

// Least absolute deviations by iteratively reweighted Gauss-Newton (weight 1 / max(|e|, 1 mm)).
Point refine(const std::vector<Observation>& obs, Point beacon) {
  double cost = absCost(obs, beacon);
  for (int iteration = 0; iteration < 20; ++iteration) {
    double a00 = 0, a01 = 0, a11 = 0, g0 = 0, g1 = 0;
    for (const auto& o : obs) {
      const double dx = beacon.x_m - o.from.x_m, dy = beacon.y_m - o.from.y_m;
      const double d = std::max(std::hypot(dx, dy), 1e-9);
      const double e = d - o.range_m;
      const double w = 1.0 / std::max(std::abs(e), 1e-3);
      const double jx = dx / d, jy = dy / d;
      a00 += w * jx * jx;
      a01 += w * jx * jy;
      a11 += w * jy * jy;
      g0 += w * jx * e;
      g1 += w * jy * e;
    }
    const double det = a00 * a11 - a01 * a01;
    if (!(std::abs(det) > 1e-12 * (a00 * a11 + 1e-300))) break;
    Point next{beacon.x_m - (a11 * g0 - a01 * g1) / det, beacon.y_m - (a00 * g1 - a01 * g0) / det};
    const double next_cost = absCost(obs, next);
    if (!(next_cost < cost)) break;
    const double moved = std::hypot(next.x_m - beacon.x_m, next.y_m - beacon.y_m);
    beacon = next;
    cost = next_cost;
    if (moved < 1e-6) break;
  }
  return beacon;
}

// Starting points: the linear least-squares solution of |m|^2 - 2 m.p = r^2 - |p|^2 where the
// positions are spread, and either side of their mean along the normal of their main axis (a
// straight run leaves the side ambiguous; both are tried).
std::vector<Point> startingPoints(const std::vector<Observation>& obs) {
  double mx = 0, my = 0, mr = 0;
  for (const auto& o : obs) {
    mx += o.from.x_m;
    my += o.from.y_m;
    mr += o.range_m;
  }
  const double n = static_cast<double>(obs.size());
  mx /= n;
  my /= n;
  mr /= n;
  double sxx = 0, sxy = 0, syy = 0, sxb = 0, syb = 0;
  for (const auto& o : obs) {
    const double x = o.from.x_m - mx, y = o.from.y_m - my;
    // Centred: 2 m.(p - mean p) = (|p|^2 - r^2) - mean(|p|^2 - r^2), with m relative to the mean.
    const double b = (x * x + y * y - o.range_m * o.range_m);
    sxx += x * x;
    sxy += x * y;
    syy += y * y;
    sxb += x * b;
    syb += y * b;
  }
  std::vector<Point> starts;
  const double det = sxx * syy - sxy * sxy;
  if (det > 1e-9 * (sxx + syy) * (sxx + syy) && det > 0.0)
    starts.push_back({mx + 0.5 * (syy * sxb - sxy * syb) / det, my + 0.5 * (sxx * syb - sxy * sxb) / det});
  // The main axis of the positions, and its normal.
  const double angle = 0.5 * std::atan2(2.0 * sxy, sxx - syy);
  const double nx = -std::sin(angle), ny = std::cos(angle);
  starts.push_back({mx + mr * nx, my + mr * ny});
  starts.push_back({mx - mr * nx, my - mr * ny});
  return starts;
}

}  // namespace

std::vector<RangeRecord> rangesToScore(const std::vector<RangeRecord>& ranges, int64_t begin_utime,
                                       int64_t end_utime) {
  std::map<int, int> count;
  for (const auto& r : ranges)
    if (r.utime >= begin_utime && r.utime <= end_utime) ++count[r.beacon_id];
  std::vector<RangeRecord> out;
  for (const auto& r : ranges)
    if (r.utime >= begin_utime && r.utime <= end_utime && count[r.beacon_id] >= 3) out.push_back(r);
  return out;
}

RangeFit rangeFit(const Path& path, const std::vector<RangeRecord>& ranges) {
  RangeFit fit;
  if (path.empty()) return fit;
  std::map<int, std::vector<Observation>> by_beacon;
  for (const auto& r : ranges) by_beacon[r.beacon_id].push_back({positionAt(path, r.utime), r.range_m});
  double total = 0.0;
  for (const auto& [id, obs] : by_beacon) {
    (void)id;
    double best = -1.0;
    for (const Point& start : startingPoints(obs)) {
      const double cost = absCost(obs, refine(obs, start));
      if (best < 0.0 || cost < best) best = cost;
    }
    total += best;
    fit.ranges += static_cast<int64_t>(obs.size());
  }
  if (fit.ranges > 0) fit.mean_abs_residual_m = total / static_cast<double>(fit.ranges);
  return fit;
}

}  // namespace roam
