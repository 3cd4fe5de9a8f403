// roam::sim::simulateTeam — a seeded team run: N robots, each one roam::sim::simulate run (one
// motion model), and the ranges between them.
//
// Every robot drives the config's path kind from its own start pose: robot i starts
// i x robot_spacing_m to the left of the config's start (across its heading), its heading turned
// by 2 pi i / N, so no two start together nor drive in lockstep. All start at start_utime with
// the same dt_s, so every robot has a pose at every step's utime. Each robot's noise (odometry,
// gyro bias walk, ranges to beacons, NLOS stretches) is its own stream, seeded from the seed and
// its index. The beacons are the team's: the config's, or num_beacons (0 allowed) drawn around
// the area every robot sweeps; each beacon's offset is the same for every robot, and the survey
// error is drawn once.
//
// Ranges between robots: the pairs (i < j) round robin, robot_range_rate_hz per pair, each taken
// at the first pose time at or after its turn, measured by i on even rounds and by j on odd ones:
//   range = range_scale * |p_i - p_j| + range_offset_m + noise,
// noise as the config's for beacons (range_sigma_m, the mixture, outlier_fraction; with
// outlier_episode_s, NLOS stretches per pair), range_dropout, sigma stated range_sigma_reported_m,
// drawn from a stream of their own. Range gaps silence the beacons only.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "dataset.hpp"
#include "sim.hpp"

namespace roam {
namespace sim {

struct TeamSimConfig {
  SimConfig robot;                  // each robot's run (seed: the team's; start: robot 0's)
  int num_robots = 2;               // 1 to 26, named A, B, ...
  double robot_spacing_m = 2.0;     // between neighbouring start positions
  double robot_range_rate_hz = 1.0;  // per pair of robots (> 0)
};

// Throws std::invalid_argument for a config it cannot run.
TeamDataset simulateTeam(const TeamSimConfig& config);

}  // namespace sim
}  // namespace roam
