// readResultLog: what roam-eval and roam-export need from a log — ground truth, surveyed
// beacons, the inputs for a dead-reckoning baseline, and every estimator's outputs.
//
// Estimators are found from the POSE_ / TRAJECTORY_ / MAP_ / STATUS_ channels; the key is the
// channel suffix (upper case), the name the messages' `estimator` field (the suffix if empty).
// An event that does not decode as its channel's type is skipped and counted; so is a cut
// event at the end of the file. Other channels are ignored.
//
// A team log (messages.hpp) has a GROUND_TRUTH_<R> per robot R instead of GROUND_TRUTH; the robots
// are those suffixes. An estimator NAME's POSE_<NAME>_<R> / TRAJECTORY_<NAME>_<R> are then its
// path for robot R (NAME may itself hold '_': the robot is the longest known robot suffix), and
// MAP_<NAME> / STATUS_<NAME> the team's. The team's dead reckoning is not integrated here.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "roam/types.hpp"

namespace roam {

// The name of an estimator_status_t state ("initializing", "tracking", "finished", "failed";
// "unknown" for any other value).
const char* stateName(int8_t state);

// One robot's outputs of a team estimator.
struct RobotOutputs {
  Path poses;                      // every POSE_<suffix>_<R>, in log order
  std::optional<Path> trajectory;  // the last TRAJECTORY_<suffix>_<R>
  const Path& scoredPath() const { return trajectory ? *trajectory : poses; }
};

struct EstimatorOutputs {
  std::string suffix;             // channel suffix, e.g. "SPECTRAL"
  std::string name;               // estimator field, e.g. "spectral"
  Path poses;                     // every POSE_<suffix>, in log order
  std::optional<Path> trajectory; // the last TRAJECTORY_<suffix>
  std::optional<Map> map;         // the last MAP_<suffix>
  std::optional<double> cpu_total_s;  // of the last STATUS_<suffix>
  std::string state;              // of the last STATUS_: initializing|tracking|finished|failed
  std::string last_error;
  // Of the last STATUS_: the counters and the estimator's diagnostics (rejections by reason,
  // calibration, solver figures), in the message's order.
  long odometry_accepted = 0, odometry_rejected = 0, ranges_accepted = 0, ranges_rejected = 0;
  std::vector<std::pair<std::string, double>> diagnostics;

  // Team log: each robot's outputs by robot name; a robot it published nothing for is absent.
  std::map<std::string, RobotOutputs> robots;

  // The path roam-eval scores: the last trajectory if any, else the poses.
  const Path& scoredPath() const { return trajectory ? *trajectory : poses; }
  // Team log: robot R's path roam-eval scores, nullptr if it published none for R.
  const Path* robotPath(const std::string& robot) const;
};

struct ResultLog {
  std::string path;
  Path ground_truth;               // GROUND_TRUTH, log order
  std::optional<Map> beacons;      // the last BEACONS
  std::optional<Pose> start;       // the first INITIAL_POSE
  std::vector<Odometry> odometry;  // ODOMETRY, log order
  std::vector<Range> ranges;       // RANGE, log order
  std::vector<EstimatorOutputs> estimators;  // in order of first appearance
  long events = 0;
  long skipped = 0;                // undecodable events (and a cut last event)
  // Team log: GROUND_TRUTH_<R> by robot name R, log order each; empty for a single robot's log.
  std::map<std::string, Path> team_ground_truth;

  bool isTeam() const { return !team_ground_truth.empty(); }
  std::vector<std::string> robotNames() const;  // the team's robots, sorted
  const EstimatorOutputs* find(const std::string& name_or_suffix) const;
};

// Throws std::runtime_error("<path>: cannot open ...") if the file is not a readable log.
ResultLog readResultLog(const std::string& path);

// Dead reckoning by the shared motion model (roam::estimation::step) from `start`; one pose per
// odometry step (plus start).
Path integrateOdometry(const Pose& start, const std::vector<Odometry>& odometry);

}  // namespace roam
