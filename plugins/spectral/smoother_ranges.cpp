// Ranges for the odometry smoother (model: smoother_ranges.hpp).
#include "smoother_ranges.hpp"
#include "roam/estimation/range_model.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "roam/estimation/median.hpp"

namespace roam::spectral {
namespace {

constexpr int kAlternations = 4;
constexpr int kGaussNewtonSteps = 10;
constexpr double kMinScale_m = 0.01;

// m re-fitted to ranges (already (r - o) / kappa) from the positions `at`.
Eigen::Vector2d refitBeacon(Eigen::Vector2d m, const std::vector<Eigen::Vector2d>& at,
                            const std::vector<double>& range_m) {
  std::vector<double> e(range_m.size()), abs_e(range_m.size());
  for (int step = 0; step < kGaussNewtonSteps; ++step) {
    for (size_t i = 0; i < range_m.size(); ++i) {
      e[i] = range_m[i] - (at[i] - m).norm();
      abs_e[i] = std::abs(e[i]);
    }
    const double scale_m = std::max(kMinScale_m, 1.4826 * estimation::upperMedian(abs_e));
    Eigen::Matrix2d H = Eigen::Matrix2d::Zero();
    Eigen::Vector2d g = Eigen::Vector2d::Zero();
    for (size_t i = 0; i < range_m.size(); ++i) {
      const double t = e[i] / (estimation::kTukey95 * scale_m);
      const Eigen::Vector2d d = m - at[i];
      const double distance_m = d.norm();
      if (!(std::abs(t) < 1.0) || !(distance_m > 1e-6)) continue;
      const double w = (1.0 - t * t) * (1.0 - t * t);
      const Eigen::Vector2d u = d / distance_m;  // d|m - p| / dm
      H += w * u * u.transpose();
      g += w * e[i] * u;
    }
    const Eigen::LDLT<Eigen::Matrix2d> solver(H);
    if (solver.info() != Eigen::Success) break;
    const Eigen::Vector2d move = solver.solve(g);
    if (!move.allFinite()) break;
    m += move;
    if (move.norm() < 1e-6) break;
  }
  return m;
}

}  // namespace

std::vector<SmootherRange> smootherRanges(const SpectralProblem& problem, const SpectralConfig& config,
                                          const SpectralSolution& solution, double* range_sigma_m) {
  const int N = static_cast<int>(problem.beacon_ids.size());
  const int T = static_cast<int>(solution.trajectory.size());
  *range_sigma_m = 0.0;
  if (T < 2 || static_cast<int>(solution.beacons.size()) != N) return {};
  std::vector<Eigen::Vector2d> m(N);
  std::vector<bool> held(N, false);
  for (int n = 0; n < N; ++n) {
    m[n] = Eigen::Vector2d(solution.beacons[n].x_m, solution.beacons[n].y_m);
    if (config.anchor == SpectralAnchor::kBeacons && problem.surveyed[n]) {
      m[n] = *problem.surveyed[n];
      held[n] = true;
    }
  }
  std::vector<SmootherRange> out;
  std::vector<std::vector<Eigen::Vector2d>> at(N);  // the path at each range's time
  std::vector<std::vector<double>> raw_m(N);
  std::vector<std::vector<size_t>> index(N);  // into out
  for (const RangeSample& r : problem.ranges) {
    const int upper = problem.path.lowerBound(r.utime);
    if (upper >= T || r.beacon < 0 || r.beacon >= N) continue;
    const int lower = std::max(0, upper - (problem.path.utime[upper] == r.utime ? 0 : 1));
    const double span = static_cast<double>(problem.path.utime[upper] - problem.path.utime[lower]);
    const double f = span > 0.0 ? static_cast<double>(r.utime - problem.path.utime[lower]) / span : 0.0;
    const Pose& a = solution.trajectory[lower];
    const Pose& b = solution.trajectory[upper];
    SmootherRange range;
    range.pose = lower;
    range.fraction = upper == lower ? 0.0 : f;
    range.range_m = r.range_m;
    index[r.beacon].push_back(out.size());
    out.push_back(range);
    at[r.beacon].emplace_back((1.0 - f) * a.x_m + f * b.x_m, (1.0 - f) * a.y_m + f * b.y_m);
    raw_m[r.beacon].push_back(r.range_m);
  }
  if (out.empty()) return {};
  double kappa = 1.0;
  std::vector<double> offset_m(N, 0.0);
  for (int alternation = 0; alternation < kAlternations; ++alternation) {
    std::vector<double> ratio;
    for (int n = 0; n < N; ++n)
      for (size_t i = 0; i < raw_m[n].size(); ++i) {
        const double distance_m = (at[n][i] - m[n]).norm();
        if (distance_m > 0.0) ratio.push_back((raw_m[n][i] - offset_m[n]) / distance_m);
      }
    if (!ratio.empty()) kappa = estimation::upperMedian(ratio);
    if (!(kappa > 0.0)) kappa = 1.0;
    for (int n = 0; n < N; ++n) {
      if (raw_m[n].empty()) continue;
      std::vector<double> error;
      for (size_t i = 0; i < raw_m[n].size(); ++i) error.push_back(raw_m[n][i] - kappa * (at[n][i] - m[n]).norm());
      offset_m[n] = estimation::upperMedian(error);
      if (held[n] || raw_m[n].size() < 3) continue;
      std::vector<double> corrected;
      for (double r : raw_m[n]) corrected.push_back((r - offset_m[n]) / kappa);
      m[n] = refitBeacon(m[n], at[n], corrected);
    }
  }
  std::vector<double> abs_e;
  for (int n = 0; n < N; ++n)
    for (size_t i = 0; i < index[n].size(); ++i) {
      SmootherRange& range = out[index[n][i]];
      range.range_m = (raw_m[n][i] - offset_m[n]) / kappa;
      range.beacon_x_m = m[n](0);
      range.beacon_y_m = m[n](1);
      abs_e.push_back(std::abs(range.range_m - (at[n][i] - m[n]).norm()));
    }
  *range_sigma_m = 1.4826 * estimation::upperMedian(abs_e);
  return out;
}

}  // namespace roam::spectral
