#include "initial_guess.hpp"

#include <Eigen/Dense>
#include <cmath>

namespace roam {
namespace batch {

std::vector<std::array<double, 3>> deadReckon(const std::array<double, 3>& start_pose,
                                              const std::vector<Odometry>& odometry) {
  std::vector<std::array<double, 3>> poses;
  poses.reserve(odometry.size() + 1);
  poses.push_back(start_pose);
  for (const Odometry& step : odometry) {
    const std::array<double, 3>& last = poses.back();
    poses.push_back({last[0] + step.delta_distance_m * std::cos(last[2]),
                     last[1] + step.delta_distance_m * std::sin(last[2]),
                     last[2] + step.delta_heading_rad});
  }
  return poses;
}

void headingsFromChords(const std::vector<int64_t>& utime, double half_window_s, double min_chord_m,
                        std::vector<std::array<double, 3>>* poses) {
  std::vector<std::array<double, 3>>& p = *poses;
  const size_t n = p.size();
  if (n < 2 || utime.size() != n) return;
  const int64_t half_us = static_cast<int64_t>(std::llround(half_window_s * 1e6));
  size_t lo = 0, hi = 0;
  double previous_rad = p[0][2];
  for (size_t k = 0; k < n; ++k) {
    while (utime[lo] < utime[k] - half_us) ++lo;
    while (hi + 1 < n && utime[hi + 1] <= utime[k] + half_us) ++hi;
    const double dx_m = p[hi][0] - p[lo][0];
    const double dy_m = p[hi][1] - p[lo][1];
    if (std::hypot(dx_m, dy_m) >= min_chord_m) {
      const double chord_rad = std::atan2(dy_m, dx_m);
      previous_rad += std::remainder(chord_rad - previous_rad, 2.0 * M_PI);
    }
    p[k][2] = previous_rad;
  }
}

bool multilaterate(const std::vector<std::array<double, 2>>& positions_m,
                   const std::vector<double>& ranges_m, std::array<double, 2>* beacon_m) {
  const Eigen::Index n = static_cast<Eigen::Index>(positions_m.size());
  if (n < 3 || ranges_m.size() != positions_m.size()) return false;
  // Centre the positions so the constant column is well conditioned against the others.
  Eigen::Vector2d centre_m = Eigen::Vector2d::Zero();
  for (const auto& p : positions_m) centre_m += Eigen::Vector2d(p[0], p[1]);
  centre_m /= static_cast<double>(n);
  Eigen::MatrixXd a(n, 3);
  Eigen::VectorXd b(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector2d p_m = Eigen::Vector2d(positions_m[i][0], positions_m[i][1]) - centre_m;
    a.row(i) << -2.0 * p_m.x(), -2.0 * p_m.y(), 1.0;
    b(i) = ranges_m[i] * ranges_m[i] - p_m.squaredNorm();
  }
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a);
  qr.setThreshold(1e-9);
  if (qr.rank() < 3) return false;
  const Eigen::Vector3d u = qr.solve(b);
  (*beacon_m)[0] = u.x() + centre_m.x();
  (*beacon_m)[1] = u.y() + centre_m.y();
  return std::isfinite((*beacon_m)[0]) && std::isfinite((*beacon_m)[1]);
}

}  // namespace batch
}  // namespace roam
