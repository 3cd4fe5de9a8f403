// The early window solved jointly (init_window_solve, anchor = start_pose; roam/estimation/window_solve.hpp):
// the 30 % NLOS lawn mower from the start pose, where the map multilaterated from the
// dead-reckoned path sets a wrong frame.
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "feed.hpp"
#include "online_em_slam.hpp"
#include "roam/options.hpp"
#include "sim.hpp"

namespace roam {
namespace {

using online_em::addOnlineEmOptions;
using online_em::OnlineEmConfig;
using online_em::OnlineEmSlam;
using online_em_test::feed;
using online_em_test::meanError;

struct StartRun {
  double mean_m, applied, gain;
  Path path;
};

StartRun run(const Dataset& data, bool window_solve) {
  OnlineEmConfig config;
  setOptions(&config, addOnlineEmOptions, {{"anchor", "start_pose"}});
  config.init_window_solve = window_solve;  // an internal constant
  OnlineEmSlam slam(config);
  feed(data, slam);
  const auto& d = slam.diagnostics();
  const auto applied = d.find("window_solve_applied"), gain = d.find("window_solve_gain");
  return {meanError(slam.filteredPath(), data.ground_truth), applied == d.end() ? -1.0 : applied->second,
          gain == d.end() ? -1.0 : gain->second, slam.filteredPath()};
}

TEST(OnlineEmWindowSolve, NlosFromTheStartPoseFixesTheFrame) {
  // Simulation seeds 1-8, start pose, mean error on / off (m): 1.06/0.41, 0.47/0.63, 0.58/1.54,
  // 0.19/0.72, 1.38/1.85, 1.11/0.98, 0.61/0.61 (not applied: gain 3.5), 0.51/0.79. Seed 3: the
  // map multilaterated from a dead-reckoned path gone 0.1 rad off; the window's ranges refute it.
  const Dataset data = sim::simulate(sim::nlos30LawnMowerWorld(3, 3000));
  const StartRun on = run(data, true), off = run(data, false), again = run(data, true);
  std::printf("NLOS 30 %%, start pose, seed 3: window solve %.3f m (gain %.1f), without %.3f m\n", on.mean_m,
              on.gain, off.mean_m);
  EXPECT_EQ(on.applied, 1.0);
  EXPECT_GT(on.gain, 9.0);  // the gate: init_outlier_gate_sigmas^2
  EXPECT_LT(on.mean_m, 0.75);
  EXPECT_GT(off.mean_m, 1.3);
  EXPECT_EQ(off.applied, -1.0);  // off: no solve at all
  // Seeded: bit-identical on a repeat.
  ASSERT_EQ(on.path.size(), again.path.size());
  for (size_t j = 0; j < on.path.size(); ++j) {
    ASSERT_EQ(on.path[j].x_m, again.path[j].x_m);
    ASSERT_EQ(on.path[j].y_m, again.path[j].y_m);
    ASSERT_EQ(on.path[j].heading_rad, again.path[j].heading_rad);
  }
}

}  // namespace
}  // namespace roam
