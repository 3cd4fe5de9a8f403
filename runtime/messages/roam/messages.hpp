// Channel names and conversions between the plain structs of roam/types.hpp and the roam LCM
// messages. The only place outside the runtime where struct <-> message mapping is written down.
#pragma once

#include <cstdint>
#include <string>

#include "roam/map_t.hpp"
#include "roam/odometry_t.hpp"
#include "roam/pose_t.hpp"
#include "roam/range_t.hpp"
#include "roam/trajectory_t.hpp"
#include "roam/types.hpp"

namespace roam {
namespace channels {

// Inputs (DESIGN.md, "Channels").
inline constexpr const char* ODOMETRY = "ODOMETRY";
inline constexpr const char* RANGE = "RANGE";
inline constexpr const char* INITIAL_POSE = "INITIAL_POSE";
inline constexpr const char* BEACONS = "BEACONS";
inline constexpr const char* GROUND_TRUTH = "GROUND_TRUTH";

// Output prefixes, one channel each per estimator instance: <PREFIX><NAME upper-cased>.
inline constexpr const char* POSE_PREFIX = "POSE_";
inline constexpr const char* MAP_PREFIX = "MAP_";
inline constexpr const char* TRAJECTORY_PREFIX = "TRAJECTORY_";
inline constexpr const char* STATUS_PREFIX = "STATUS_";

}  // namespace channels

// "POSE_" + "spectral" -> "POSE_SPECTRAL". A prefix without the trailing '_' gets one
// ("POSE" + "dr" -> "POSE_DR"); an empty prefix gives the upper-cased name alone.
std::string outputChannel(const std::string& prefix, const std::string& estimator_name);

// ASCII upper case ("ekf-2" -> "EKF-2"): the channel suffix of an estimator name.
std::string upperCase(const std::string& text);

// odometry_t <-> Odometry
roam::odometry_t toMessage(const Odometry& odometry);
Odometry fromMessage(const roam::odometry_t& message);

// range_t <-> Range
roam::range_t toMessage(const Range& range);
Range fromMessage(const roam::range_t& message);

// pose_t <-> Pose; `estimator` is "" for inputs (INITIAL_POSE, GROUND_TRUTH).
roam::pose_t toMessage(const Pose& pose, const std::string& estimator = "");
Pose fromMessage(const roam::pose_t& message);

// map_t <-> Map (the message's utime and estimator are not part of Map).
roam::map_t toMessage(const Map& map, int64_t utime, const std::string& estimator = "");
Map fromMessage(const roam::map_t& message);

// trajectory_t <-> Path (covariances are not carried: NaN on the way back).
roam::trajectory_t toMessage(const Path& path, int64_t utime, const std::string& estimator = "");
Path fromMessage(const roam::trajectory_t& message);

}  // namespace roam
