// roam-sim's racetrack path (--path racetrack): straights of --area-width joined by half circles
// of --loop-radius, always turning left, so the vehicle comes back to its start after each lap.
#include <gtest/gtest.h>

#include <cmath>

#include "sim.hpp"

namespace {

TEST(SimRacetrack, EachLapIsTwoStraightsAndTwoHalfCirclesBackToTheStart) {
  roam::sim::SimConfig config;
  config.path = roam::sim::PathKind::kRacetrack;
  config.dt_s = 0.2;
  config.speed_mps = 1.0;
  config.area_width_m = 40.0;
  config.loop_radius_m = 12.0;
  // One lap: 2 x 200 straight steps of 0.2 m, 2 x round(pi 12 / 0.2) = 2 x 188 turn steps.
  constexpr int kLapSteps = 2 * 200 + 2 * 188;
  config.num_steps = 2 * kLapSteps;
  const roam::sim::SimRun run = roam::sim::simulate(config);
  ASSERT_EQ(run.ground_truth.size(), static_cast<size_t>(2 * kLapSteps + 1));
  const roam::Pose& start = run.ground_truth.front();
  // The first straight runs along the start heading, then the path turns left by pi.
  const roam::Pose& straight_end = run.ground_truth[200];
  EXPECT_NEAR(std::hypot(straight_end.x_m - start.x_m, straight_end.y_m - start.y_m), 40.0, 1e-9);
  EXPECT_NEAR(std::remainder(run.ground_truth[388].heading_rad - start.heading_rad - M_PI, 2 * M_PI), 0.0, 1e-9);
  // The far straight is 24 m (two radii) to the left of the first.
  const double left_m = -std::sin(start.heading_rad) * (run.ground_truth[388].x_m - start.x_m) +
                        std::cos(start.heading_rad) * (run.ground_truth[388].y_m - start.y_m);
  EXPECT_NEAR(left_m, 24.0, 0.01);
  // Back at the start, heading as at the start, after each lap.
  for (int lap = 1; lap <= 2; ++lap) {
    const roam::Pose& end = run.ground_truth[lap * kLapSteps];
    EXPECT_NEAR(end.x_m, start.x_m, 1e-6) << lap;
    EXPECT_NEAR(end.y_m, start.y_m, 1e-6) << lap;
    EXPECT_NEAR(std::remainder(end.heading_rad - start.heading_rad, 2 * M_PI), 0.0, 1e-9) << lap;
  }
  EXPECT_EQ(roam::sim::parsePathKind("racetrack"), roam::sim::PathKind::kRacetrack);
}

}  // namespace
