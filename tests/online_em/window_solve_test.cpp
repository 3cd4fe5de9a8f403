// The early window solved jointly (init_window_solve, anchor = start_pose; window_solve.hpp):
// exact recovery of a path bent by a heading error and of the map on noise-free ranges, and
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
#include "window_solve.hpp"

namespace roam {
namespace {

using online_em::addOnlineEmOptions;
using online_em::OnlineEmConfig;
using online_em::OnlineEmSlam;
using online_em::solveWindow;
using online_em::WindowProblem;
using online_em::WindowRange;
using online_em::WindowSolution;
using online_em_test::feed;
using online_em_test::meanError;

TEST(OnlineEmWindowSolve, RecoversABentPathAndTheMapExactly) {
  // Truth: two 20 m lanes 5 m apart, 0.2 m steps, 0.2 s apart; three landmarks off the path.
  std::vector<Eigen::Vector3d> truth{{0.0, 0.0, 0.0}};
  for (int j = 0; j < 100; ++j) truth.push_back(truth.back() + Eigen::Vector3d(0.2, 0.0, 0.0));
  for (int j = 0; j < 25; ++j) truth.push_back(truth.back() + Eigen::Vector3d(0.0, 0.2, 0.0));
  for (int j = 0; j < 100; ++j) truth.push_back(truth.back() + Eigen::Vector3d(-0.2, 0.0, 0.0));
  const std::vector<Eigen::Vector2d> landmarks{{10.0, -8.0}, {25.0, 12.0}, {-6.0, 9.0}};
  // The nominal path: the truth's increments turned by a heading error 0.04 rad from 5 s on and
  // 0.09 rad from 10 s on (whole blocks of 5 s); a loose heading prior (0.1 rad per step) so that
  // the ranges decide (with 0.01 rad per step the MAP keeps a quarter of the error: 0.2 m, the
  // landmarks absorbing part of the bend).
  WindowProblem problem;
  problem.path = {truth[0]};
  for (size_t j = 0; j + 1 < truth.size(); ++j) {
    const double t_s = 0.2 * static_cast<double>(j);
    const double error_rad = t_s >= 10.0 ? 0.09 : (t_s >= 5.0 ? 0.04 : 0.0);
    const Eigen::Vector2d d = Eigen::Rotation2Dd(error_rad) * (truth[j + 1] - truth[j]).head<2>();
    problem.path.push_back(problem.path.back() + Eigen::Vector3d(d.x(), d.y(), 0.0));
    problem.heading_variance_rad2.push_back(1e-2);
  }
  for (size_t j = 0; j < truth.size(); ++j) problem.time_s.push_back(0.2 * static_cast<double>(j));
  for (int j = 0; j + 1 < static_cast<int>(truth.size()); j += 2)
    for (int i = 0; i < 3; ++i) {
      WindowRange r;
      r.landmark = i;
      r.step = j;
      r.fraction = 0.5;
      r.range_m = 1.05 * (landmarks[i] - 0.5 * (truth[j] + truth[j + 1]).head<2>()).norm();  // 5 % long
      r.sigma_m = 0.3;
      problem.ranges.push_back(r);
    }
  for (const Eigen::Vector2d& m : landmarks) problem.landmarks_m.push_back(m + Eigen::Vector2d(1.5, -1.0));
  problem.range_scale_prior_sigma = 0.1;
  problem.iterations = 20;
  problem.weight = [](const WindowRange& r, double e_m, double* log_likelihood) {
    *log_likelihood = -0.5 * e_m * e_m / (r.sigma_m * r.sigma_m);
    return 1.0 / (r.sigma_m * r.sigma_m);
  };
  const WindowSolution solution = solveWindow(problem);
  ASSERT_TRUE(solution.solved);
  double worst_path_m = 0.0, worst_map_m = 0.0;
  for (size_t j = 0; j < truth.size(); ++j)
    worst_path_m = std::max(worst_path_m, (solution.path[j].head<2>() - truth[j].head<2>()).norm());
  for (int i = 0; i < 3; ++i) worst_map_m = std::max(worst_map_m, (solution.landmarks_m[i] - landmarks[i]).norm());
  std::printf("noise-free window: path %.2e m, map %.2e m, range scale %.6f\n", worst_path_m, worst_map_m,
              solution.range_scale);
  // Exact data: only the priors' pull remains (measured: path 3.1 mm, map 5.1 mm, scale 1.04987).
  EXPECT_LT(worst_path_m, 0.02);
  EXPECT_LT(worst_map_m, 0.02);
  EXPECT_NEAR(solution.range_scale, 1.05, 1e-3);
}

struct StartRun {
  double mean_m, applied, gain;
  Path path;
};

StartRun run(const Dataset& data, bool window_solve) {
  OnlineEmConfig config;
  setOptions(&config, addOnlineEmOptions,
             {{"anchor", "start_pose"}, {"init_window_solve", window_solve ? "true" : "false"}});
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
