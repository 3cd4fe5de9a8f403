// Spectral SLAM on runs with two 30 s radio silences and 2 % of the ranges far off (issue 15:
// "2 % outliers with two 30 s gaps"): a short window next to a gap with one outlier among its
// ~8 ranges must keep its robust fit (not fall back to one the outlier drags), and a pose inside
// a silence longer than half the window gets no interpolated range (dead reckoning bridges it).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "gap_fill.hpp"
#include "spectral_slam.hpp"
#include "spectral_test_util.hpp"

namespace roam::spectral {
namespace {

using testing::feed;
using testing::pathErrors;

// roam-sim --seed S --steps 3000 --dt 0.2 --speed 1 --schedule round_robin --range-rate 2
//   --odo-distance-sigma-rel 0.02 --odo-heading-sigma 0.003 --outlier-fraction 0.02
//   --outlier-min 2 --outlier-max 40 --range-gap 150:30 --range-gap 400:30  PATH-OPTIONS
sim::SimConfig gappedWorld(uint64_t seed, sim::PathKind path) {
  sim::SimConfig c = sim::nlos30LawnMowerWorld(seed, 3000);
  c.outlier_fraction = 0.02;
  c.range_gaps = {{150.0, 30.0}, {400.0, 30.0}};
  c.path = path;
  if (path == sim::PathKind::kLoop) {
    c.loop_radius_m = 15.0;
    c.range_sigma_m = 0.4;
  } else if (path == sim::PathKind::kFigureEight) {
    c.loop_radius_m = 12.0;
  }
  return c;
}

double meanError(const sim::SimRun& run, SpectralAnchor anchor, int rank) {
  SpectralConfig config;
  config.anchor = anchor;
  config.rank = rank;
  SpectralSlam slam(config);
  feed(slam, run);
  slam.finish();
  if (!slam.solution()) return -1.0;
  return pathErrors(slam.solution()->trajectory, run.ground_truth).mean_m;
}

// Noise-free: the solved poses are the dead-reckoned arc (1 m steps, 0.05 rad per step) turned by
// 0.3 rad about the origin, with 40 poses in the middle unsolved and their own solved heading
// offsets set to a wrong 0.5 rad (a window-edge heading). Turn, scale 1 and the stretch headings
// agree, so the fill is the turned dead reckoning to rounding; the old one-ended bridge with the
// edge heading put the middle metres off.
TEST(SpectralGaps, FillBetweenSolvedPosesRecoversATurnedPathExactly) {
  constexpr double kTurn_rad = 0.3, kTolerance_m = 1e-9;
  OdometryPath path;
  path.reset(Pose{});
  for (int k = 1; k <= 120; ++k) {
    Odometry odometry;
    odometry.utime = static_cast<int64_t>(k) * 1000000;
    odometry.forward_m = 1.0;
    odometry.delta_heading_rad = 0.05;
    path.append(odometry);
  }
  const int T = path.size();
  const double c = std::cos(kTurn_rad), s = std::sin(kTurn_rad);
  std::vector<bool> solved(T, true);
  std::vector<double> offset_rad(T, kTurn_rad);
  Path out(T);
  for (int k = 0; k < T; ++k) {
    out[k].x_m = c * path.x_m[k] - s * path.y_m[k];
    out[k].y_m = s * path.x_m[k] + c * path.y_m[k];
    out[k].heading_rad = path.heading_rad[k] + kTurn_rad;
  }
  const Path truth = out;
  for (int k = 40; k < 80; ++k) {
    solved[k] = false;
    out[k] = Pose{};
  }
  offset_rad[39] = offset_rad[80] = 0.5;
  fillUnsolvedPoses(path, solved, offset_rad, 30.0, out);
  for (int k = 40; k < 80; ++k) {
    EXPECT_NEAR(out[k].x_m, truth[k].x_m, kTolerance_m) << k;
    EXPECT_NEAR(out[k].y_m, truth[k].y_m, kTolerance_m) << k;
    EXPECT_NEAR(out[k].heading_rad, truth[k].heading_rad, 1e-9) << k;
  }
  // The run's end unsolved: dead reckoning from pose 99 with the stretch's heading (0.3 rad, not
  // the edge pose's 0.5), which is the truth again.
  for (int k = 100; k < T; ++k) solved[k] = false;
  offset_rad[99] = 0.5;
  fillUnsolvedPoses(path, solved, offset_rad, 30.0, out);
  for (int k = 100; k < T; ++k) EXPECT_NEAR(out[k].x_m, truth[k].x_m, kTolerance_m) << k;
}

TEST(SpectralGaps, OutliersNextToRadioSilencesStayOutOfThePath) {
  // Loop, seed 524, surveyed beacons: 1.64 / 1.37 m (rank 4 / 7) before, the fits of the windows
  // beside the first gap dragged by one outlier each (errors of 8-17 m there); measured 0.30 /
  // 0.29 m; 0.28 / 0.28 m with the two-ended gap fill. Dead reckoning 1.99 m.
  const sim::SimRun loop = sim::simulate(gappedWorld(524, sim::PathKind::kLoop));
  for (int rank : {4, 7}) {
    const double mean_m = meanError(loop, SpectralAnchor::kBeacons, rank);
    std::printf("loop seed 524, beacons, rank %d: %.3f m\n", rank, mean_m);
    ASSERT_GE(mean_m, 0.0) << rank;
    EXPECT_LT(mean_m, 0.35) << rank;
  }
  // Loop, seed 521, surveyed beacons: 0.77 / 0.77 m before the two-ended gap fill and the check
  // of the gap's edges (solved poses just after the first gap 4-6 m off, the fill ending on them:
  // 11 m at its far end); measured 0.36 / 0.37 m.
  const sim::SimRun loop521 = sim::simulate(gappedWorld(521, sim::PathKind::kLoop));
  for (int rank : {4, 7}) {
    const double mean_m = meanError(loop521, SpectralAnchor::kBeacons, rank);
    std::printf("loop seed 521, beacons, rank %d: %.3f m\n", rank, mean_m);
    ASSERT_GE(mean_m, 0.0) << rank;
    EXPECT_LT(mean_m, 0.45) << rank;
  }
  // Lawn mower, seed 502, surveyed beacons, rank 7: 0.82 m before this round's gap work, 0.74 m
  // with the gap fill; windows reaching into the second silence with a third of their ranges
  // put the poses before it 4-9 m off. With fuller fits preferred there: measured 0.33 m.
  const sim::SimRun lawn = sim::simulate(gappedWorld(502, sim::PathKind::kLawnMower));
  const double lawn_m = meanError(lawn, SpectralAnchor::kBeacons, 7);
  std::printf("lawn mower seed 502, beacons, rank 7: %.3f m\n", lawn_m);
  ASSERT_GE(lawn_m, 0.0);
  EXPECT_LT(lawn_m, 0.45);
  // Figure-8, seed 514, start pose, rank 7: 1.59 m before; measured 0.68 m, 0.70 m with the gap fill. Dead reckoning 1.44 m.
  const sim::SimRun figure8 = sim::simulate(gappedWorld(514, sim::PathKind::kFigureEight));
  const double start_m = meanError(figure8, SpectralAnchor::kStartPose, 7);
  std::printf("figure-8 seed 514, start pose, rank 7: %.3f m\n", start_m);
  ASSERT_GE(start_m, 0.0);
  EXPECT_LT(start_m, 0.8);
}

}  // namespace
}  // namespace roam::spectral
