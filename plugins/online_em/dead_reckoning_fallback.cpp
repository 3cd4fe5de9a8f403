// Dead-reckoning fallback (fallback_deadreckoning): the filter's solution is not trusted where, at
// the end of the run, its learned outlier weight w1 sits at its bound (kMaxOutlierWeight): fewer
// than 1 - w1 of the ranges fit the path and map. From the start pose no beacon is fixed, the map
// is fitted to the same ranges, and below the breakdown point of a robust estimator (one half) a
// wrong basin that explains another minority fits as well. With surveyed beacons the map is held
// to the survey, so it is the path that no longer fits: a cloud that fell behind the vehicle
// scores its inliers as outliers and nothing pulls it back (README "Round 20"). Published instead:
// dead reckoning from the start pose (roam's shared motion model, uncalibrated, as the
// deadreckoning plugin and spectral + batch's fallback); from the start pose each landmark is
// multilaterated from it by the shared consensus of triples on all its ranges (the
// initialisation's inlier band), with surveyed beacons the map stays the survey's.
//
// Before that, with surveyed beacons: a run that held the heading-rate bias at 0 because its
// ranges are sparse (heading_rate_bias_max_drift_rad) has a second explanation for losing the
// vehicle, a gyro that drifts faster than the particles' heading noise follows (a slow UWB robot
// ranging every 6.7 s with a 0.005 rad/s gyro: 33 mrad per fix). The rule holds b because at those
// rates a b learned on a vehicle whose heading does not drift (an AUV's compass) takes up outliers
// and costs; where the held run is lost anyway, that cost is moot. So the run is made once more,
// on every input, with b estimated at any rate (and smoothed, as the sparse run was), and
// published where that run's outlier weight ends under the bound and it found the drifting gyro
// that explains the loss: |b| >= kRetryBiasSigmas sigma_b (complete-data sigma). A retry that wins
// without a bias is another draw of a lost filter, not the other model: on AUV-like runs with
// surveyed beacons and no gyro bias, 3 of 400 retries ended under the bound at 0.45-0.80 sigma_b
// (two near the truth, one 4 x dead reckoning); the slow robot's retries found b at 24-25 sigma_b.
// Otherwise dead reckoning. From the start pose there is no retry: a map fitted to the same ranges
// has its own wrong basins, and of 160 AUV-like start-pose runs the 4 retries that ended under the
// bound were all worse than dead reckoning (1.4-2.3 x).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <vector>

#include "online_em_slam.hpp"
#include "roam/estimation/motion_model.hpp"
#include "roam/estimation/multilateration.hpp"

