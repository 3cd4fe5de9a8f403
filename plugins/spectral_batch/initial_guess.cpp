#include "initial_guess.hpp"

#include <Eigen/Dense>
#include <cmath>

namespace roam {
namespace spectral_batch {

std::array<double, 3> propagate(const std::array<double, 3>& pose, const Odometry& odometry, double dt_s,
                                const estimation::OdometryCalibration& calibration) {
  const Eigen::Vector3d next = estimation::step(Eigen::Vector3d(pose[0], pose[1], pose[2]),
                                                estimation::calibratedIncrement(odometry, dt_s, calibration));
  return {next[0], next[1], next[2]};
}

std::vector<std::array<double, 3>> deadReckon(const std::array<double, 3>& start_pose,
                                              const std::vector<Odometry>& odometry,
                                              const std::vector<double>& dt_s,
                                              const estimation::OdometryCalibration& calibration) {
  std::vector<std::array<double, 3>> poses;
  poses.reserve(odometry.size() + 1);
  poses.push_back(start_pose);
  for (size_t k = 0; k < odometry.size(); ++k)
    poses.push_back(propagate(poses.back(), odometry[k], k < dt_s.size() ? dt_s[k] : 0.0, calibration));
  return poses;
}

void headingsFromOdometryAlignment(const std::vector<Odometry>& odometry, double half_window_m,
                                   std::vector<std::array<double, 3>>* poses) {
  std::vector<std::array<double, 3>>& p = *poses;
  const size_t n = p.size();
  if (n < 2 || odometry.size() + 1 != n) return;
  const std::vector<std::array<double, 3>> dr = deadReckon({0.0, 0.0, 0.0}, odometry);
  // Prefix sums (about the means, for conditioning) of a = dead-reckoned, b = seed positions.
  Eigen::Vector2d mean_a = Eigen::Vector2d::Zero(), mean_b = Eigen::Vector2d::Zero();
  for (size_t k = 0; k < n; ++k) {
    mean_a += Eigen::Vector2d(dr[k][0], dr[k][1]);
    mean_b += Eigen::Vector2d(p[k][0], p[k][1]);
  }
  mean_a /= static_cast<double>(n);
  mean_b /= static_cast<double>(n);
  // Columns: ax, ay, bx, by, ax bx + ay by (dot), ax by - ay bx (cross), ax^2 + ay^2.
  std::vector<std::array<double, 7>> sum(n + 1, std::array<double, 7>{});
  std::vector<double> travelled(n, 0.0);
  for (size_t k = 0; k < n; ++k) {
    const double ax = dr[k][0] - mean_a.x(), ay = dr[k][1] - mean_a.y();
    const double bx = p[k][0] - mean_b.x(), by = p[k][1] - mean_b.y();
    const std::array<double, 7> term{ax, ay, bx, by, ax * bx + ay * by, ax * by - ay * bx, ax * ax + ay * ay};
    for (int c = 0; c < 7; ++c) sum[k + 1][c] = sum[k][c] + term[c];
    if (k > 0) travelled[k] = travelled[k - 1] + std::hypot(odometry[k - 1].forward_m, odometry[k - 1].lateral_m);
  }
  size_t lo = 0, hi = 0;
  double previous_rad = 0.0;
  bool have_previous = false;
  for (size_t k = 0; k < n; ++k) {
    while (travelled[lo] < travelled[k] - half_window_m) ++lo;
    while (hi + 1 < n && travelled[hi + 1] <= travelled[k] + half_window_m) ++hi;
    const double m = static_cast<double>(hi - lo + 1);
    std::array<double, 7> s{};
    for (int c = 0; c < 7; ++c) s[c] = sum[hi + 1][c] - sum[lo][c];
    // Centred sums: sum (a - a_bar) . (b - b_bar) = sum a.b - sum a . sum b / m, likewise cross.
    const double dot = s[4] - (s[0] * s[2] + s[1] * s[3]) / m;
    const double cross = s[5] - (s[0] * s[3] - s[1] * s[2]) / m;
    const double spread_m2 = s[6] - (s[0] * s[0] + s[1] * s[1]) / m;
    // No motion in the window (spread below a centimetre): the rotation is undetermined.
    double heading_rad = p[k][2];
    if (spread_m2 > 1e-4 * m && std::hypot(dot, cross) > 0.0) heading_rad = dr[k][2] + std::atan2(cross, dot);
    if (have_previous) heading_rad = previous_rad + std::remainder(heading_rad - previous_rad, 2.0 * M_PI);
    p[k][2] = previous_rad = heading_rad;
    have_previous = true;
  }
}

}  // namespace spectral_batch
}  // namespace roam
