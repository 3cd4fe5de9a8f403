// roam-sim's gyro bias walk (--gyro-bias-walk, rad/s per sqrt(s)): the bias starts at --gyro-bias
// and random-walks with that density; only the reported turns differ from the same seed without
// a walk, bit for bit everywhere else.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "sim.hpp"

namespace {

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

TEST(SimGyroBiasWalk, OnlyTheTurnsChangeAndTheBiasWalksWithItsDensity) {
  roam::sim::SimConfig config = roam::sim::gyroDriftFigure8World(5, 6000);  // 1200 s at 5 Hz
  const roam::sim::SimRun constant = roam::sim::simulate(config);
  const double walk = 1e-5;
  config.odo_heading_bias_walk_radps_per_sqrt_s = walk;
  const roam::sim::SimRun walking = roam::sim::simulate(config);

  ASSERT_EQ(walking.odometry.size(), constant.odometry.size());
  ASSERT_EQ(walking.ranges.size(), constant.ranges.size());
  for (size_t k = 0; k < constant.ranges.size(); ++k)
    EXPECT_TRUE(sameBits(walking.ranges[k].range_m, constant.ranges[k].range_m)) << "range " << k;
  for (size_t k = 0; k < constant.ground_truth.size(); ++k) {
    EXPECT_TRUE(sameBits(walking.ground_truth[k].x_m, constant.ground_truth[k].x_m));
    EXPECT_TRUE(sameBits(walking.ground_truth[k].heading_rad, constant.ground_truth[k].heading_rad));
  }
  // The reported turn differs by (b_k - b_0) dt: b_0 is the configured bias, and the bias's
  // increments over one 0.2 s step have sigma walk * sqrt(0.2).
  const double dt_s = config.dt_s;
  double sum_sq = 0.0, previous = 0.0, largest = 0.0;
  for (size_t k = 0; k < constant.odometry.size(); ++k) {
    EXPECT_TRUE(sameBits(walking.odometry[k].forward_m, constant.odometry[k].forward_m));
    const double drift_radps =
        (walking.odometry[k].delta_heading_rad - constant.odometry[k].delta_heading_rad) / dt_s;
    if (k == 0) EXPECT_NEAR(drift_radps, 0.0, 1e-12);
    else sum_sq += (drift_radps - previous) * (drift_radps - previous);
    previous = drift_radps;
    largest = std::max(largest, std::abs(drift_radps));
  }
  const double step_sigma = std::sqrt(sum_sq / static_cast<double>(constant.odometry.size() - 1));
  EXPECT_NEAR(step_sigma, walk * std::sqrt(dt_s), 0.05 * walk * std::sqrt(dt_s));  // 6000 draws: ~1 %
  // Over 1200 s the walk's sigma is 3.5e-4 rad/s: it went somewhere, and nowhere absurd.
  EXPECT_GT(largest, 1e-5);
  EXPECT_LT(largest, 5.0 * walk * std::sqrt(1200.0));
}

TEST(SimGyroBiasWalk, RefusesANegativeOrNonFiniteWalk) {
  roam::sim::SimConfig config = roam::sim::gyroDriftFigure8World(5, 10);
  config.odo_heading_bias_walk_radps_per_sqrt_s = -1e-5;
  EXPECT_THROW(roam::sim::simulate(config), std::invalid_argument);
  config.odo_heading_bias_walk_radps_per_sqrt_s = std::nan("");
  EXPECT_THROW(roam::sim::simulate(config), std::invalid_argument);
}

}  // namespace