namespace roam {
namespace online_em {
namespace {
// A two-sided 0.3 % test, as rerun_end_bias_sigmas' default.
constexpr double kRetryBiasSigmas = 3.0;
}  // namespace

bool OnlineEmSlam::fallbackEnabled() const {
  return config_.fallback_deadreckoning && config_.estimate_mixture && config_.indicators == OnlineEmConfig::Indicators::kMarginal;
}

void OnlineEmSlam::recordDeadReckoning(const Odometry& odometry) {
  if (!fallbackEnabled() || dead_reckoned_.empty()) return;
  const DeadReckonedPose& last = dead_reckoned_.back();
  Pose from;
  from.utime = last.utime;
  from.x_m = last.x_m;
  from.y_m = last.y_m;
  from.heading_rad = last.heading_rad;
  const Pose p = estimation::step(from, odometry);
  dead_reckoned_.push_back({p.utime, p.x_m, p.y_m, p.heading_rad});
}

void OnlineEmSlam::recordDeadReckonedRanges(const std::vector<Range>& ranges) {
  // Only the start pose's fallback multilaterates its map from them.
  if (!fallbackEnabled() || dead_reckoned_.empty() || config_.anchor != OnlineEmConfig::Anchor::kStartPose) return;
  for (const Range& r : ranges)
    dead_reckoned_ranges_.push_back({dead_reckoned_.size() - 1, r.beacon_id, r.range_m, r.sigma_m});
}

bool OnlineEmSlam::retriesWithBiasEstimated() const {
  return fallbackEnabled() && config_.anchor == OnlineEmConfig::Anchor::kBeacons && config_.calibrate_odometry &&
         config_.motion_model == OnlineEmConfig::MotionModel::kOdometry && config_.heading_rate_bias_max_drift_rad > 0.0 &&
         !biasEstimated();
}

bool OnlineEmSlam::retryWithBiasEstimated() {
  if (!retriesWithBiasEstimated() || all_inputs_.empty()) return false;
  OnlineEmConfig config = config_;
  config.heading_rate_bias_max_drift_rad = 0.0;  // estimated at any rate
  if (config.smooth_trajectory == OnlineEmConfig::SmoothTrajectory::kSparse)
    config.smooth_trajectory = OnlineEmConfig::SmoothTrajectory::kBeacons;
  config.fallback_deadreckoning = false;  // judged here
  auto retry = std::make_unique<OnlineEmSlam>(config);
  retry->setInitialPose(start_pose_);
  retry->setBeacons(surveyed_);
  for (const Input& input : all_inputs_) {
    if (input.is_odometry)
      retry->addOdometry(input.odometry);
    else
      retry->addRange(input.range);
  }
  retry->finish();
  const double weight = retry->learned_outlier_weight_;
  setDiagnostic("bias_retry_outlier_weight", weight);
  const double sigma_b = retry->heading_rate_bias_sigma_rad_s_;
  if (std::isfinite(sigma_b) && sigma_b > 0.0)
    setDiagnostic("bias_retry_bias_sigmas", std::abs(retry->calibration_.heading_rate_bias_rad_s) / sigma_b);
  char text[400];
  if (weight >= kMaxOutlierWeight) {
    note("re-run with the heading-rate bias estimated (the held run lost the vehicle): its outlier weight ended at "
         "its bound too");
    return false;
  }
  if (!retry->biasSignificant(kRetryBiasSigmas)) {
    std::snprintf(text, sizeof text,
                  "re-run with the heading-rate bias estimated (the held run lost the vehicle): it found no drifting "
                  "gyro (b = %.5f rad/s, under %.0f sigma), so it is not the explanation",
                  retry->calibration_.heading_rate_bias_rad_s, kRetryBiasSigmas);
    note(text);
    return false;
  }
  std::snprintf(text, sizeof text,
                "published a re-run with the heading-rate bias estimated (b = %.5f rad/s, outlier weight %.2f): held at "
                "0 (heading_rate_bias_max_drift_rad), the filter lost the vehicle (outlier weight at its bound, %.2f)",
                retry->odometryCalibration().heading_rate_bias_rad_s, weight, kMaxOutlierWeight);
  note(text);
  for (const auto& [key, value] : retry->diagnostics())
    if (key.rfind("note: ", 0) != 0) setDiagnostic(key, value);
  setDiagnostic("bias_retry", 1.0);
  emitMap(retry->currentMap());
  bias_retry_ = std::move(retry);
  return true;
}

Path OnlineEmSlam::deadReckonedPath() const {
  Path path;
  path.reserve(dead_reckoned_.size());
  for (const DeadReckonedPose& p : dead_reckoned_) {
    Pose pose;
    pose.utime = p.utime;
    pose.x_m = p.x_m;
    pose.y_m = p.y_m;
    pose.heading_rad = p.heading_rad;
    path.push_back(pose);
  }
  return path;
}

void OnlineEmSlam::fallBackToDeadReckoning() {
  fallen_back_ = true;
  setDiagnostic("dead_reckoning_fallback", 1.0);
  setDiagnostic("odometry_distance_scale", 1.0);
  setDiagnostic("heading_rate_bias_rad_s", 0.0);
  setDiagnostic("range_scale", 1.0);
  setDiagnostic("range_offset_m", 0.0);
  const bool surveyed = config_.anchor == OnlineEmConfig::Anchor::kBeacons;
  char text[320];
  std::snprintf(text, sizeof text,
                "published dead reckoning: its learned outlier weight ended at its bound (%.2f): under %.0f %% of "
                "the ranges fit %s, so the solution is not trusted (fallback_deadreckoning)",
                kMaxOutlierWeight, 100.0 * (1.0 - kMaxOutlierWeight),
                surveyed ? "its path to the surveyed beacons (the filter lost the vehicle)" : "a map placed from those same ranges");
  note(text);
  // With surveyed beacons the map is the survey's (held to it by beacon_prior_sigma_m): it stays.
  if (surveyed) return;
  std::map<int, std::vector<std::array<double, 2>>> points;
  std::map<int, std::vector<double>> ranges_m;
  std::map<int, double> sigma_m;
  for (const DeadReckonedRange& r : dead_reckoned_ranges_) {
    const DeadReckonedPose& p = dead_reckoned_[r.pose];
    points[r.beacon_id].push_back({p.x_m, p.y_m});
    ranges_m[r.beacon_id].push_back(r.range_m);
    sigma_m.emplace(r.beacon_id, r.sigma_m > 0.0 ? r.sigma_m : config_.range_sigma_m);
  }
  Map map;
  for (const auto& [id, positions] : points) {
    std::array<double, 2> beacon_m{0.0, 0.0};
    if (!multilaterateLandmark(positions, ranges_m[id], sigma_m[id], &beacon_m)) continue;
    Beacon b;
    b.id = id;
    b.x_m = beacon_m[0];
    b.y_m = beacon_m[1];
    map.push_back(b);
  }
  emitMap(map);
}

}  // namespace online_em
}  // namespace roam
