// Fixed-interval smoother of the solved positions with the calibrated odometry (model:
// odometry_smoother.hpp).
#include "odometry_smoother.hpp"
#include "roam/estimation/range_model.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Dense>

#include "roam/estimation/motion_model.hpp"

namespace roam::spectral {
namespace {
// Prior on each heading correction: only keeps the system definite where nothing else holds it.
constexpr double kHeadingPriorSigma_rad = 1.0;
constexpr double kHeldHeadingWeight = 1e12;  // interior: the correction held at 0
// Gauss-Newton passes with ranges: the solved path starts within decimetres of the truth, ranges
// are metres long, so the linearisation error after the first pass is millimetres.
constexpr int kRangeIterations = 3;
}  // namespace

double spectralPositionSigma(double median_range_residual_m, double ranges_per_pose) {
  if (!(median_range_residual_m > 0.0) || !(ranges_per_pose > 0.0))
    throw std::invalid_argument("spectralPositionSigma: residual and ranges per pose must be > 0");
  return 1.4826 * median_range_residual_m * std::sqrt(2.0 / ranges_per_pose);
}

void smoothWithOdometry(const OdometryPath& path, const std::vector<double>& heading_rad,
                        const std::vector<int>& solved_poses, double distance_scale,
                        double position_sigma_m, const SmootherNoise& noise, Path* trajectory,
                        const std::vector<SmootherRange>* ranges, double range_sigma_m) {
  const int T = path.size();
  if (static_cast<int>(trajectory->size()) != T || static_cast<int>(heading_rad.size()) != T)
    throw std::invalid_argument("smoothWithOdometry: one trajectory pose per path pose");
  if (solved_poses.size() < 2 || !(position_sigma_m > 0.0)) return;
  using Mat2 = Eigen::Matrix2d;
  using Vec2 = Eigen::Vector2d;
  using Mat3 = Eigen::Matrix3d;
  using Vec3 = Eigen::Vector3d;
  const Path& in = *trajectory;
  const double w_p = 1.0 / (position_sigma_m * position_sigma_m);
  // State per pose: (x, y, delta), delta the correction to the heading that turns odometry k
  // (held at zero without noise.correct_headings). Normal equations: diagonal blocks D, the
  // coupling of k and k+1 in U[k], right-hand side r.
  const int S = noise.correct_headings ? 3 : 2;
  const bool with_ranges = ranges != nullptr && !ranges->empty() && range_sigma_m > 0.0;
  std::vector<Vec2> p(T);  // the linearisation point, then the solution
  for (int k = 0; k < T; ++k) p[k] = Vec2(in[k].x_m, in[k].y_m);
  for (int pass = 0; pass < (with_ranges ? kRangeIterations : 1); ++pass) {
    std::vector<Mat3> D(T, Mat3::Zero()), U(T > 0 ? T - 1 : 0, Mat3::Zero());
    std::vector<Vec3> r(T, Vec3::Zero());
    if (S == 2)
      for (Mat3& block : D) block(2, 2) = 1.0;  // delta fixed at 0
    else
      for (int k = 0; k < T; ++k) {
        const bool end = path.utime[k] - path.utime.front() < noise.free_heading_end_us ||
                         path.utime.back() - path.utime[k] < noise.free_heading_end_us;
        D[k](2, 2) = end ? 1.0 / (kHeadingPriorSigma_rad * kHeadingPriorSigma_rad) : kHeldHeadingWeight;
      }
    if (!with_ranges)
      for (int j : solved_poses) {
        D[j].topLeftCorner<2, 2>() += w_p * Mat2::Identity();
        r[j].head<2>() += w_p * Vec2(in[j].x_m, in[j].y_m);
      }
    else
      for (const SmootherRange& range : *ranges) {
        // u . ((1 - f) p_k + f p_k+1) = r + u . m at the linearisation point, u the unit direction
        // from the beacon; weight Tukey(e / sigma_r) / sigma_r^2.
        const int k = std::clamp(range.pose, 0, T - 1), k1 = std::min(k + 1, T - 1);
        const double f = k1 == k ? 0.0 : range.fraction;
        const Vec2 m(range.beacon_x_m, range.beacon_y_m);
        const Vec2 from_beacon = (1.0 - f) * p[k] + f * p[k1] - m;
        const double distance_m = from_beacon.norm();
        if (!(distance_m > 1e-6)) continue;
        const double t = (range.range_m - distance_m) / (estimation::kTukey95 * range_sigma_m);
        if (!(std::abs(t) < 1.0)) continue;
        const double w = (1.0 - t * t) * (1.0 - t * t) / (range_sigma_m * range_sigma_m);
        const Vec2 u = from_beacon / distance_m;
        const double target = range.range_m + u.dot(m);
        const Vec2 ja = (1.0 - f) * u, jb = f * u;
        D[k].topLeftCorner<2, 2>() += w * ja * ja.transpose();
        r[k].head<2>() += w * target * ja;
        if (k1 != k) {
          D[k1].topLeftCorner<2, 2>() += w * jb * jb.transpose();
          r[k1].head<2>() += w * target * jb;
          U[k].topLeftCorner<2, 2>() += w * ja * jb.transpose();
        }
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
      const Mat2 W = Mat2::Identity() / (sigma_d * sigma_d + l * l * var_theta);
      // Step residual p_{k+1} - p_k - d - delta_k J d (J d: d turned by 90 degrees, the first-order
      // change of d with its heading): Jacobians A (pose k) and B (pose k+1).
      Eigen::Matrix<double, 2, 3> A = Eigen::Matrix<double, 2, 3>::Zero(), B = A;
      A.leftCols<2>() = -Mat2::Identity();
      if (S == 3) A.col(2) = -Vec2(-d(1), d(0));
      B.leftCols<2>() = Mat2::Identity();
      D[k] += A.transpose() * W * A;
      D[k + 1] += B.transpose() * W * B;
      U[k] += A.transpose() * W * B;
      r[k] += A.transpose() * W * d;
      r[k + 1] += B.transpose() * W * d;
      if (S == 3) {
        // The correction random-walks with the odometry's own heading noise per step.
        const double w_turn = 1.0 / var_theta;
        D[k](2, 2) += w_turn;
        D[k + 1](2, 2) += w_turn;
        U[k](2, 2) -= w_turn;
      }
    }
    // Block Thomas on the symmetric block-tridiagonal system.
    std::vector<Mat3> Dinv(T);
    for (int k = 0; k < T; ++k) {
      if (k > 0) {
        const Mat3 m = U[k - 1].transpose() * Dinv[k - 1];
        D[k] -= m * U[k - 1];
        r[k] -= m * r[k - 1];
      }
      Dinv[k] = D[k].inverse();
    }
    std::vector<Vec3> x(T);
    x[T - 1] = Dinv[T - 1] * r[T - 1];
    for (int k = T - 2; k >= 0; --k) x[k] = Dinv[k] * (r[k] - U[k] * x[k + 1]);
    for (int k = 0; k < T; ++k) p[k] = x[k].head<2>();
  }
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
