// A run as plain structs: what roam-import reads from CSV, roam-sim generates, and the log
// writer turns into ODOMETRY / RANGE / GROUND_TRUTH / INITIAL_POSE / BEACONS events.
#pragma once

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
