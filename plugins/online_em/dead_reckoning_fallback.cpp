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
#include <algorithm>
#include <array>
#include <cstdio>
#include <map>
#include <vector>

#include "online_em_slam.hpp"
#include "roam/estimation/motion_model.hpp"
#include "roam/estimation/multilateration.hpp"

namespace roam {
namespace online_em {

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
