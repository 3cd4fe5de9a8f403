// The heading-rate bias before the solve (model in spectral_batch_slam.hpp):
// - decideHeadingAsStated: from the start pose at sparse range rates (the shared rule,
//   roam/estimation/bias_observability.hpp) the odometry's stated heading noise is taken and the
//   bias held at 0 (sparse_heading_as_stated);
// - scanHeadingRateBias: the bias whose dead reckoning best explains the ranges (a robust Cauchy
//   range cost against the surveyed beacons, or against beacons multilaterated robustly from that
//   path), scanned coarse to fine over +-3 prior sigmas, so that the local solve starts in its
//   basin.
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <vector>

#include "initial_guess.hpp"
#include "roam/estimation/bias_observability.hpp"
#include "roam/estimation/multilateration.hpp"
#include "roam/estimation/range_model.hpp"
#include "spectral_batch_slam.hpp"

namespace roam {
namespace spectral_batch {
namespace {

// Heading-rate bias scan: stop refining once half a step of bias leaves at most this heading
// error at the end of the run (a local solve, which estimates the bias itself, starts in its
// basin from there: 0.25 rad is ~1 m sideways per 4 m of travel at the far end, halved on
// average over the path), and never beyond 3 levels (the old fixed depth).
constexpr double kScanHeadingTolerance_rad = 0.25;
constexpr int kMaxScanLevels = 3;

}  // namespace

void SpectralBatchSlam::decideHeadingAsStated(bool final) {
  // The shared rule on the first ranges' fix times (roam/estimation/bias_observability.hpp),
  // re-read from the ranges kept: from the start pose at sparse rates the odometry's heading is
  // taken as stated and the bias held (sparse_heading_as_stated in batch_config.hpp).
  heading_as_stated_ = false;
  if (!config_.sparse_heading_as_stated || config_.anchor != SpectralBatchConfig::Anchor::kStartPose) return;
  // Only a log that states its odometry noise, every step of it: without a statement the heading
  // is the wheel model's, and its rotation gauge the window's.
  if (odometry_.empty() ||
      !std::all_of(odometry_.begin(), odometry_.end(), [](const Odometry& o) { return o.hasCovariance(); }))
    return;
  estimation::BiasObservability rule(kHeadingRateBiasPriorSigma_rad_s, config_.heading_rate_bias_max_drift_rad);
  for (const Range& range : ranges_)
    if (rule.addRange(range.utime) != estimation::BiasObservability::Decision::kUndecided) break;
  heading_as_stated_ = rule.decision() == estimation::BiasObservability::Decision::kHold;
  setDiagnostic("heading_as_stated", heading_as_stated_ ? 1.0 : 0.0);
  if (heading_as_stated_ && final)
    note("took each odometry step's stated heading noise and " + rule.heldNote("heading_rate_bias_max_drift_rad"));
}

double SpectralBatchSlam::scanHeadingRateBias(const std::vector<Tie>& tied) const {
  // Robust range cost of dead reckoning with bias b, beacons surveyed (anchor = beacons) or
  // robustly multilaterated from that path; Cauchy at the loss's scale over the range sigma.
  const double c = estimation::kCauchy95;
  auto score = [&](double bias_rad_s) {
    const std::vector<std::array<double, 3>> poses =
        spectral_batch::deadReckon(start_pose_, odometry_, dt_s_, estimation::OdometryCalibration{1.0, bias_rad_s});
    std::map<int, std::vector<std::array<double, 2>>> positions;
    std::map<int, std::vector<double>> ranges;
    std::map<int, double> sigma;
    for (const Tie& t : tied) {
      const auto& a = poses[t.pose];
      std::array<double, 2> p{a[0], a[1]};
      if (t.alpha != 0.0) {
        const auto& b = poses[t.pose + 1];
        p = {a[0] + t.alpha * (b[0] - a[0]), a[1] + t.alpha * (b[1] - a[1])};
      }
      positions[t.range->beacon_id].push_back(p);
      ranges[t.range->beacon_id].push_back(t.range->range_m);
      sigma[t.range->beacon_id] = rangeSigma(*t.range);
    }
    double cost = 0.0;
    for (const auto& [id, ps] : positions) {
      const Beacon* surveyed = nullptr;
      if (config_.anchor == SpectralBatchConfig::Anchor::kBeacons)
        for (const Beacon& b : surveyed_)
          if (b.id == id) surveyed = &b;
      if (surveyed) {
        for (size_t i = 0; i < ps.size(); ++i) {
          const double r = (std::hypot(surveyed->x_m - ps[i][0], surveyed->y_m - ps[i][1]) - ranges[id][i]) /
                           (sigma[id] * c);
          cost += 0.5 * c * c * std::log1p(r * r);
        }
      } else {
        estimation::RobustMultilateration robust;
        if (estimation::multilaterateRobust(ps, ranges[id], sigma[id], &robust)) cost += robust.cost;
        else cost += 0.5 * c * c * std::log1p(1e6) * static_cast<double>(ps.size());  // unobservable: worst
      }
    }
    return cost;
  };
  // Coarse to fine over +-3 prior sigmas: 31 points, then refinements at a tenth of the step
  // within +-10 fine steps of the best, until half a step leaves at most kScanHeadingTolerance_rad
  // of heading error at the end of the run. The batch solve estimates the bias itself; the scan
  // only has to start it in its basin. A refinement walks downhill from the best point (to the
  // neighbour that lowers the cost, then on while it keeps lowering it): the grid's minimum where
  // the cost is unimodal over the +-10 fine steps, in ~3-6 scores instead of 20 (each score is a
  // dead reckoning and a robust multilateration of every beacon: most of the scan's time).
  const double duration_s = 1e-6 * static_cast<double>(pose_utime_.back() - pose_utime_.front());
  const double span = 3.0 * kHeadingRateBiasPriorSigma_rad_s;
  double best = 0.0, best_cost = score(0.0);
  double step = span / 15.0;
  for (int i = -15; i <= 15; ++i) {
    const double b = step * i;
    if (b == 0.0) continue;
    const double cost = score(b);
    if (cost < best_cost) {
      best_cost = cost;
      best = b;
    }
  }
  for (int level = 1; level < kMaxScanLevels; ++level) {
    if (0.5 * step * duration_s <= kScanHeadingTolerance_rad) break;
    step /= 10.0;
    const double centre = best;
    const double cost_up = score(centre + step), cost_down = score(centre - step);
    int direction = 0;
    if (cost_up < best_cost && cost_up <= cost_down) {
      direction = 1;
      best_cost = cost_up;
      best = centre + step;
    } else if (cost_down < best_cost) {
      direction = -1;
      best_cost = cost_down;
      best = centre - step;
    }
    for (int i = 2; direction != 0 && i <= 10; ++i) {
      const double b = centre + step * direction * i;
      const double cost = score(b);
      if (!(cost < best_cost)) break;
      best_cost = cost;
      best = b;
    }
  }
  return best;
}

}  // namespace spectral_batch
}  // namespace roam
