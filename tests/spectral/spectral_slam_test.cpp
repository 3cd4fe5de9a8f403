// Spectral SLAM core on synthetic runs (roam::sim): exact recovery, circle-layout beacons,
// range scale, sparse UWB-like ranges, repeatability, bad configs.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <set>
#include <stdexcept>
#include <tuple>

#include "spectral_slam.hpp"
#include "spectral_test_util.hpp"

namespace roam::spectral {
namespace {

using testing::feed;
using testing::maxBeaconError;
using testing::pathErrors;

// Noise-free data: every step is algebra in doubles on values ~1e3 m^2, so 1e-6 m leaves
// orders of magnitude for the Gram-matrix eigen-decomposition (condition squared).
constexpr double kExactTolerance_m = 1e-6;
constexpr double kExactHeadingTolerance_rad = 1e-6;
// Sparse synthetic run (sparseWorld) bounds, ~3x the measured values: anchor = beacons mean
// 0.102 m (rank 4 and 7); anchor = start_pose 0.756 m (the frame then inherits the odometry's
// heading error over the alignment stretch: 0.002 rad/step random walk); median heading error
// 0.005-0.027 rad.
constexpr double kSparseBeaconsMeanBound_m = 0.3;
constexpr double kSparseStartPoseMeanBound_m = 2.0;
constexpr double kSparseHeadingBound_rad = 0.08;

// The paper's Fig. 1A: 6 random beacons, 500 steps, every beacon ranged at every step.
sim::SimConfig figure1aWorld() {
  sim::SimConfig c;
  c.seed = 7;
  c.num_steps = 500;
  c.path = sim::PathKind::kRandomWalk;
  c.area_width_m = 30.0;
  c.area_height_m = 30.0;
  c.num_beacons = 6;
  c.schedule = sim::RangeSchedule::kEveryStepAllBeacons;
  return c;
}

class NoiseFreeRecovery : public ::testing::TestWithParam<std::tuple<int, SpectralAnchor>> {};

// Fig. 1A's world with its start at start_m, solved with the test's rank and anchor: the path,
// headings and beacons to rounding, in the world frame, solved in a local frame at origin_m.
void expectExactRecovery(const std::tuple<int, SpectralAnchor>& param, const Eigen::Vector2d& start_m,
                         const Eigen::Vector2d& origin_m) {
  sim::SimConfig world = figure1aWorld();
  world.start.x_m = start_m.x();
  world.start.y_m = start_m.y();
  const sim::SimRun run = sim::simulate(world);
  SpectralConfig config;
  config.rank = std::get<0>(param);
  config.anchor = std::get<1>(param);
  SpectralSlam slam(config);
  feed(slam, run);
  slam.finish();
  Path path;
  ASSERT_TRUE(slam.trajectory(true, &path)) << slam.lastRejection();
  ASSERT_EQ(path.size(), run.ground_truth.size());  // start pose + one per step
  EXPECT_EQ(slam.origin(), origin_m);
  // With ranges at every pose, every pose is solved (no bridging).
  EXPECT_EQ(slam.solution()->solved_poses, static_cast<int>(path.size()));
  const auto errors = pathErrors(path, run.ground_truth);
  EXPECT_LT(errors.max_m, kExactTolerance_m);
  EXPECT_LT(errors.max_heading_rad, kExactHeadingTolerance_rad);
  Map map;
  ASSERT_TRUE(slam.takeMap(&map));
  ASSERT_EQ(map.size(), 6u);
  EXPECT_LT(maxBeaconError(map, run.beacons), kExactTolerance_m);
  // Unbiased ranges: the learned first row of X is one.
  if (config.anchor == SpectralAnchor::kBeacons) {
    EXPECT_NEAR(slam.solution()->state_scale, 1.0, 1e-9);
  }
}

TEST_P(NoiseFreeRecovery, RecoversPathHeadingsAndBeaconsExactly) {
  expectExactRecovery(GetParam(), Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero());
}

// The same world at map-grid coordinates (a UTM easting and northing): the model squares
// positions, so without the local frame the surveyed beacons read as collinear and the start
// pose's solve misfits by metres. Recovery is exact in the world frame, as at the origin.
TEST_P(NoiseFreeRecovery, RecoversExactlyAtMapGridCoordinates) {
  expectExactRecovery(GetParam(), Eigen::Vector2d(412345.6, 4612345.7), Eigen::Vector2d(412000.0, 4612000.0));
}

INSTANTIATE_TEST_SUITE_P(RanksAndAnchors, NoiseFreeRecovery,
                         ::testing::Combine(::testing::Values(4, 7),
                                            ::testing::Values(SpectralAnchor::kBeacons,
                                                              SpectralAnchor::kStartPose)));

// With surveyed beacons and no start pose the local frame is centred on the survey: the path's
// positions come from the beacons alone, exact as at the origin.
// The published map on a loop with 8 beacons (logs/synthetic/loop-8beacons' world, three seeds):
// the metric upgrade's learned beacons divided by a coefficient one beacon's poorly denoised row
// brought near 0 (448 m mean beacon error on seed 102 while the path was 0.08 m). The map is now
// placed from the solved path by the shared multilateration: every beacon within 1 m, at least
// half of them placed (4-5 of 8 here; the rest, seen from the loop over a narrow angle, fail the
// placement's acceptance test and keep their surveyed positions).
TEST(SpectralSlam, EveryPublishedBeaconOnALoopIsPlacedFromTheSolvedPath) {
  for (uint64_t seed : {102u, 202u, 302u}) {
    sim::SimConfig world;
    world.seed = seed;
    world.num_steps = 3000;
    world.path = sim::PathKind::kLoop;
    world.loop_radius_m = 15.0;
    world.num_beacons = 8;
    world.range_rate_hz = 2.0;
    world.range_sigma_m = 0.3;
    world.range_dropout = 0.1;
    const sim::SimRun run = sim::simulate(world);
    for (int rank : {4, 7}) {
      SpectralConfig config;
      config.rank = rank;
      config.anchor = SpectralAnchor::kBeacons;
      SpectralSlam slam(config);
      feed(slam, run);
      slam.finish();
      Map map;
      ASSERT_TRUE(slam.takeMap(&map)) << slam.lastRejection();
      ASSERT_EQ(map.size(), 8u);
      EXPECT_LT(maxBeaconError(map, run.beacons), 1.0) << "seed " << seed << " rank " << rank;
      EXPECT_GE(slam.solution()->placed_beacons, 4) << "seed " << seed << " rank " << rank;
    }
  }
}

TEST(SpectralSlam, SurveyedBeaconsAtMapGridCoordinatesNeedNoStartPose) {
  sim::SimConfig world = figure1aWorld();
  world.start.x_m = 412345.6;
  world.start.y_m = 4612345.7;
  const sim::SimRun run = sim::simulate(world);
  SpectralConfig config;
  config.anchor = SpectralAnchor::kBeacons;
  SpectralSlam slam(config);
  test::FeedOptions options;
  options.with_start = false;
  options.finish = false;
  test::feed(run, slam, options);
  slam.finish();
  Path path;
  ASSERT_TRUE(slam.trajectory(true, &path)) << slam.lastRejection();
  // The path starts at the first odometry's time (that step has no pose before it).
  const Path truth(run.ground_truth.begin() + 1, run.ground_truth.end());
  ASSERT_EQ(path.size(), truth.size());
  EXPECT_EQ(slam.origin(), Eigen::Vector2d(412000.0, 4612000.0));
  EXPECT_LT(pathErrors(path, truth).max_m, kExactTolerance_m);
}

TEST(SpectralSlam, RangeScaleIsOneGlobalStateScale) {
  // Ranges 7 % long: d^2 scales by 1.07^2 = 1.1449, so X = 1.1449 X_true and s must be 1.1449;
  // positions p = -X[1:2]/s are then exact.
  sim::SimConfig c = figure1aWorld();
  c.range_scale = 1.07;
  const sim::SimRun run = sim::simulate(c);
  for (int rank : {4, 7}) {
    SpectralConfig config;
    config.rank = rank;
    SpectralSlam slam(config);
    feed(slam, run);
    slam.finish();
    EXPECT_NEAR(slam.solution()->state_scale, 1.07 * 1.07, 1e-9);
    EXPECT_LT(pathErrors(slam.solution()->trajectory, run.ground_truth).max_m, kExactTolerance_m);
  }
}

TEST(SpectralSlam, BeaconsAtTheCornersOfASquare) {
  // Four beacons on one circle: |m|^2/2 is affine in m, the landmark factor is rank 3, and the
  // plain least-squares upgrade is ill-posed. Fixing X[0] globally must still give exact paths,
  // also with a range scale error (which a per-column division would hide but a free X[0] would
  // turn into a wrong translation).
  sim::SimConfig c = figure1aWorld();
  c.num_beacons = 4;
  c.beacons = {{0, -10.0, -10.0}, {1, 40.0, -10.0}, {2, 40.0, 40.0}, {3, -10.0, 40.0}};
  c.range_scale = 1.07;
  const sim::SimRun run = sim::simulate(c);
  for (int rank : {4, 7}) {
    SpectralConfig config;
    config.rank = rank;
    SpectralSlam slam(config);
    feed(slam, run);
    slam.finish();
    EXPECT_LT(pathErrors(slam.solution()->trajectory, run.ground_truth).max_m, kExactTolerance_m) << rank;
  }
  // Noisy sparse version of the same layout (round robin, 0.1 m range noise).
  c.schedule = sim::RangeSchedule::kRoundRobin;
  c.range_rate_hz = 2.0;
  c.range_sigma_m = 0.1;
  c.num_steps = 1500;
  c.seed = 11;
  const sim::SimRun noisy = sim::simulate(c);
  SpectralConfig config;
  SpectralSlam slam(config);
  feed(slam, noisy);
  slam.finish();
  // Measured 0.042 m mean; an ill-posed upgrade gives metres (the issue: 46 m).
  EXPECT_LT(pathErrors(slam.solution()->trajectory, noisy.ground_truth).mean_m, 0.15);
}

// Sparse UWB-like ranges: one beacon at a time at 2 Hz, 0.1 m range noise, 1 % odometry noise.
sim::SimConfig sparseWorld() {
  sim::SimConfig c;
  c.seed = 3;
  c.num_steps = 2000;
  c.path = sim::PathKind::kLawnMower;
  c.num_beacons = 4;
  c.schedule = sim::RangeSchedule::kRoundRobin;
  c.range_rate_hz = 2.0;
  c.range_sigma_m = 0.1;
  c.odo_distance_sigma_rel = 0.01;
  c.odo_heading_sigma_rad = 0.002;
  return c;
}

TEST(SpectralSlam, SparseRangesAreInterpolated) {
  const sim::SimRun run = sim::simulate(sparseWorld());
  for (SpectralAnchor anchor : {SpectralAnchor::kBeacons, SpectralAnchor::kStartPose}) {
    for (int rank : {4, 7}) {
      SpectralConfig config;
      config.anchor = anchor;
      config.rank = rank;
      SpectralSlam slam(config);
      feed(slam, run);
      slam.finish();
      const auto errors = pathErrors(slam.solution()->trajectory, run.ground_truth);
      // Bounds: ~3x the measured values (see the report), far below dead reckoning.
      EXPECT_LT(errors.mean_m, anchor == SpectralAnchor::kBeacons ? kSparseBeaconsMeanBound_m
                                                                  : kSparseStartPoseMeanBound_m)
          << rank;
      EXPECT_LT(errors.median_heading_rad, kSparseHeadingBound_rad) << rank;
    }
  }
}

TEST(SpectralSlam, RepeatRunsAreBitIdentical) {
  const sim::SimRun run = sim::simulate(sparseWorld());
  Path first, second;
  for (Path* out : {&first, &second}) {
    SpectralSlam slam(SpectralConfig{});
    feed(slam, run);
    slam.finish();
    ASSERT_TRUE(slam.trajectory(true, out));
  }
  ASSERT_EQ(first.size(), second.size());
  for (size_t k = 0; k < first.size(); ++k) {
    EXPECT_EQ(first[k].x_m, second[k].x_m);
    EXPECT_EQ(first[k].y_m, second[k].y_m);
    EXPECT_EQ(first[k].heading_rad, second[k].heading_rad);
  }
}

TEST(SpectralSlam, BatchModeEmitsEveryPoseAtFinish) {
  const sim::SimRun run = sim::simulate(figure1aWorld());
  SpectralSlam slam(SpectralConfig{});
  feed(slam, run);
  EXPECT_TRUE(slam.takePoses().empty());
  slam.finish();
  EXPECT_EQ(slam.takePoses().size(), run.ground_truth.size());
  EXPECT_EQ(slam.state(), EstimatorState::kFinished);
}

TEST(SpectralSlam, RejectsBadConfigWithTheReason) {
  // The core checks a struct with the plugin's own declarations (checkConfig): the error names
  // the key and the broken constraint.
  auto message = [](SpectralConfig c) {
    try {
      SpectralSlam slam(c);
    } catch (const ConfigError& e) {
      return e.key() + " | " + e.what();
    }
    return std::string();
  };
  SpectralConfig c;
  c.rank = 5;
  EXPECT_EQ(message(c), "rank | rank: expected one of 4 | 7, got '5'");
  c = SpectralConfig{};
  c.window_s = 0.0;
  EXPECT_EQ(message(c), "window_s | window_s: expected a value > 0, got '0'");
  c = SpectralConfig{};
  c.mode = static_cast<SpectralMode>(9);
  EXPECT_EQ(message(c), "mode | mode: expected one of batch | online, got '(not a named value)'");
  // From a config file, enums are parsed once into enums.
  Options options(KeyValues{{"anchor", "start_pose"}, {"mode", "online"}});
  addSpectralOptions(options, &c);
  options.parse();
  EXPECT_EQ(c.anchor, SpectralAnchor::kStartPose);
  EXPECT_EQ(c.mode, SpectralMode::kOnline);
  Options bad(KeyValues{{"anchor", "beacon"}});
  addSpectralOptions(bad, &c);
  EXPECT_THROW(bad.parse(), ConfigError);
  // The internal constants are not keys (README, "Internal constants").
  Options internal(KeyValues{{"window_overlap", "0.5"}});
  addSpectralOptions(internal, &c);
  EXPECT_THROW(internal.parse(), ConfigError);
}

TEST(SpectralSlam, AnchorBeaconsWithoutSurveyFailsClearly) {
  const sim::SimRun run = sim::simulate(figure1aWorld());
  SpectralSlam slam(SpectralConfig{});
  feed(slam, run, /*give_beacons=*/false);
  try {
    slam.finish();
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(">= 4 surveyed beacons"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace roam::spectral

namespace roam::spectral {
namespace {

TEST(SpectralSlam, TooFewBeaconsEndsWithoutASolutionAndSaysWhy) {
  // Three beacons cannot fix a rank-4 factorisation (C is N x 4): no solution, no failure.
  sim::SimRun run = sim::simulate(figure1aWorld());
  const std::set<int> first_three{run.beacons[0].id, run.beacons[1].id, run.beacons[2].id};
  std::vector<Range> kept;
  for (const Range& range : run.ranges)
    if (first_three.count(range.beacon_id) > 0) kept.push_back(range);
  ASSERT_LT(kept.size(), run.ranges.size());
  run.ranges = kept;
  SpectralConfig config;
  config.anchor = SpectralAnchor::kStartPose;
  SpectralSlam slam(config);
  feed(slam, run, /*give_beacons=*/false);
  ASSERT_NO_THROW(slam.finish());
  EXPECT_EQ(slam.state(), EstimatorState::kFinished);
  EXPECT_EQ(slam.lastRejection(), "data: spectral: needs ranges to >= 4 beacons, got 3");
  EXPECT_FALSE(slam.solution().has_value());
  Path path;
  EXPECT_FALSE(slam.trajectory(true, &path));
}

}  // namespace
}  // namespace roam::spectral

namespace roam::spectral {
namespace {

TEST(SpectralSlam, APathOnOneCircleCannotFixTheStartPoseUpgradeAndSaysSo) {
  // Poses on a circle |p - c| = r satisfy |p|^2/2 = c.p + (r^2 - |c|^2)/2: the fourth row of X
  // is a combination of the other three, X has rank 3, and the structure of X no longer fixes
  // the metric upgrade (noise-free, so exactly degenerate). anchor = beacons is unaffected.
  sim::SimConfig world = figure1aWorld();
  world.path = sim::PathKind::kLoop;
  const sim::SimRun run = sim::simulate(world);
  SpectralConfig config;
  config.anchor = SpectralAnchor::kStartPose;
  SpectralSlam from_start(config);
  feed(from_start, run);
  ASSERT_NO_THROW(from_start.finish());
  EXPECT_EQ(from_start.state(), EstimatorState::kFinished);
  EXPECT_NE(from_start.lastRejection().find("data: anchor = start_pose: the path does not fix the metric upgrade"),
            std::string::npos)
      << from_start.lastRejection();
  EXPECT_FALSE(from_start.solution().has_value());

  config.anchor = SpectralAnchor::kBeacons;
  SpectralSlam surveyed(config);
  feed(surveyed, run);
  surveyed.finish();
  ASSERT_TRUE(surveyed.solution().has_value());
  EXPECT_LT(pathErrors(surveyed.solution()->trajectory, run.ground_truth).max_m, kExactTolerance_m);
}

}  // namespace
}  // namespace roam::spectral

namespace roam::spectral {
namespace {

TEST(SpectralSlam, RobustInterpolationKeepsOutliersOutOfThePath) {
  // sparseWorld() (4 beacons, 2 Hz round robin, 0.1 m noise) with 5 % and 10 % of the ranges read
  // 5-30 m long (NLOS-like). The robust window fits (least quantile of squares over minimal
  // subsets, then Tukey with the data's own scale) and the trimmed SVD keep them out; the paper's
  // plain least squares lets each bend its window's model, and then the self-check refuses the
  // run (no solution, the reason in STATUS) or the answer is far off.
  for (double fraction : {0.0, 0.05, 0.1}) {
    sim::SimConfig world = sparseWorld();
    world.outlier_fraction = fraction;
    world.outlier_min_m = 5.0;
    world.outlier_max_m = 30.0;
    const sim::SimRun run = sim::simulate(world);
    double mean_m[2] = {-1.0, -1.0};  // -1: no solution
    for (bool robust : {true, false}) {
      SpectralConfig config;
      config.robust_interpolation = robust;
      config.drop_range_jumps = false;  // the window fits alone
      SpectralSlam slam(config);
      feed(slam, run);
      slam.finish();
      if (slam.solution())
        mean_m[robust ? 0 : 1] = pathErrors(slam.solution()->trajectory, run.ground_truth).mean_m;
    }
    std::printf("outliers %.0f %%: robust %.3f m, plain least squares %.3f m mean error (-1: none)\n",
                100 * fraction, mean_m[0], mean_m[1]);
    ASSERT_GE(mean_m[0], 0.0) << fraction;
    if (fraction == 0.0) {
      EXPECT_LT(mean_m[0], 1.1 * mean_m[1]);  // clean data: as good as least squares
      EXPECT_LT(mean_m[0], kSparseBeaconsMeanBound_m);
    } else {
      // Measured 0.235 m (5 %) and 1.79 m (10 %); bounds ~1.5x.
      EXPECT_LT(mean_m[0], fraction < 0.07 ? 0.35 : 2.7) << fraction;
      EXPECT_TRUE(mean_m[1] < 0.0 || mean_m[1] > 4.0 * mean_m[0]) << fraction;
    }
  }
}

}  // namespace
}  // namespace roam::spectral
