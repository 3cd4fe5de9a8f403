// Conversions between the plugin ABI's C structs and the roam LCM messages.
#pragma once

#include <string>
#include <vector>

#include "roam/beacon_t.hpp"
#include "roam/map_t.hpp"
#include "roam/odometry_t.hpp"
#include "roam/plugin_abi.h"
#include "roam/pose_t.hpp"
#include "roam/range_t.hpp"
#include "roam/trajectory_t.hpp"

namespace roam {
namespace runtime {

inline roam_odometry abiFromMessage(const roam::odometry_t& message) {
  return roam_odometry{message.utime, message.delta_distance, message.delta_heading};
}

inline roam_range abiFromMessage(const roam::range_t& message) {
  roam_range range{};
  range.utime = message.utime;
  range.beacon_id = message.beacon_id;
  range.has_bearing = message.has_bearing ? 1 : 0;
  range.range_m = message.range;
  range.sigma_m = message.sigma;
  range.bearing_rad = message.bearing;
  return range;
}

inline roam_pose abiFromMessage(const roam::pose_t& message) {
  roam_pose pose{};
  pose.utime = message.utime;
  pose.x_m = message.x;
  pose.y_m = message.y;
  pose.heading_rad = message.heading;
  for (int i = 0; i < 9; ++i) pose.covariance[i] = message.covariance[i];
  return pose;
}

inline std::vector<roam_beacon> abiFromMessage(const roam::map_t& message) {
  std::vector<roam_beacon> beacons;
  for (const auto& in : message.beacons) {
    roam_beacon beacon{};
    beacon.id = in.id;
    beacon.x_m = in.x;
    beacon.y_m = in.y;
    for (int i = 0; i < 4; ++i) beacon.covariance[i] = in.covariance[i];
    beacons.push_back(beacon);
  }
  return beacons;
}

inline roam::pose_t poseMessage(const roam_pose& pose, const std::string& estimator) {
  roam::pose_t message;
  message.utime = pose.utime;
  message.estimator = estimator;
  message.x = pose.x_m;
  message.y = pose.y_m;
  message.heading = pose.heading_rad;
  for (int i = 0; i < 9; ++i) message.covariance[i] = pose.covariance[i];
  return message;
}

inline roam::map_t mapMessage(int64_t utime, const std::vector<roam_beacon>& beacons,
                              const std::string& estimator) {
  roam::map_t message;
  message.utime = utime;
  message.estimator = estimator;
  message.num_beacons = static_cast<int32_t>(beacons.size());
  for (const auto& beacon : beacons) {
    roam::beacon_t out;
    out.id = beacon.id;
    out.x = beacon.x_m;
    out.y = beacon.y_m;
    for (int i = 0; i < 4; ++i) out.covariance[i] = beacon.covariance[i];
    message.beacons.push_back(out);
  }
  return message;
}

inline roam::trajectory_t trajectoryMessage(int64_t utime, const std::vector<roam_pose>& poses,
                                            const std::string& estimator) {
  roam::trajectory_t message;
  message.utime = utime;
  message.estimator = estimator;
  message.num_poses = static_cast<int32_t>(poses.size());
  for (const auto& pose : poses) {
    message.utimes.push_back(pose.utime);
    message.x.push_back(pose.x_m);
    message.y.push_back(pose.y_m);
    message.heading.push_back(pose.heading_rad);
  }
  return message;
}

}  // namespace runtime
}  // namespace roam
