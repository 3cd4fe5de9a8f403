// A standing start with a drifting gyro (roam-sim --hold-s): the vehicle stands still 45 s
// (Plaza 1 does) while the heading odometry turns by the bias, b x 45 s, then drives.
//  - surveyed beacons: without the standing rule (stationary_speed_mps; the shared standstill
//    rule: standing still turns by 0) the cloud starts to move b x 45 s off in heading with only
//    the per-step noise's spread, and the filter loses the path until the bias is learned;
//  - start pose: the frame correction's gate counts the window's heading noise under the wheel
//    model (per metre and per turn), not a per-step sigma over the ~225 standing steps that
//    hid a 0.002 rad/s bias's 0.09 rad turn (no correction, no calibrated re-run).
#include <cmath>
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "feed.hpp"
#include "online_em_slam.hpp"
#include "roam/options.hpp"
#include "sim.hpp"

namespace roam {
namespace {

using online_em_test::feed;
using online_em_test::meanError;
using online_em::addOnlineEmOptions;
using online_em::OnlineEmConfig;
using online_em::OnlineEmSlam;

sim::SimConfig standingStart(sim::SimConfig c, double bias_rad_s) {
  c.hold_s = 45.0;
  c.hold_heading_sigma_rad = 0.0003;  // a gyro at rest: its bias and a small angle random walk
  c.odo_heading_bias_radps = bias_rad_s;
  return c;
}

struct StandingResult {
  double mean_m, bias_rad_s;
};

StandingResult runStanding(const Dataset& data, const std::string& anchor, double stationary_speed_mps = OnlineEmConfig{}.stationary_speed_mps) {
  OnlineEmConfig config;
  setOptions(&config, addOnlineEmOptions, {{"anchor", anchor}});
  config.stationary_speed_mps = stationary_speed_mps;  // an internal constant
  OnlineEmSlam slam(config);
  feed(data, slam);
  return {meanError(slam.filteredPath(), data.ground_truth), slam.odometryCalibration().heading_rate_bias_rad_s};
}

TEST(OnlineEmStandingStart, BeaconsWithAFastDriftingGyro) {
  const Dataset data = sim::simulate(standingStart(sim::nlos30LawnMowerWorld(52, 1500), 0.01));
  // Measured: standing rule 0.212 m (b 0.01088), without it 9.74 m.
  const StandingResult standing = runStanding(data, "beacons");
  const StandingResult without_rule = runStanding(data, "beacons", 0.0);
  std::printf("standing start, 30 %% NLOS, b 0.01, beacons: standing rule %.3f m (b %.5f); without it %.3f m (b %.5f)\n",
              standing.mean_m, standing.bias_rad_s, without_rule.mean_m, without_rule.bias_rad_s);
  EXPECT_LT(standing.mean_m, 0.5);  // issue 15's target for online EM, beacons
  EXPECT_NEAR(standing.bias_rad_s, 0.01, 0.002);
  EXPECT_GT(without_rule.mean_m, 4.0 * standing.mean_m);
}

TEST(OnlineEmStandingStart, StartPoseWithASlowDriftingGyro) {
  // Four seeds in a row, 0.002 rad/s: the bias turns the heading 0.09 rad before the first metre.
  // Measured, seeds 53-56: 0.34, 0.48, 0.55, 0.40 m (mean 0.44; 1.31, 0.55, 0.78, 0.24 before the
  // standing rule); with the per-step gate
  // (2 x 0.005 rad x sqrt(window steps)) 1.45, 1.75, 1.74, 1.67 m (mean 1.65).
  double sum_m = 0.0;
  for (int seed : {53, 54, 55, 56}) {
    const Dataset data = sim::simulate(standingStart(sim::gyroDriftFigure8World(seed, 3000), 0.002));
    const StandingResult start = runStanding(data, "start_pose");
    std::printf("standing start, figure-8, b 0.002, start pose, seed %d: %.3f m (b %.5f)\n", seed, start.mean_m,
                start.bias_rad_s);
    sum_m += start.mean_m;
  }
  EXPECT_LT(sum_m / 4.0, 1.0);
}

}  // namespace
}  // namespace roam
