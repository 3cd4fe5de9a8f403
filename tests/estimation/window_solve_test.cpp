// The early window solved jointly (roam/estimation/window_solve.hpp): exact recovery of a path
// bent by a heading error and of the map on noise-free ranges.

#include <cmath>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "roam/estimation/window_solve.hpp"

namespace roam {
namespace {

using estimation::solveWindow;
using estimation::WindowProblem;
using estimation::WindowRange;
using estimation::WindowSolution;

TEST(WindowSolve, RecoversABentPathAndTheMapExactly) {
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

  // The null hypothesis: with the path held the solve keeps the nominal (bent) path, whose ranges
  // cost more than the free solve's (the landmarks absorb part of the bend): twice the gain
  // (measured 25.5) passes online EM's gate of 3^2 = 9.
  const WindowSolution held = solveWindow(estimation::withPathHeld(problem));
  ASSERT_TRUE(held.solved);
  double held_moved_m = 0.0;
  for (size_t j = 0; j < truth.size(); ++j)
    held_moved_m = std::max(held_moved_m, (held.path[j].head<2>() - problem.path[j].head<2>()).norm());
  EXPECT_LT(held_moved_m, 1e-4);
  EXPECT_EQ(solution.heading_blocks, 9);  // 225 steps of 0.2 s (0 to 44.8 s): blocks of 5 s
  EXPECT_GT(2.0 * (solution.log_posterior - held.log_posterior), 9.0);
}

}  // namespace
}  // namespace roam
