// Spectral SLAM on runs with two 30 s radio silences and 2 % of the ranges far off (issue 15:
// "2 % outliers with two 30 s gaps"): a short window next to a gap with one outlier among its
// ~8 ranges must keep its robust fit (not fall back to one the outlier drags), and a pose inside
// a silence longer than half the window gets no interpolated range (dead reckoning bridges it).
#include <gtest/gtest.h>

#include <cstdio>

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

TEST(SpectralGaps, OutliersNextToRadioSilencesStayOutOfThePath) {
  // Loop, seed 524, surveyed beacons: 1.64 / 1.37 m (rank 4 / 7) before, the fits of the windows
  // beside the first gap dragged by one outlier each (errors of 8-17 m there); measured 0.30 /
  // 0.29 m. Dead reckoning 1.99 m.
  const sim::SimRun loop = sim::simulate(gappedWorld(524, sim::PathKind::kLoop));
  for (int rank : {4, 7}) {
    const double mean_m = meanError(loop, SpectralAnchor::kBeacons, rank);
    std::printf("loop seed 524, beacons, rank %d: %.3f m\n", rank, mean_m);
    ASSERT_GE(mean_m, 0.0) << rank;
    EXPECT_LT(mean_m, 0.5) << rank;
  }
  // Figure-8, seed 514, start pose, rank 7: 1.59 m before; measured 0.68 m. Dead reckoning 1.44 m.
  const sim::SimRun figure8 = sim::simulate(gappedWorld(514, sim::PathKind::kFigureEight));
  const double start_m = meanError(figure8, SpectralAnchor::kStartPose, 7);
  std::printf("figure-8 seed 514, start pose, rank 7: %.3f m\n", start_m);
  ASSERT_GE(start_m, 0.0);
  EXPECT_LT(start_m, 1.0);
}

}  // namespace
}  // namespace roam::spectral
