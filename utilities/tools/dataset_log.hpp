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
#pragma once

#include <cstdint>
#include <string>

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

}  // namespace roam
