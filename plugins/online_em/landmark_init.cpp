// Landmark initialisation (anchor = start_pose; model in online_em_slam.hpp, "Robust
// initialisation"): each landmark's ranges are buffered at the particle cloud's mean pose until
// they can place it (a range with a bearing places it at once). tryInitialise multilaterates it
// by a consensus of range triples (roam/estimation/multilateration.hpp, inlier band
// init_outlier_gate_sigmas x sr) once the ranging positions span enough angle seen from it
// (init_min_spread_fraction) and are spread by init_min_spread_m about their line (the mirror
// ambiguity); neverInitialisedReason names the check a landmark never passed, for its rejected
// ranges.
#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "online_em_slam.hpp"
#include "roam/estimation/multilateration.hpp"

namespace roam {
namespace online_em {

bool OnlineEmSlam::multilaterateLandmark(const std::vector<std::array<double, 2>>& points,
                                         const std::vector<double>& ranges_m, double sr,
                                         std::array<double, 2>* beacon_m) const {
  const double gate = config_.init_outlier_gate_sigmas;
  return gate > 0.0 ? estimation::multilaterateTriples(points, ranges_m, std::max(1.0, gate * sr), beacon_m)
                    : estimation::multilaterateLinear(points, ranges_m, beacon_m);
}

void OnlineEmSlam::tryInitialise(int i) {
  Landmark& landmark = landmarks_[i];
  std::vector<Eigen::Vector2d> positions;
  std::vector<double> ranges;
  for (size_t j = 0; j < landmark.pending_poses.size(); ++j) {
    positions.push_back(landmark.pending_poses[j].head<2>());
    ranges.push_back((landmark.pending_observations[j].range_m - range_offset_m_) / range_scale_);
  }
  std::optional<Eigen::Vector2d> position;
  const RangeObservation& last = landmark.pending_observations.back();
  if (last.has_bearing) {
    // Range and bearing place the landmark at once: m = p + r (cos(th + b), sin(th + b)).
    const Eigen::Vector3d& pose = landmark.pending_poses.back();
    position = pose.head<2>() + ranges.back() * Eigen::Vector2d(std::cos(pose.z() + last.bearing_rad),
                                                                std::sin(pose.z() + last.bearing_rad));
    positions = {positions.back()};
    landmark.pending_poses = {landmark.pending_poses.back()};
    landmark.pending_observations = {last};
  } else {
    landmark.failed_check = InitCheck::kTooFew;
    if (static_cast<int>(landmark.pending_poses.size()) < config_.init_min_ranges) return;
    // Inliers: within 3 sigma of the range noise (the range's own sigma if given), at least 1 m
    // for the dead-reckoned positions the ranges were taken from.
    const double sr = last.sigma_m > 0.0 ? last.sigma_m : config_.range_sigma_m;
    // The spread must also be a fraction of the distance to the beacon, or a path noisy about a
    // line fits the mirror image as well (an AUV's first straight lane, hundreds of metres away).
    std::vector<double> sorted = ranges;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    const double fraction_spread_m = config_.init_min_spread_fraction * sorted[sorted.size() / 2];
    // The shared multilateration (roam::estimation): refused while the positions are near a
    // line; the consensus of triples with the inlier band gate * sr (at least 1 m, for the
    // dead-reckoned positions); gate 0: the linear solution on all ranges.
    std::vector<std::array<double, 2>> points;
    for (const Eigen::Vector2d& p : positions) points.push_back({p.x(), p.y()});
    const double spread_m = estimation::positionSpread(points);
    landmark.failed_check = InitCheck::kNarrowAngle;
    if (spread_m < fraction_spread_m) return;
    landmark.failed_check = InitCheck::kShortSpread;
    if (spread_m < config_.init_min_spread_m) return;
    std::array<double, 2> beacon_m{0.0, 0.0};
    landmark.failed_check = InitCheck::kNoConsensus;
    if (!multilaterateLandmark(points, ranges, sr, &beacon_m)) return;
    position = Eigen::Vector2d(beacon_m[0], beacon_m[1]);
  }
  if (!position) return;
  landmark.initialised = true;
  landmark.position_m = *position;
  // Its statistic starts as the average statistic of the buffered ranges, each with the
  // posterior probabilities of the two mixture components at the new estimate.
  const Eigen::Vector4d phi_i = phi(i);
  Eigen::Matrix<double, 1, kStatSize> mean_stat = Eigen::Matrix<double, 1, kStatSize>::Zero();
  double stat0[kStatSize], stat1[kStatSize];
  for (size_t j = 0; j < positions.size(); ++j) {
    const Eigen::Vector3d& p = landmark.pending_poses[j];
    const RangeObservation& y = landmark.pending_observations[j];
    double r1 = 0.0;
    mixtureLogLikelihood(y, p.x(), p.y(), p.z(), phi_i, &r1);
    observation_.statistic(y, p.x(), p.y(), p.z(), phi_i, 0, stat0);
    observation_.statistic(y, p.x(), p.y(), p.z(), phi_i, 1, stat1);
    for (int s = 0; s < kStatSize; ++s) mean_stat[s] += (1.0 - r1) * stat0[s] + r1 * stat1[s];
  }
  mean_stat /= static_cast<double>(positions.size());
  statistics_.middleCols(kStatSize * i, kStatSize).rowwise() = mean_stat;
  landmark.count = static_cast<int64_t>(positions.size());
  landmark.pending_poses.clear();
  landmark.pending_observations.clear();
  if (auto counted = pending_live_ranges_.find(landmark.id); counted != pending_live_ranges_.end()) {
    for (int64_t k = 0; k < counted->second; ++k) acceptRange();
    pending_live_ranges_.erase(counted);
  }
  int initialised = 0;
  for (const Landmark& l : landmarks_) initialised += l.initialised ? 1 : 0;
  if (initialised >= 2 && initialised == static_cast<int>(landmarks_.size())) {
    window_open_ = false;
    // The window solve where the ranges re-fix the path often enough (the bias rule).
    window_solve_pending_ =
        config_.init_window_solve && config_.anchor == OnlineEmConfig::Anchor::kStartPose && bias_rate_.estimateSoFar();
  }
  mStep();
}

std::string OnlineEmSlam::neverInitialisedReason(InitCheck check) {
  switch (check) {
    case InitCheck::kTooFew:
      return "landmark never initialised: too few ranges (init_min_ranges)";
    case InitCheck::kNarrowAngle:
      return "landmark never initialised: its ranging positions span too narrow an angle seen from it "
             "(init_min_spread_fraction)";
    case InitCheck::kShortSpread:
      return "landmark never initialised: its ranging positions lie too near a line (init_min_spread_m)";
    default:
      return "landmark never initialised: no position agrees with most of its ranges (init_outlier_gate_sigmas)";
  }
}

}  // namespace online_em
}  // namespace roam
