#include "range_interpolation.hpp"
#include "roam/estimation/range_model.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>

#include <Eigen/Dense>

namespace roam::spectral {
namespace {

// One window's ranges to one beacon: features phi(p) of the dead-reckoned positions in the
// columns, targets d^2/2.
using Features = Eigen::Matrix<double, 4, Eigen::Dynamic>;

// The directions of theta the window's geometry determines: least squares with a relative
// singular-value cut-off rcond on the design keeps the eigenvectors of the 4 x 4 normal matrix
// (eigenvalues = squared singular values of the design) with eigenvalue > rcond^2 lambda_max.
// The features are centred and scaled to unit RMS radius, so squaring the condition number costs
// nothing that matters. Fast path, exact: lambda_max <= trace(N) and lambda_min >= 1/trace(N^-1),
// so when 1/trace(N^-1) > rcond^2 trace(N) nothing is cut and the basis is the identity; only a
// near-straight window pays for the eigen-decomposition.
using Basis = Eigen::Matrix<double, 4, Eigen::Dynamic, 0, 4, 4>;
Basis retainedBasis(const Eigen::Matrix4d& normal, double rcond) {
  const double cut_ratio = rcond * rcond;
  const Eigen::LLT<Eigen::Matrix4d> cholesky(normal);
  if (cholesky.info() == Eigen::Success) {
    const double trace_inverse = cholesky.solve(Eigen::Matrix4d::Identity()).trace();
    if (std::isfinite(trace_inverse) && trace_inverse > 0.0 &&
        1.0 > cut_ratio * normal.trace() * trace_inverse)
      return Eigen::Matrix4d::Identity();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eigen(normal);
  const Eigen::Vector4d& lambda = eigen.eigenvalues();  // ascending
  const double cut = cut_ratio * lambda(3);
  Basis basis(4, 0);
  for (int i = 3; i >= 0; --i) {
    if (!(lambda(i) > cut)) break;
    basis.conservativeResize(Eigen::NoChange, basis.cols() + 1);
    basis.col(basis.cols() - 1) = eigen.eigenvectors().col(i);
  }
  return basis;
}

// Least squares restricted to span(basis): theta = B (B^T N B)^-1 B^T b. False if the weighted
// normal matrix is singular on that span.
bool solveInBasis(const Eigen::Matrix4d& normal, const Eigen::Vector4d& projected, const Basis& basis,
                  Eigen::Vector4d* theta) {
  using Reduced = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 4, 4>;
  if (basis.cols() == 0) {
    theta->setZero();
    return true;
  }
  const Reduced reduced = basis.transpose() * normal * basis;
  const Eigen::LLT<Reduced> cholesky(reduced);
  if (cholesky.info() != Eigen::Success) return false;
  const Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 4, 1> coefficients =
      cholesky.solve(basis.transpose() * projected);
  *theta = basis * coefficients;
  return theta->allFinite();
}

// Normal equations of a weighted fit, accumulated one range at a time.
struct NormalEquations {
  Eigen::Matrix4d normal = Eigen::Matrix4d::Zero();
  Eigen::Vector4d projected = Eigen::Vector4d::Zero();
  int weighted = 0;  // ranges with weight > 0
  void add(const Eigen::Vector4d& phi, double target, double weight) {
    if (weight == 0.0) return;
    const Eigen::Vector4d weighted_phi = weight * phi;
    normal.noalias() += weighted_phi * phi.transpose();
    projected += weighted_phi * target;
    ++weighted;
  }
};

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
// False if the plain fit has no solution (the window is left out). A stage stops once its weights settle (weights identical to those the model was solved with
// are not solved again: that would return the same model); a reweighting that would leave
// fewer than config.min_ranges_per_window ranges with weight is not applied. The reweighted fits
// stay in the directions the window's geometry determines (retainedBasis of the unweighted fit).
// Each iteration is one pass over the ranges (residual, weight and normal equations together)
// and a Cholesky solve of at most 4 x 4.
bool fitWindowModel(const Features& phi, const Eigen::VectorXd& target, const InterpolationConfig& config,
                    Eigen::Vector4d* model) {
  constexpr int kIterations = 10;
  constexpr double kSettled = 1e-3;  // largest weight change that counts as converged
  constexpr double kHuberK = estimation::kHuber95;
  constexpr int kSubsetTrials = 50;
  constexpr uint32_t kSubsetSeed = 20130621u;
  constexpr double kMinScale_m = 0.01;
  const int n = static_cast<int>(phi.cols());
  NormalEquations plain;
  for (int i = 0; i < n; ++i) plain.add(phi.col(i), target(i), 1.0);
  const Basis basis = retainedBasis(plain.normal, config.rcond);
  Eigen::Vector4d& theta = *model;
  if (!solveInBasis(plain.normal, plain.projected, basis, &theta)) return false;
  if (!config.robust) return true;

  std::vector<double> range_m(n), model_w(n, 0.0), previous_w(n), w(n), abs_e(n);
  for (int i = 0; i < n; ++i) range_m[i] = std::sqrt(2.0 * target(i));
  auto abs_residual_m = [&](const Eigen::Vector4d& model, int i) {
    return std::abs(range_m[i] - std::sqrt(std::max(0.0, 2.0 * model.dot(phi.col(i)))));
  };
  // h-th smallest |e| (least quantile of squares, h = (n + p + 1) / 2: 50 % breakdown for any n).
  const int p = static_cast<int>(basis.cols());
  const int h = std::min(n - 1, (n + p + 1) / 2);
  auto quantile_abs_residual_m = [&](const Eigen::Vector4d& model) {
    for (int i = 0; i < n; ++i) abs_e[i] = abs_residual_m(model, i);
    std::nth_element(abs_e.begin(), abs_e.begin() + h, abs_e.end());
    return abs_e[h];
  };
  // Iteratively reweighted least squares from theta with w_i = weight(|e_i|), until the weights
  // settle (largest change < kSettled) or repeat those theta was solved with (model_w); stops
  // without applying a reweighting that leaves fewer than min_weighted ranges with weight or
  // that cannot be solved. adaptive_basis: each solve in the directions the weighted ranges
  // determine (ranges that fixed a weak direction may be the ones dropped); otherwise in `basis`.
  auto reweight = [&](auto weight, int min_weighted, bool adaptive_basis) {
    std::fill(previous_w.begin(), previous_w.end(), 1.0);
    for (int iteration = 0; iteration < kIterations; ++iteration) {
      NormalEquations reweighted;
      bool same_as_model = true;
      double change = 0.0;
      for (int i = 0; i < n; ++i) {
        w[i] = weight(abs_residual_m(theta, i));
        same_as_model = same_as_model && w[i] == model_w[i];
        change = std::max(change, std::abs(w[i] - previous_w[i]));
        reweighted.add(phi.col(i), target(i), w[i]);
      }
      if (reweighted.weighted < min_weighted) break;
      if (same_as_model) break;  // theta is already the solution with these weights
      Eigen::Vector4d solved;
      const Basis directions = adaptive_basis ? retainedBasis(reweighted.normal, config.rcond) : basis;
      if (!solveInBasis(reweighted.normal, reweighted.projected, directions, &solved)) break;
      theta = solved;
      model_w = w;
      if (change < kSettled) break;
      previous_w = w;
    }
  };
  auto tukey = [](double scale_m) {
    return [scale_m](double e_m) {
      const double u = e_m / (estimation::kTukey95 * scale_m);
      return u < 1.0 ? (1.0 - u * u) * (1.0 - u * u) : 0.0;
    };
  };
  // Start: least quantile of squares over minimal subsets (as many ranges as the retained basis has
  // directions), drawn by a fixed-seed generator so runs repeat. With a fraction eps of outliers
  // a subset is clean with probability (1 - eps)^p: 50 draws find one with > 99 % probability up
  // to eps = 50 % (p = 4). The least-squares fit is a candidate too (noise-free data: exact).
  const Eigen::Vector4d least_squares = theta;
  double best_median_m = quantile_abs_residual_m(theta);
  // The subsets are needed only when the least-squares residuals show outliers: if every |e| lies
  // within the biweight's cut-off c s (s the small-sample scale of those residuals, at most
  // range_sigma_m), the LS fit
  // already is a start the biweight keeps every range of, and no subset is drawn.
  bool clean = true;
  {
    const double scale_ls_m = std::max(kMinScale_m, 1.4826 * (1.0 + 5.0 / std::max(1, n - p)) * best_median_m);
    // At most the configured range sigma: outliers inflate the LS residuals' own scale (masking).
    const double cut_m = estimation::kTukey95 * std::min(scale_ls_m, config.range_sigma_m);
    for (int i = 0; i < n && clean; ++i) clean = abs_residual_m(least_squares, i) < cut_m;
  }
  if (!clean && p > 0 && n > p) {
    std::mt19937 generator(kSubsetSeed);
    std::vector<int> subset(p);
    for (int trial = 0; trial < kSubsetTrials; ++trial) {
      NormalEquations minimal;
      for (int k = 0; k < p; ++k) {
        int index;
        do {
          index = static_cast<int>(generator() % static_cast<uint32_t>(n));
        } while (std::find(subset.begin(), subset.begin() + k, index) != subset.begin() + k);
        subset[k] = index;
        minimal.add(phi.col(index), target(index), 1.0);
      }
      // A subset that does not span the window's directions (ranges close together) would
      // extrapolate wildly along the one it misses: skipped.
      if (retainedBasis(minimal.normal, config.rcond).cols() < p) continue;
      Eigen::Vector4d candidate;
      if (!solveInBasis(minimal.normal, minimal.projected, basis, &candidate)) continue;
      const double median_m = quantile_abs_residual_m(candidate);
      if (median_m < best_median_m) {
        best_median_m = median_m;
        theta = candidate;
      }
    }
  }
  // Tukey's biweight from there, c = 4.685 s, with the robust scale of the start's residuals,
  // s = 1.4826 (1 + 5 / (n - p)) |e|_(h) (Rousseeuw & Leroy's small-sample scale), at least
  // kMinScale_m: the data's own noise, not the configured sigma.
  const double scale_m = std::max(kMinScale_m, 1.4826 * (1.0 + 5.0 / std::max(1, n - p)) * best_median_m);
  // A fit kept by at least h ranges (a majority, the start's own breakdown point) is accepted
  // even below min_ranges_per_window: a short window (next to a ranging gap) with one outlier
  // among 8 ranges would otherwise fall back to the fit below, which starts from least squares
  // and which that outlier drags (synthetic loop, 2 % outliers, 30 s gaps: 1.4-1.6 m -> 0.3 m).
  reweight(tukey(scale_m), h, true);
  // Accepted if the biweight settled on a fit that keeps at least h ranges (a minimal subset's
  // exact fit that no refit confirmed is not); otherwise the Huber-then-biweight fit below.
  int kept = 0;
  for (int i = 0; i < n; ++i) kept += model_w[i] > 0.0 ? 1 : 0;
  if (kept >= h) return true;
  theta = least_squares;
  std::fill(model_w.begin(), model_w.end(), 1.0);
  for (int stage = 0; stage < 2; ++stage) {
    double scale_m = config.range_sigma_m;
    if (stage == 1) {
      for (int i = 0; i < n; ++i) abs_e[i] = abs_residual_m(theta, i);
      std::nth_element(abs_e.begin(), abs_e.begin() + n / 2, abs_e.end());
      scale_m = std::clamp(1.4826 * abs_e[n / 2], kMinScale_m, config.range_sigma_m);
    }
    if (stage == 0) {
      reweight([scale_m](double e_m) { return std::min(1.0, kHuberK * scale_m / std::max(e_m, 1e-300)); },
               config.min_ranges_per_window, false);
    } else {
      reweight(tukey(scale_m), config.min_ranges_per_window, false);
    }
  }
  return true;
}

// The longest stretch without a range of one beacon that the window's model is trusted to
// bridge: kMaxGapSpacings times the beacon's median spacing between ranges in the window, and at
// least half the window. A round-robin schedule with random dropouts leaves gaps of a few
// spacings (10 % dropout: 4 spacings with probability 1e-3), and real radios (Plaza 1) leave
// beacons unheard for stretches the window still surrounds; a radio silence over more than half
// the window is no longer interpolation but extrapolation along a path the window's ranges never
// saw, which the ranges on either side fix poorly (synthetic loop, 30 s silence in 53 s windows:
// metres off). Poses inside such a gap get no value: the solver bridges them by dead reckoning
// between solved poses, as it does for any unranged stretch.
int64_t maxBridgedGap_us(const std::vector<int64_t>& utime, int64_t window_us) {
  constexpr int64_t kMaxGapSpacings = 4;
  std::vector<int64_t> spacing;  // between distinct times (two ranges at one time are one place)
  for (size_t i = 1; i < utime.size(); ++i)
    if (utime[i] > utime[i - 1]) spacing.push_back(utime[i] - utime[i - 1]);
  if (spacing.empty()) return window_us / 2;
  std::nth_element(spacing.begin(), spacing.begin() + spacing.size() / 2, spacing.end());
  return std::max(kMaxGapSpacings * spacing[spacing.size() / 2], window_us / 2);
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
      sum_half_sq_{std::vector<std::vector<double>>(num_beacons), std::vector<std::vector<double>>(num_beacons)},
      sum_rate_{std::vector<std::vector<double>>(num_beacons), std::vector<std::vector<double>>(num_beacons)},
      count_{std::vector<std::vector<int>>(num_beacons), std::vector<std::vector<int>>(num_beacons)} {}

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
  for (int part = 0; part < 2; ++part) {
    for (int n = 0; n < num_beacons_; ++n) {
      if (static_cast<int>(count_[part][n].size()) >= poses) continue;
      sum_half_sq_[part][n].resize(poses, 0.0);
      sum_rate_[part][n].resize(poses, 0.0);
      count_[part][n].resize(poses, 0);
    }
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

  // One pass over the window's ranges, bucketed by beacon.
  struct Bucket {
    std::vector<Eigen::Vector4d> features;
    std::vector<double> half_sq;
    std::vector<int64_t> utime;
  };
  std::vector<Bucket> buckets(num_beacons_);
  for (auto it = lo; it != hi; ++it) {
    if (it->beacon < 0 || it->beacon >= num_beacons_) continue;
    double x_m, y_m;
    if (!path.positionAt(it->utime, &x_m, &y_m)) continue;
    Bucket& bucket = buckets[it->beacon];
    bucket.utime.push_back(it->utime);
    bucket.features.push_back(features(x_m, y_m));
    bucket.half_sq.push_back(0.5 * it->range_m * it->range_m);
  }

  for (int n = 0; n < num_beacons_; ++n) {
    const Bucket& bucket = buckets[n];
    const int count = static_cast<int>(bucket.features.size());
    if (count < config_.min_ranges_per_window) continue;
    Features phi(4, count);
    for (int i = 0; i < count; ++i) phi.col(i) = bucket.features[i];
    const Eigen::VectorXd target = Eigen::Map<const Eigen::VectorXd>(bucket.half_sq.data(), count);
    Eigen::Vector4d theta;
    if (!fitWindowModel(phi, target, config_, &theta)) continue;
    const int64_t first_us = bucket.utime.front(), last_us = bucket.utime.back();
    // A fit whose ranges span under half the window (the window reaches into a silence or past
    // the last range) is kept apart: used only where no fuller fit covers the pose.
    const int part = 2 * (last_us - first_us) >= window_us_ ? 0 : 1;
    const int64_t max_gap_us = maxBridgedGap_us(bucket.utime, window_us_);

    size_t next = 0;  // first range at or after pose k
    for (int k = path.lowerBound(first_us); k < end_pose && path.utime[k] <= last_us; ++k) {
      while (bucket.utime[next] < path.utime[k]) ++next;
      if (bucket.utime[next] != path.utime[k] && bucket.utime[next] - bucket.utime[next - 1] > max_gap_us)
        continue;  // inside a ranging gap: no range here to interpolate between
      const double u = (path.x_m[k] - cx_m) / scale_m, v = (path.y_m[k] - cy_m) / scale_m;
      const double half_sq = theta.dot(features(path.x_m[k], path.y_m[k]));
      // d/dp of theta . phi(p): (1/scale) * (-theta1 + theta3 u, -theta2 + theta3 v).
      const double gx = (-theta(1) + theta(3) * u) / scale_m;
      const double gy = (-theta(2) + theta(3) * v) / scale_m;
      const double rate = gx * path.cos_heading[k] + gy * path.sin_heading[k];
      sum_half_sq_[part][n][k] += half_sq;
      sum_rate_[part][n][k] += rate;
      ++count_[part][n][k];
    }
  }
}

int RangeInterpolator::part(int beacon, int pose) const {
  if (pose >= static_cast<int>(count_[0][beacon].size())) return -1;
  if (count_[0][beacon][pose] > 0) return 0;
  return count_[1][beacon][pose] > 0 ? 1 : -1;
}

bool RangeInterpolator::halfSquaredRange(int beacon, int pose, double* value) const {
  const int p = part(beacon, pose);
  if (p < 0) return false;
  *value = sum_half_sq_[p][beacon][pose] / count_[p][beacon][pose];
  return true;
}

bool RangeInterpolator::rangeRate(int beacon, int pose, double* value) const {
  const int p = part(beacon, pose);
  if (p < 0) return false;
  *value = sum_rate_[p][beacon][pose] / count_[p][beacon][pose];
  return true;
}

}  // namespace roam::spectral
