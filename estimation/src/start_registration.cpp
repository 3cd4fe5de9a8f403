#include "roam/estimation/start_registration.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "roam/estimation/median.hpp"
#include "roam/estimation/multilateration.hpp"
#include "roam/estimation/range_model.hpp"
#include "roam/types.hpp"

namespace roam {
namespace estimation {
namespace {

constexpr double kPi = 3.14159265358979323846;
// Cauchy's rho on a whitened residual e: c^2 log(1 + e^2 / c^2) (e^2 for small e).
double rho(double e) { return kCauchy95 * kCauchy95 * std::log1p((e / kCauchy95) * (e / kCauchy95)); }
// The noise factor's floor: exact ranges (f = 0) must not whiten by infinity.
constexpr double kMinNoiseFactor = 1e-6;

Eigen::Vector2d rotated(double heading_rad, const Eigen::Vector2d& v) {
  const double c = std::cos(heading_rad), s = std::sin(heading_rad);
  return {c * v.x() - s * v.y(), s * v.x() + c * v.y()};
}

// Residual e_i = |a_i - R q_i - t| - r_i, whitened by f sigma_i.
double whitened(const StartRangeObservation& o, const Eigen::Vector3d& start, double f) {
  const Eigen::Vector2d d = o.world_m - rotated(start.z(), o.local_m) - start.head<2>();
  return (d.norm() - o.range_m) / (f * o.sigma_m);
}

double cost(const std::vector<StartRangeObservation>& observations, const Eigen::Vector3d& start, double f) {
  double sum = 0.0;
  for (const auto& o : observations) sum += rho(whitened(o, start, f));
  return sum;
}

// Gauss-Newton with Cauchy weights (IRLS) and step halving, over t alone (dims 2) or (t, theta)
// (dims 3). Returns the cost at the solution; information is J' W J there (whitened).
template <int kDims>
double solve(const std::vector<StartRangeObservation>& observations, double f, int max_iterations,
             Eigen::Vector3d* start, Eigen::Matrix<double, kDims, kDims>* information) {
  double current = cost(observations, *start, f);
  Eigen::Matrix<double, kDims, kDims> h;
  for (int iteration = 0; iteration <= max_iterations; ++iteration) {
    h.setZero();
    Eigen::Matrix<double, kDims, 1> g = Eigen::Matrix<double, kDims, 1>::Zero();
    for (const auto& o : observations) {
      const Eigen::Vector2d local = rotated(start->z(), o.local_m);
      const Eigen::Vector2d d = o.world_m - local - start->head<2>();
      const double distance = d.norm();
      if (distance < 1e-12) continue;
      const Eigen::Vector2d u = d / distance;
      const double scale = f * o.sigma_m;
      const double e = (distance - o.range_m) / scale;
      Eigen::Matrix<double, kDims, 1> j;
      j.template head<2>() = -u / scale;
      if constexpr (kDims == 3) j(2) = -u.dot(Eigen::Vector2d(-local.y(), local.x())) / scale;
      const double w = cauchyWeight(e);
      h += w * j * j.transpose();
      g += w * j * e;
    }
    if (information) *information = h;
    if (iteration == max_iterations) break;
    const Eigen::Matrix<double, kDims, 1> delta = h.ldlt().solve(-g);
    if (!delta.allFinite()) break;
    bool improved = false;
    for (double step = 1.0; step > 1e-4; step *= 0.5) {
      Eigen::Vector3d trial = *start;
      trial.head<kDims>() += step * delta;
      const double trial_cost = cost(observations, trial, f);
      if (trial_cost < current) {
        const double gain = current - trial_cost;
        *start = trial;
        current = trial_cost;
        improved = gain > 1e-12 * (1.0 + current);
        break;
      }
    }
    if (!improved) break;
  }
  return current;
}

// The cost profiled at a heading: t by multilateration of a_i - R q_i, then Gauss-Newton.
double profile(const std::vector<StartRangeObservation>& observations, double heading_rad, double f,
               int max_iterations, Eigen::Vector3d* start) {
  std::vector<std::array<double, 2>> points;
  std::vector<double> ranges;
  points.reserve(observations.size());
  ranges.reserve(observations.size());
  for (const auto& o : observations) {
    const Eigen::Vector2d p = o.world_m - rotated(heading_rad, o.local_m);
    points.push_back({p.x(), p.y()});
    ranges.push_back(o.range_m);
  }
  std::array<double, 2> t{0.0, 0.0};
  if (!multilaterateLinear(points, ranges, &t)) return std::numeric_limits<double>::infinity();
  *start = Eigen::Vector3d(t[0], t[1], heading_rad);
  return solve<2>(observations, f, max_iterations, start, nullptr);
}

struct Profile {
  std::vector<double> costs;
  std::vector<Eigen::Vector3d> starts;
  int best = -1;
};

Profile profileAll(const std::vector<StartRangeObservation>& observations, const StartRegistrationConfig& config,
                   double f) {
  Profile out;
  out.costs.resize(static_cast<size_t>(config.heading_steps));
  out.starts.resize(static_cast<size_t>(config.heading_steps));
  for (int k = 0; k < config.heading_steps; ++k) {
    const double heading_rad = -kPi + 2.0 * kPi * k / config.heading_steps;
    out.costs[k] = profile(observations, heading_rad, f, config.max_iterations, &out.starts[k]);
    if (std::isfinite(out.costs[k]) && (out.best < 0 || out.costs[k] < out.costs[out.best])) out.best = k;
  }
  return out;
}

}  // namespace

StartRegistration registerStart(const std::vector<StartRangeObservation>& observations,
                                const StartRegistrationConfig& config) {
  StartRegistration out;
  out.ranges = static_cast<int>(observations.size());
  if (out.ranges < std::max(config.min_ranges, 4) || config.heading_steps < 8) return out;
  out.status = StartRegistration::Status::kNoSolution;

  // The profile's sample: every k-th range.
  std::vector<StartRangeObservation> sample;
  const size_t every = (observations.size() + config.profile_ranges - 1) / std::max(1, config.profile_ranges);
  for (size_t i = 0; i < observations.size(); i += std::max<size_t>(1, every)) sample.push_back(observations[i]);

  // First pass at f = 1: the best heading, refined; f from the residuals there (1.4826 x the
  // median |whitened residual|, the Gaussian's: up to half of the ranges may be outliers).
  Profile first = profileAll(sample, config, 1.0);
  if (first.best < 0) return out;
  Eigen::Vector3d start = first.starts[first.best];
  Eigen::Matrix3d information;
  solve<3>(observations, 1.0, config.max_iterations, &start, &information);
  std::vector<double> magnitudes;
  magnitudes.reserve(observations.size());
  for (const auto& o : observations) magnitudes.push_back(std::abs(whitened(o, start, 1.0)));
  const double f = std::max(kMinNoiseFactor, 1.4826 * upperMedian(magnitudes));

  // Second pass at f: the profile the acceptance reads, and the solution from its best heading.
  Profile second = profileAll(sample, config, f);
  if (second.best < 0) return out;
  start = second.starts[second.best];
  out.cost = solve<3>(observations, f, config.max_iterations, &start, &information);
  start.z() = wrapAngle(start.z());
  out.start = start;
  out.noise_factor = f;
  for (const auto& o : observations) out.inliers += std::abs(whitened(o, start, f)) <= 3.0 * kCauchy95 ? 1 : 0;

  // The headings the ranges cannot reject: profiled cost within rival_chi2 of the best. They must
  // form one arc about the best, of at most max_heading_arc_rad.
  const int n = config.heading_steps;
  const double grid_step_rad = 2.0 * kPi / n;
  const auto excess = [&](int k) { return second.costs[((k % n) + n) % n] - second.costs[second.best]; };
  int left = 0, right = 0;
  while (left + right + 1 < n && excess(second.best - left - 1) < config.rival_chi2) ++left;
  while (left + right + 1 < n && excess(second.best + right + 1) < config.rival_chi2) ++right;
  out.rival_excess = std::numeric_limits<double>::infinity();
  for (int k = second.best + right + 1; k < second.best + n - left; ++k) {
    if (excess(k) < out.rival_excess) {
      out.rival_excess = excess(k);
      out.rival_heading_rad = wrapAngle(-kPi + grid_step_rad * k);
    }
  }
  out.heading_arc_rad = (left + right) * grid_step_rad;
  if (out.heading_arc_rad > config.max_heading_arc_rad) {
    out.rival_excess = 0.0;
    out.rival_heading_rad = wrapAngle(-kPi + grid_step_rad * (left >= right ? second.best - left : second.best + right));
  }
  if (out.rival_excess < config.rival_chi2) {
    out.status = StartRegistration::Status::kAmbiguous;
    return out;
  }
  Eigen::LDLT<Eigen::Matrix3d> ldlt(information);
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0.0)) return out;
  out.covariance = ldlt.solve(Eigen::Matrix3d::Identity());
  out.status = StartRegistration::Status::kFound;
  return out;
}

}  // namespace estimation
}  // namespace roam
