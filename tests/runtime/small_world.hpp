// The small synthetic world the runtime and bad-input tests replay: 300 steps of a lawn mower,
// 4 beacons ranged round robin (UWB-like), 2 % odometry noise, 0.1 m range noise. Seeded.
#pragma once

#include <filesystem>

#include "dataset_log.hpp"
#include "sim.hpp"

namespace roam {
namespace testing_util {

inline sim::SimConfig smallWorld() {
  sim::SimConfig config;
  config.seed = 7;
  config.num_steps = 300;
  config.schedule = sim::RangeSchedule::kRoundRobin;
  config.odo_distance_sigma_rel = 0.02;
  config.range_sigma_m = 0.1;
  return config;
}

// smallWorld() simulated and written as <dir>/sim.lcmlog, the input of the replay tests.
inline std::filesystem::path writeSmallWorldLog(const std::filesystem::path& dir) {
  const std::filesystem::path log = dir / "sim.lcmlog";
  writeDatasetLog(log.string(), sim::simulate(smallWorld()));
  return log;
}

}  // namespace testing_util
}  // namespace roam
