// A run as plain structs: what roam-import reads from CSV, roam-sim generates, and the log
// writer turns into ODOMETRY / RANGE / GROUND_TRUTH / INITIAL_POSE / BEACONS events.
#pragma once

#include <string>
#include <vector>

#include "roam/types.hpp"

namespace roam {

struct Dataset {
  Pose start;                      // the known start pose (INITIAL_POSE)
  Path ground_truth;               // for scoring only; may be empty
  std::vector<Odometry> odometry;  // in time order; odometry[k] ends at its utime
  std::vector<Range> ranges;       // in time order
  Map beacons;                     // surveyed / true beacon positions (BEACONS)
};

// A team's run: each robot's own run (its start, ground truth, odometry and ranges to fixed
// beacons, every item's `robot` = its index in `robots`), the ranges between two robots (Range
// with robot = the measuring robot, other_robot = the robot ranged to, in time order), and the
// team's beacons (each member's `beacons` is empty). Written as a team log: INITIAL_POSE_<name>,
// GROUND_TRUTH_<name>, ODOMETRY_<name>, RANGE_<name>, ROBOT_RANGE_<name> and BEACONS.
struct TeamDataset {
  std::vector<std::string> robots;  // the team's names, the suffix of each member's channels
  std::vector<Dataset> members;     // one per robot, in the order of `robots`
  std::vector<Range> robot_ranges;  // ranges between two robots, in time order
  Map beacons;
};

// The readers' tally of one kind of line or row they set aside or read specially: how many, and
// the line of the first, for the note that says so.
struct LineTally {
  long count = 0;
  long first_line = 0;
  void add(long line) {
    if (count++ == 0) first_line = line;
  }
};

}  // namespace roam
