// writeDatasetLog: a roam::Dataset as an LCM log, the input every roam-run replay reads.
//
// Events, each stamped with its message's utime:
//   INITIAL_POSE (pose_t, the start pose) and BEACONS (map_t, utime = start pose's), first;
//   then GROUND_TRUTH (pose_t), ODOMETRY (odometry_t) and RANGE (range_t) merged by utime —
//   at equal utime GROUND_TRUTH, then ODOMETRY, then RANGE; each source keeps its own order.
// range_latency_us > 0: each RANGE is logged (merged and stamped as an event) that much after its
// message's utime, as a sensor whose ranges arrive late would be recorded; the message keeps
// its utime.
// BEACONS is written even when the map is empty (so a reader knows there are none).
//
// writeTeamLog: a roam::TeamDataset as a team's log (runtime/messages/roam/messages.hpp). First
// INITIAL_POSE_<R> for every robot R in team order, then BEACONS once, all logged at the team's
// earliest start utime (each pose_t keeps its robot's start utime, BEACONS that earliest one);
// then every robot's GROUND_TRUTH_<R>, ODOMETRY_<R>, RANGE_<R> (range_t) and the ranges between
// robots, ROBOT_RANGE_<R> (robot_range_t, R the measuring robot, other_robot the other's name),
// merged by utime: at equal utime GROUND_TRUTH, ODOMETRY, RANGE, then ROBOT_RANGE, each of them
// robot by robot in team order; each source keeps its own order.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "dataset.hpp"

namespace roam {

struct LogWriteSummary {
  long events = 0;
  long ground_truth = 0;
  long odometry = 0;
  long ranges = 0;
  long beacons = 0;
};

// Throws std::runtime_error ("<path>: cannot open for writing" / "write failed").
LogWriteSummary writeDatasetLog(const std::string& path, const Dataset& dataset, int64_t range_latency_us = 0);

struct TeamLogWriteSummary {
  long events = 0;
  std::vector<LogWriteSummary> members;  // per robot: its events (and the team's beacons' count)
  std::vector<long> robot_ranges;        // per robot: the ranges to other robots it measured
  long beacons = 0;
};

// Throws std::invalid_argument for a team whose members do not match its names or whose robot
// ranges name no member (or the robot itself), std::runtime_error as writeDatasetLog.
TeamLogWriteSummary writeTeamLog(const std::string& path, const TeamDataset& team);

}  // namespace roam
