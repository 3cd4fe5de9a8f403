#include "range_interpolation.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

namespace roam {
namespace {

// Least squares with a relative singular-value cut-off, through the 4 x 4 normal matrix: its
// eigenvalues are the squared singular values of the design, so the cut-off rcond on singular
// values is rcond^2 on eigenvalues. The features are centred and scaled to unit RMS radius, so
// squaring the condition number costs nothing that matters, and each (re)weighted solve is O(n)
// instead of an n x 4 SVD.
Eigen::Vector4d solveLeastSquares(const Eigen::MatrixX4d& design, const Eigen::VectorXd& target, double rcond) {
  const Eigen::Matrix4d normal = design.transpose() * design;
  const Eigen::Vector4d projected = design.transpose() * target;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eigen(normal);
  const Eigen::Vector4d& lambda = eigen.eigenvalues();  // ascending
  const double cut = rcond * rcond * lambda(3);
  Eigen::Vector4d theta = Eigen::Vector4d::Zero();
  for (int i = 0; i < 4; ++i) {
    if (!(lambda(i) > cut)) continue;
    const Eigen::Vector4d v = eigen.eigenvectors().col(i);
    theta += v * (v.dot(projected) / lambda(i));
  }
  return theta;
}

// One beacon's model theta . phi(p) of the half squared range over a window. Plain least squares
// (the paper); then, if config.robust, an M-estimate on the residual in range units,
// e = r - sqrt(2 theta . phi), by iteratively reweighted least squares in two stages:
//   1. Huber, scale config.range_sigma_m (the sensor's stated noise), k = 1.345 sigma: convex, so
//      IRLS reaches its unique minimum from the least-squares start however far outliers dragged
//      that; each outlier's pull is bounded.
//   2. Tukey's biweight from there, c = 4.685 s (95 % efficiency on Gaussian noise), with the scale
//      s = 1.4826 median|e| of the Huber fit, at most config.range_sigma_m (a window whose Huber
//      fit is still bent by outliers has an inflated median residual; the sensor's stated noise
//      bounds it) and at least kMinScale_m (noise-free data keep every weight at one): ranges
//      more than c off the model get weight zero.
// A stage stops once its weights settle; a reweighting that would leave fewer than
// config.min_ranges_per_window ranges with weight is not applied.
Eigen::Vector4d fitWindowModel(const Eigen::MatrixX4d& design, const Eigen::VectorXd& target,
                               const InterpolationConfig& config) {
  constexpr int kIterations = 10;
  constexpr double kSettled = 1e-3;  // largest weight change that counts as converged
  constexpr double kHuberK = 1.345;
  constexpr double kTukeyC = 4.685;
  constexpr double kMinScale_m = 0.01;
  Eigen::Vector4d theta = solveLeastSquares(design, target, config.rcond);
  if (!config.robust) return theta;
  const Eigen::Index n = design.rows();
  const Eigen::ArrayXd range_m = (2.0 * target.array()).sqrt();
  auto residuals_m = [&](const Eigen::Vector4d& model) {
    return Eigen::ArrayXd(range_m - (2.0 * (design * model).array()).max(0.0).sqrt());
  };
  auto reweighted = [&](const Eigen::ArrayXd& w) {
    const Eigen::ArrayXd root_w = w.sqrt();
    return solveLeastSquares(root_w.matrix().asDiagonal() * design, (root_w * target.array()).matrix(),
                             config.rcond);
  };
  for (int stage = 0; stage < 2; ++stage) {
    double scale_m = config.range_sigma_m;
    if (stage == 1) {
      const Eigen::ArrayXd abs_e_m = residuals_m(theta).abs();
      std::vector<double> abs_e(abs_e_m.data(), abs_e_m.data() + n);
      std::nth_element(abs_e.begin(), abs_e.begin() + n / 2, abs_e.end());
      scale_m = std::clamp(1.4826 * abs_e[n / 2], kMinScale_m, config.range_sigma_m);
    }
    Eigen::ArrayXd previous_w = Eigen::ArrayXd::Ones(n);
    for (int iteration = 0; iteration < kIterations; ++iteration) {
      const Eigen::ArrayXd abs_e_m = residuals_m(theta).abs();
      Eigen::ArrayXd w;
      if (stage == 0) {
        w = (kHuberK * scale_m / abs_e_m.max(1e-300)).min(1.0);
      } else {
        const Eigen::ArrayXd u = abs_e_m / (kTukeyC * scale_m);
        w = (u < 1.0).select((1.0 - u.square()).square(), 0.0);
      }
      if ((w > 0.0).count() < config.min_ranges_per_window) break;
      theta = reweighted(w);
      if ((w - previous_w).abs().maxCoeff() < kSettled) break;
      previous_w = w;
    }
  }
  return theta;
}

}  // namespace

RangeInterpolator::RangeInterpolator(int num_beacons, const InterpolationConfig& config,
                                     int64_t origin_utime)
    : num_beacons_(num_beacons),
      config_(config),
      origin_utime_(origin_utime),
      window_us_(static_cast<int64_t>(std::llround(config.window_s * 1e6))),
      stride_us_(std::max<int64_t>(
          1, static_cast<int64_t>(std::llround(config.window_s * (1.0 - config.window_overlap) * 1e6)))),
      sum_half_sq_(num_beacons),
      sum_rate_(num_beacons),
      count_(num_beacons) {}

int64_t RangeInterpolator::windowBegin(int window) const {
  return origin_utime_ + static_cast<int64_t>(window) * stride_us_;
}

int64_t RangeInterpolator::windowEnd(int window) const { return windowBegin(window) + window_us_; }

int RangeInterpolator::windowsToCover(int64_t last_utime) const {
  if (last_utime <= origin_utime_) return 1;
  // The last window needed is the first whose end reaches last_utime.
  const int64_t beyond = last_utime - origin_utime_ - window_us_;
  if (beyond <= 0) return 1;
  return static_cast<int>((beyond + stride_us_ - 1) / stride_us_) + 1;
}

void RangeInterpolator::grow(int poses) {
  for (int n = 0; n < num_beacons_; ++n) {
    if (static_cast<int>(count_[n].size()) >= poses) continue;
    sum_half_sq_[n].resize(poses, 0.0);
    sum_rate_[n].resize(poses, 0.0);
    count_[n].resize(poses, 0);
  }
}

void RangeInterpolator::addWindow(int window, const OdometryPath& path,
                                  const std::vector<RangeSample>& ranges) {
  const int64_t begin_us = windowBegin(window), end_us = windowEnd(window);
  const int first_pose = path.lowerBound(begin_us);
  int end_pose = path.lowerBound(end_us);
  if (end_pose < path.size() && path.utime[end_pose] == end_us) ++end_pose;
  if (end_pose - first_pose < 2) return;
  grow(path.size());

  // Centre and scale of the window's dead-reckoned poses: features of order one.
  double cx_m = 0.0, cy_m = 0.0;
  for (int k = first_pose; k < end_pose; ++k) {
    cx_m += path.x_m[k];
    cy_m += path.y_m[k];
  }
  const double poses = end_pose - first_pose;
  cx_m /= poses;
  cy_m /= poses;
  double radius_sq = 0.0;
  for (int k = first_pose; k < end_pose; ++k)
    radius_sq += std::pow(path.x_m[k] - cx_m, 2) + std::pow(path.y_m[k] - cy_m, 2);
  const double scale_m = std::max(std::sqrt(radius_sq / poses), 1e-3);
  auto features = [&](double x_m, double y_m) {
    const double u = (x_m - cx_m) / scale_m, v = (y_m - cy_m) / scale_m;
    return Eigen::Vector4d(1.0, -u, -v, 0.5 * (u * u + v * v));
  };

  const auto by_time = [](const RangeSample& r, int64_t t) { return r.utime < t; };
  const auto lo = std::lower_bound(ranges.begin(), ranges.end(), begin_us, by_time);
  const auto hi = std::lower_bound(ranges.begin(), ranges.end(), end_us + 1, by_time);

  for (int n = 0; n < num_beacons_; ++n) {
    std::vector<Eigen::Vector4d> rows;
    std::vector<double> targets;
    int64_t first_us = 0, last_us = 0;
    for (auto it = lo; it != hi; ++it) {
      if (it->beacon != n) continue;
      double x_m, y_m;
      if (!path.positionAt(it->utime, &x_m, &y_m)) continue;
      if (rows.empty()) first_us = it->utime;
      last_us = it->utime;
      rows.push_back(features(x_m, y_m));
      targets.push_back(0.5 * it->range_m * it->range_m);
    }
    if (static_cast<int>(rows.size()) < config_.min_ranges_per_window) continue;
    Eigen::MatrixX4d design(rows.size(), 4);
    Eigen::VectorXd target(rows.size());
    for (size_t i = 0; i < rows.size(); ++i) {
      design.row(i) = rows[i].transpose();
      target(i) = targets[i];
    }
    const Eigen::Vector4d theta = fitWindowModel(design, target, config_);

    for (int k = path.lowerBound(first_us); k < end_pose && path.utime[k] <= last_us; ++k) {
      const double u = (path.x_m[k] - cx_m) / scale_m, v = (path.y_m[k] - cy_m) / scale_m;
      const double half_sq = theta.dot(features(path.x_m[k], path.y_m[k]));
      // d/dp of theta . phi(p): (1/scale) * (-theta1 + theta3 u, -theta2 + theta3 v).
      const double gx = (-theta(1) + theta(3) * u) / scale_m;
      const double gy = (-theta(2) + theta(3) * v) / scale_m;
      const double rate = gx * std::cos(path.heading_rad[k]) + gy * std::sin(path.heading_rad[k]);
      sum_half_sq_[n][k] += half_sq;
      sum_rate_[n][k] += rate;
      ++count_[n][k];
    }
  }
}

bool RangeInterpolator::halfSquaredRange(int beacon, int pose, double* value) const {
  if (pose >= static_cast<int>(count_[beacon].size()) || count_[beacon][pose] == 0) return false;
  *value = sum_half_sq_[beacon][pose] / count_[beacon][pose];
  return true;
}

bool RangeInterpolator::rangeRate(int beacon, int pose, double* value) const {
  if (pose >= static_cast<int>(count_[beacon].size()) || count_[beacon][pose] == 0) return false;
  *value = sum_rate_[beacon][pose] / count_[beacon][pose];
  return true;
}

}  // namespace roam
