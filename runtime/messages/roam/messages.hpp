// Channel names and the conversions between roam's LCM messages and the C structs of the plugin
// ABI (roam/plugin_abi.h): the host's side of the boundary, one conversion each way per message.
// The other side, C struct <-> roam/types.hpp, is the shim's (roam::shim::toC / fromC). A tool
// that reads a log into roam/types.hpp composes the two: shim::fromC(fromMessage(message)).
// A field added to a message touches its .lcm file, its field list in messages.cpp and its field
// list in plugin_shim.cpp.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "roam/map_t.hpp"
#include "roam/odometry_t.hpp"
#include "roam/plugin_abi.h"
#include "roam/pose_t.hpp"
#include "roam/range_t.hpp"
#include "roam/trajectory_t.hpp"

namespace roam {
namespace channels {

// Inputs (DESIGN.md, "Channels").
inline constexpr const char* ODOMETRY = "ODOMETRY";
inline constexpr const char* RANGE = "RANGE";
inline constexpr const char* INITIAL_POSE = "INITIAL_POSE";
inline constexpr const char* BEACONS = "BEACONS";
inline constexpr const char* GROUND_TRUTH = "GROUND_TRUTH";
// A team's log: each robot's inputs on its own channels, <CHANNEL>_<robot> (ODOMETRY_A, RANGE_A,
// INITIAL_POSE_A, GROUND_TRUTH_A), its ranges to other robots (robot_range_t) on ROBOT_RANGE_<robot>;
// BEACONS is the team's. Outputs of an estimator NAME for robot R: POSE_NAME_R, TRAJECTORY_NAME_R.
inline constexpr const char* ROBOT_RANGE = "ROBOT_RANGE";

// Output prefixes, one channel each per estimator instance: <PREFIX><NAME upper-cased>.
inline constexpr const char* POSE_PREFIX = "POSE_";
inline constexpr const char* MAP_PREFIX = "MAP_";
inline constexpr const char* TRAJECTORY_PREFIX = "TRAJECTORY_";
inline constexpr const char* STATUS_PREFIX = "STATUS_";

}  // namespace channels

// "POSE_" + "spectral" -> "POSE_SPECTRAL". A prefix without the trailing '_' gets one
// ("POSE" + "dr" -> "POSE_DR"); an empty prefix gives the upper-cased name alone.
std::string outputChannel(const std::string& prefix, const std::string& estimator_name);

// A team member's channel: teamChannel("ODOMETRY", "A") -> "ODOMETRY_A".
inline std::string teamChannel(const std::string& channel, const std::string& robot) { return channel + "_" + robot; }

// ASCII upper case ("ekf-2" -> "EKF-2"): the channel suffix of an estimator name.
std::string upperCase(const std::string& text);

// odometry_t <-> roam_odometry
roam_odometry fromMessage(const roam::odometry_t& message);
roam::odometry_t toMessage(const roam_odometry& odometry);

// range_t <-> roam_range (has_bearing is 0 or 1 on both sides)
roam_range fromMessage(const roam::range_t& message);
roam::range_t toMessage(const roam_range& range);

// pose_t <-> roam_pose; `estimator` is "" for inputs (INITIAL_POSE, GROUND_TRUTH).
roam_pose fromMessage(const roam::pose_t& message);
roam::pose_t toMessage(const roam_pose& pose, const std::string& estimator = "");

// map_t <-> beacons (the message's utime and estimator are not part of the beacons).
std::vector<roam_beacon> fromMessage(const roam::map_t& message);
roam::map_t toMessage(const std::vector<roam_beacon>& beacons, int64_t utime,
                      const std::string& estimator = "");

// trajectory_t <-> poses. Covariances are not carried: NaN on the way back. Throws
// std::runtime_error if the message's parallel arrays differ in length.
std::vector<roam_pose> fromMessage(const roam::trajectory_t& message);
roam::trajectory_t toMessage(const std::vector<roam_pose>& poses, int64_t utime,
                             const std::string& estimator = "");

}  // namespace roam
