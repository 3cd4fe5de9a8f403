// roam-sim's standing start (--hold-s S): the vehicle stands still for the first S seconds
// (ground truth fixed, zero forward odometry, heading odometry = gyro bias * dt + its noise,
// ranges still taken), then drives the path; hold 0 is the run without it.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "sim.hpp"

namespace {

TEST(SimHold, StandsStillThenDrives) {
  roam::sim::SimConfig config = roam::sim::gyroDriftFigure8World(5, 1000);
  config.odo_heading_bias_radps = 0.005;
  const roam::sim::SimRun moving = roam::sim::simulate(config);
  config.hold_s = 45.0;  // 225 steps of 0.2 s
  const roam::sim::SimRun held = roam::sim::simulate(config);
  constexpr int kHoldSteps = 225;
  ASSERT_EQ(held.ground_truth.size(), 1001u);
  ASSERT_EQ(held.odometry.size(), 1000u);
  for (int k = 0; k <= kHoldSteps; ++k) {
    EXPECT_EQ(held.ground_truth[k].x_m, held.start.x_m) << k;
    EXPECT_EQ(held.ground_truth[k].y_m, held.start.y_m) << k;
    EXPECT_EQ(held.ground_truth[k].heading_rad, held.start.heading_rad) << k;
  }
  // The gyro drifts while standing: sum of 225 turns = 0.005 * 45 = 0.225 rad, plus noise of
  // 0.003 sqrt(225) = 0.045 rad (within 4 sigma: 0.18 rad).
  double turn_rad = 0.0;
  for (int k = 0; k < kHoldSteps; ++k) {
    EXPECT_EQ(held.odometry[k].forward_m, 0.0) << k;
    turn_rad += held.odometry[k].delta_heading_rad;
  }
  EXPECT_NEAR(turn_rad, 0.225, 0.18);
  // Then it drives: the first step after the hold is the path's first, a 0.2 m arc of a 12 m
  // circle (chord 0.2 (1 - (0.2/12)^2 / 24) = 0.199995 m).
  const double first_step_m = std::hypot(held.ground_truth[kHoldSteps + 1].x_m - held.ground_truth[kHoldSteps].x_m,
                                         held.ground_truth[kHoldSteps + 1].y_m - held.ground_truth[kHoldSteps].y_m);
  EXPECT_NEAR(first_step_m, 0.199995, 1e-6);
  // Ranges are taken while standing: 2 Hz round robin over 45 s = 90.
  int held_ranges = 0;
  for (const roam::Range& r : held.ranges) held_ranges += r.utime <= held.ground_truth[kHoldSteps].utime ? 1 : 0;
  EXPECT_EQ(held_ranges, 90);
  // A quieter gyro at rest: the turn while standing is 0.225 rad within 4 x 0.0003 sqrt(225).
  config.hold_heading_sigma_rad = 0.0003;
  const roam::sim::SimRun quiet = roam::sim::simulate(config);
  double quiet_turn_rad = 0.0;
  for (int k = 0; k < kHoldSteps; ++k) quiet_turn_rad += quiet.odometry[k].delta_heading_rad;
  EXPECT_NEAR(quiet_turn_rad, 0.225, 0.018);
  config.hold_heading_sigma_rad = -1.0;
  // hold 0 is the run without it.
  config.hold_s = 0.0;
  const roam::sim::SimRun again = roam::sim::simulate(config);
  ASSERT_EQ(again.ground_truth.size(), moving.ground_truth.size());
  for (size_t k = 0; k < moving.ground_truth.size(); ++k) EXPECT_EQ(again.ground_truth[k].x_m, moving.ground_truth[k].x_m);
}

TEST(SimHold, RejectsNegativeOrNonFinite) {
  roam::sim::SimConfig config = roam::sim::gyroDriftFigure8World(5, 100);
  for (double bad : {-1.0, std::nan(""), static_cast<double>(INFINITY)}) {
    config.hold_s = bad;
    EXPECT_THROW(roam::sim::simulate(config), std::invalid_argument) << bad;
  }
}

}  // namespace
