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
    poses.push_back({last[0] + step.forward_m * std::cos(last[2]),
                     last[1] + step.forward_m * std::sin(last[2]),
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
    if (k > 0) travelled[k] = travelled[k - 1] + std::abs(odometry[k - 1].forward_m);
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
