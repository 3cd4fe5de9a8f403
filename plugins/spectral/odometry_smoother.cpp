// Fixed-interval smoother of the solved positions with the calibrated odometry (model:
// odometry_smoother.hpp).
#include "odometry_smoother.hpp"

#include <cmath>
#include <stdexcept>

#include <Eigen/Dense>

#include "roam/estimation/motion_model.hpp"

namespace roam::spectral {

double spectralPositionSigma(double median_range_residual_m, double ranges_per_pose) {
  if (!(median_range_residual_m > 0.0) || !(ranges_per_pose > 0.0))
    throw std::invalid_argument("spectralPositionSigma: residual and ranges per pose must be > 0");
  return 1.4826 * median_range_residual_m * std::sqrt(2.0 / ranges_per_pose);
}

void smoothWithOdometry(const OdometryPath& path, const std::vector<double>& heading_rad,
                        const std::vector<int>& solved_poses, double distance_scale,
                        double position_sigma_m, const SmootherNoise& noise, Path* trajectory) {
  const int T = path.size();
  if (static_cast<int>(trajectory->size()) != T || static_cast<int>(heading_rad.size()) != T)
    throw std::invalid_argument("smoothWithOdometry: one trajectory pose per path pose");
  if (solved_poses.size() < 2 || !(position_sigma_m > 0.0)) return;
  using Mat2 = Eigen::Matrix2d;
  using Vec2 = Eigen::Vector2d;
  const Path& in = *trajectory;
  const double w_p = 1.0 / (position_sigma_m * position_sigma_m);
  std::vector<Mat2> D(T, Mat2::Zero()), W(T > 0 ? T - 1 : 0);  // diagonal blocks; step weights
  std::vector<Vec2> r(T, Vec2::Zero());
  for (int j : solved_poses) {
    D[j] += w_p * Mat2::Identity();
    r[j] += w_p * Vec2(in[j].x_m, in[j].y_m);
  }
  const estimation::OdometryCalibration scale_only{distance_scale, 0.0};
  for (int k = 0; k + 1 < T; ++k) {
    const double dt_s = 1e-6 * static_cast<double>(path.utime[k + 1] - path.utime[k]);
    const Eigen::Vector3d inc = estimation::calibratedIncrement(path.odometry[k], dt_s, scale_only);
    const double l = std::hypot(inc(0), inc(1));
    const double c = std::cos(heading_rad[k]), s = std::sin(heading_rad[k]);
    const Vec2 d(c * inc(0) - s * inc(1), s * inc(0) + c * inc(1));
    const double sigma_d = noise.distance_sigma_rel * l + noise.distance_sigma_m;
    const double var_theta = estimation::wheelHeadingVariance_rad2(l, inc(2), noise.heading);
    W[k] = Mat2::Identity() / (sigma_d * sigma_d + l * l * var_theta);
    D[k] += W[k];
    D[k + 1] += W[k];
    r[k] -= W[k] * d;
    r[k + 1] += W[k] * d;
  }
  // Block Thomas: off-diagonal blocks are -W[k].
  std::vector<Mat2> Dinv(T);
  for (int k = 0; k < T; ++k) {
    if (k > 0) {
      const Mat2 m = W[k - 1] * Dinv[k - 1];
      D[k] -= m * W[k - 1];
      r[k] += m * r[k - 1];
    }
    Dinv[k] = D[k].inverse();
  }
  std::vector<Vec2> p(T);
  p[T - 1] = Dinv[T - 1] * r[T - 1];
  for (int k = T - 2; k >= 0; --k) p[k] = Dinv[k] * (r[k] + W[k] * p[k + 1]);
  // Keep the frame: the rigid motion that best fits the smoothed solved poses onto the solve's.
  Vec2 mean_in = Vec2::Zero(), mean_out = Vec2::Zero();
  for (int j : solved_poses) {
    mean_in += Vec2(in[j].x_m, in[j].y_m);
    mean_out += p[j];
  }
  mean_in /= static_cast<double>(solved_poses.size());
  mean_out /= static_cast<double>(solved_poses.size());
  double dot = 0.0, cross = 0.0;
  for (int j : solved_poses) {
    const Vec2 a = p[j] - mean_out, b = Vec2(in[j].x_m, in[j].y_m) - mean_in;
    dot += a.dot(b);
    cross += a(0) * b(1) - a(1) * b(0);
  }
  const double turn = (dot == 0.0 && cross == 0.0) ? 0.0 : std::atan2(cross, dot);
  Mat2 R;
  R << std::cos(turn), -std::sin(turn), std::sin(turn), std::cos(turn);
  for (int k = 0; k < T; ++k) {
    const Vec2 q = R * (p[k] - mean_out) + mean_in;
    (*trajectory)[k].x_m = q(0);
    (*trajectory)[k].y_m = q(1);
  }
}

}  // namespace roam::spectral
