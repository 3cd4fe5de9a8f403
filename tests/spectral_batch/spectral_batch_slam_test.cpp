// SpectralBatchSlam end to end on seeded synthetic runs: calibration, outliers and the robust
// loss, live re-solves, repeatability, config errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "batch_config.hpp"
#include "feed.hpp"
#include "sim.hpp"
#include "spectral_batch_slam.hpp"
#include "roam/estimation/motion_model.hpp"
#include "spectral_seed.hpp"

namespace roam {
namespace spectral_batch {
namespace {

// A noisy 2-minute lawn mower with 4 beacons, every pose ranged to every beacon.
sim::SimConfig noisyRun(uint64_t seed) {
  sim::SimConfig config;
  config.seed = seed;
  config.num_steps = 600;
  config.area_width_m = 20.0;
  config.area_height_m = 15.0;
  config.schedule = sim::RangeSchedule::kEveryStepAllBeacons;
  config.odo_distance_sigma_rel = 0.01;
  config.odo_heading_sigma_rad = 0.002;
  config.range_sigma_m = 0.05;
  return config;
}

SpectralBatchConfig deadReckoningStart() {
  SpectralBatchConfig config;
  config.init = SpectralBatchConfig::Init::kDeadReckoning;
  config.range_sigma_m = 0.05;  // the simulated noise
  // The simulated start heading is exact: keep it as the rotation gauge (the default aligns the
  // rotation to the first 50 m of odometry, which on this 120 m run with 1 % noise costs ~0.2 m;
  // it is checked on its own in GyroDriftIsCalibrated).
  config.gauge_align_m = 0.0;
  return config;
}

struct Result {
  double mean_error_m;
  double scale;
  double offset_m;
  Path path;
};

Result run(const Dataset& data, const SpectralBatchConfig& config) {
  SpectralBatchSlam slam(config);
  test::feed(data, slam);
  Result result;
  EXPECT_TRUE(slam.trajectory(true, &result.path));
  result.mean_error_m = test::meanError_m(result.path, data.ground_truth);
  result.scale = slam.rangeScale();
  result.offset_m = slam.rangeOffset_m();
  return result;
}

TEST(SpectralBatchSlam, RecoversRangeScale) {
  // Ranges 7 % long (measured = 1.07 true). With calibration on the scale comes back to 1e-3:
  // 2,400 ranges of sigma 0.05 m spread over 5-35 m pin it to ~1e-4; odometry distances (1 %
  // per step, 120 m in all) hold the metric scale of the map.
  constexpr double kScaleTolerance = 1e-3;
  constexpr double kOffsetTolerance_m = 0.05;
  sim::SimConfig sim_config = noisyRun(21);
  sim_config.range_scale = 1.07;
  const Dataset data = sim::simulate(sim_config);
  const Result calibrated = run(data, deadReckoningStart());
  EXPECT_NEAR(calibrated.scale, 1.07, kScaleTolerance);
  EXPECT_NEAR(calibrated.offset_m, 0.0, kOffsetTolerance_m);
  EXPECT_LT(calibrated.mean_error_m, 0.1);

  // Without calibration the 7 % has to go somewhere: the path is visibly worse.
  SpectralBatchConfig uncalibrated_config = deadReckoningStart();
  uncalibrated_config.estimate_range_scale = false;
  uncalibrated_config.estimate_range_offset = false;
  const Result uncalibrated = run(data, uncalibrated_config);
  EXPECT_EQ(uncalibrated.scale, 1.0);
  EXPECT_GT(uncalibrated.mean_error_m, 2.0 * calibrated.mean_error_m);
  std::printf("scale 1.07: calibrated %.4f (offset %.4f m), error %.3f m; uncalibrated %.3f m\n",
              calibrated.scale, calibrated.offset_m, calibrated.mean_error_m, uncalibrated.mean_error_m);
}

TEST(SpectralBatchSlam, RobustLossRejectsOutliers) {
  // 10 % of the ranges replaced by true + U(5, 30) m. Bound: the clean run's error is ~0.03 m;
  // a redescending loss gives the outliers (>= 100 sigma) no weight, so 0.1 m holds with margin.
  // Plain least squares lets them drag the path by metres.
  constexpr double kRobustBound_m = 0.1;
  sim::SimConfig sim_config = noisyRun(22);
  sim_config.outlier_fraction = 0.1;
  const Dataset data = sim::simulate(sim_config);
  double errors_m[4];
  int i = 0;
  for (const char* loss : {"cauchy", "tukey", "huber", "none"}) {
    SpectralBatchConfig config = deadReckoningStart();
    setOptions(&config, addSpectralBatchOptions, {{"loss", loss}});
    config.verbose = getenv("VERBOSE") != nullptr;
    errors_m[i++] = run(data, config).mean_error_m;
  }
  std::printf("outliers: cauchy %.3f m, tukey %.3f m, huber %.3f m, none %.3f m\n", errors_m[0],
              errors_m[1], errors_m[2], errors_m[3]);
  EXPECT_LT(errors_m[0], kRobustBound_m);
  EXPECT_LT(errors_m[1], kRobustBound_m);
  EXPECT_GT(errors_m[3], kRobustBound_m);
}

TEST(SpectralBatchSlam, RepeatRunsAreBitIdentical) {
  const Dataset data = sim::simulate(noisyRun(23));
  const Result first = run(data, deadReckoningStart());
  const Result second = run(data, deadReckoningStart());
  ASSERT_EQ(first.path.size(), second.path.size());
  for (size_t k = 0; k < first.path.size(); ++k) {
    EXPECT_EQ(first.path[k].x_m, second.path[k].x_m);
    EXPECT_EQ(first.path[k].y_m, second.path[k].y_m);
    EXPECT_EQ(first.path[k].heading_rad, second.path[k].heading_rad);
  }
}

TEST(SpectralBatchSlam, PosePerStepAndMapAtFinish) {
  const Dataset data = sim::simulate(noisyRun(24));
  SpectralBatchSlam slam(deadReckoningStart());
  test::feed(data, slam);
  // The start pose plus one per odometry step.
  EXPECT_EQ(slam.takePoses().size(), data.odometry.size() + 1);
  Map map;
  ASSERT_TRUE(slam.takeMap(&map));
  ASSERT_EQ(map.size(), data.beacons.size());
  for (size_t j = 0; j < map.size(); ++j) {
    EXPECT_EQ(map[j].id, data.beacons[j].id);
    EXPECT_NEAR(map[j].x_m, data.beacons[j].x_m, 0.2);
    EXPECT_NEAR(map[j].y_m, data.beacons[j].y_m, 0.2);
  }
  EXPECT_EQ(slam.state(), EstimatorState::kFinished);
  EXPECT_EQ(slam.solves(), 1);
  EXPECT_GT(slam.diagnostics().at("solver_iterations"), 0.0);
  EXPECT_LT(slam.diagnostics().at("solver_final_cost"), slam.diagnostics().at("solver_initial_cost"));
}

TEST(SpectralBatchSlam, LiveModeResolvesWarmStarted) {
  // 120 s of data, a re-solve every 30 s of data time: 4 live solves (at 30, 60, 90, 120 s)
  // plus the final one, each publishing a trajectory; the result matches the batch solve.
  const Dataset data = sim::simulate(noisyRun(25));
  SpectralBatchConfig config = deadReckoningStart();
  config.resolve_interval_s = 30.0;
  SpectralBatchSlam slam(config);
  slam.setInitialPose(data.start);
  size_t r = 0;
  int trajectories = 0;
  size_t steps = 0;
  for (const Odometry& odometry : data.odometry) {
    while (r < data.ranges.size() && data.ranges[r].utime < odometry.utime) slam.addRange(data.ranges[r++]);
    slam.addOdometry(odometry);
    ++steps;
    Path path;
    if (slam.trajectory(false, &path)) {
      ++trajectories;
      EXPECT_EQ(path.size(), steps + 1);  // every pose so far
    }
  }
  while (r < data.ranges.size()) slam.addRange(data.ranges[r++]);
  slam.finish();
  EXPECT_EQ(trajectories, 4);
  EXPECT_EQ(slam.solves(), 5);
  Path live;
  ASSERT_TRUE(slam.trajectory(true, &live));
  const Result batch = run(data, deadReckoningStart());
  EXPECT_NEAR(test::meanError_m(live, data.ground_truth), batch.mean_error_m, 0.01);
}

// Setting key = value fails with a ConfigError naming the key, with this message.
void expectBadValue(const char* key, const char* value, const char* message) {
  SpectralBatchConfig config;
  try {
    setOptions(&config, addSpectralBatchOptions, {{key, value}});
    FAIL() << "expected an error for " << key << " = " << value;
  } catch (const ConfigError& error) {
    EXPECT_EQ(error.key(), key);
    EXPECT_STREQ(error.what(), message);
  }
}

TEST(SpectralBatchSlam, BadConfigNamesTheKey) {
  expectBadValue("loss", "welsch", "expected one of huber | cauchy | tukey | none, got 'welsch'");
  expectBadValue("gauge", "free", "expected one of window | pinned, got 'free'");
  expectBadValue("range_scale_sigma", "-1", "expected a value >= 0, got '-1'");
  // A core built from a struct meets the same declared checks, naming the key.
  SpectralBatchConfig config;
  config.range_sigma_m = 0.0;
  try {
    SpectralBatchSlam slam{config};
    FAIL() << "expected an error";
  } catch (const ConfigError& error) {
    EXPECT_EQ(error.key(), "range_sigma_m");
    EXPECT_STREQ(error.what(), "range_sigma_m: expected a value > 0, got '0'");
  }

  Options unknown(KeyValues{{"rangesigma_m", "0.3"}});
  addSpectralBatchOptions(unknown, &config);
  try {
    unknown.parse();
    FAIL() << "expected an error";
  } catch (const ConfigError& error) {
    EXPECT_EQ(error.key(), "rangesigma_m");
    EXPECT_NE(std::string(error.what()).find("range_sigma_m"), std::string::npos) << error.what();
  }
  Options bad_solver(KeyValues{{"linear_solver", "magic"}});
  addSpectralBatchOptions(bad_solver, &config);
  EXPECT_THROW(bad_solver.parse(), ConfigError);
}

TEST(SpectralBatchSlam, SpectralInitNeedsTheSpectralCore) {
  SpectralBatchConfig config;
  config.init = SpectralBatchConfig::Init::kSpectral;
  if (spectral_batch::spectralSeedAvailable()) {
    EXPECT_NO_THROW(SpectralBatchSlam{config});
  } else {
    EXPECT_THROW(SpectralBatchSlam{config}, std::invalid_argument);
  }
}

}  // namespace
}  // namespace spectral_batch
}  // namespace roam

namespace roam {
namespace spectral_batch {
namespace {

// Mean error of the dead reckoning of a run's own odometry from its start pose.
double deadReckoningError_m(const Dataset& data) {
  Path path;
  Pose pose = data.ground_truth.front();
  path.push_back(pose);
  for (const Odometry& odometry : data.odometry) path.push_back(pose = estimation::step(pose, odometry));
  return test::meanError_m(path, data.ground_truth);
}

TEST(SpectralBatchSlam, GyroDriftIsCalibrated) {
  // A figure-8 with a MEMS gyro bias of 0.01 rad/s (0.57 deg/s): 400 s of it turns dead reckoning
  // by 4 rad. The heading-rate bias comes back to ~1e-4 rad/s and the path to decimetres; without
  // the calibration the batch solve is metres off.
  sim::SimConfig sim_config;
  sim_config.seed = 301;
  sim_config.num_steps = 2000;
  sim_config.path = sim::PathKind::kFigureEight;
  sim_config.loop_radius_m = 8.0;
  sim_config.num_beacons = 6;
  sim_config.schedule = sim::RangeSchedule::kRoundRobin;
  sim_config.range_sigma_m = 0.3;
  sim_config.odo_distance_sigma_rel = 0.02;
  sim_config.odo_heading_sigma_rad = 0.003;
  sim_config.odo_heading_bias_radps = 0.01;
  const Dataset data = sim::simulate(sim_config);
  SpectralBatchConfig config;
  config.init = SpectralBatchConfig::Init::kDeadReckoning;
  SpectralBatchSlam slam(config);
  test::feed(data, slam);
  Path path;
  ASSERT_TRUE(slam.trajectory(true, &path));
  const double error_m = test::meanError_m(path, data.ground_truth);
  const double bias = slam.odometryCalibration().heading_rate_bias_rad_s;
  config.estimate_odometry_calibration = false;
  SpectralBatchSlam plain(config);
  test::feed(data, plain);
  ASSERT_TRUE(plain.trajectory(true, &path));
  const double plain_error_m = test::meanError_m(path, data.ground_truth);
  std::printf("gyro drift: bias %.5f rad/s, error %.3f m; uncalibrated %.3f m; dead reckoning %.3f m\n", bias,
              error_m, plain_error_m, deadReckoningError_m(data));
  EXPECT_NEAR(bias, 0.01, 1e-3);
  EXPECT_LT(error_m, 0.7);
  EXPECT_GT(plain_error_m, error_m);
}

TEST(SpectralBatchSlam, GyroDriftFigure8FromTheStartPose) {
  // The held-out kind (issue 15): the development drifting-gyro figure-8 (20 min, 0.01 rad/s of gyro
  // bias), anchor = start_pose, default keys. Measured on seeds 201-203 of roam-sim's command:
  // 0.261 / 0.107 / 0.121 m (201-206 in the README: 0.10-0.27, mean 0.185). What is left is the
  // frame about the start (rotation and offset set by the first tens of metres), not the shape: a
  // similarity fit leaves ~0.08 m. Bounds: every seed within 0.3 m, the mean within 0.2 m.
  double sum_m = 0.0;
  for (const uint64_t seed : {201u, 202u, 203u}) {
    const Dataset data = sim::simulate(sim::gyroDriftFigure8World(seed, 6000));
    SpectralBatchConfig config;
    config.init = SpectralBatchConfig::Init::kDeadReckoning;
    SpectralBatchSlam slam(config);
    test::feed(data, slam);
    Path path;
    ASSERT_TRUE(slam.trajectory(true, &path));
    const double error_m = test::meanError_m(path, data.ground_truth);
    std::printf("figure-8 seed %u: %.3f m, bias %.5f rad/s\n", static_cast<unsigned>(seed), error_m,
                slam.odometryCalibration().heading_rate_bias_rad_s);
    EXPECT_LT(error_m, 0.3);
    sum_m += error_m;
  }
  EXPECT_LT(sum_m / 3.0, 0.2);
}

// The rotation about the start (rad) that best maps the first n poses of path onto truth (least
// squares over the displacements from pose 0).
double rotationAboutStart_rad(const Path& path, const Path& truth, size_t n) {
  double dot = 0.0, cross = 0.0;
  for (size_t k = 1; k < n && k < path.size(); ++k) {
    const double px = path[k].x_m - path[0].x_m, py = path[k].y_m - path[0].y_m;
    const double qx = truth[k].x_m - truth[0].x_m, qy = truth[k].y_m - truth[0].y_m;
    dot += px * qx + py * qy;
    cross += px * qy - py * qx;
  }
  return std::atan2(cross, dot);
}

TEST(SpectralBatchSlam, StartPoseGaugeIsTheOnlyDifference) {
  // Round 7 (README): from the start pose on the drifting-gyro figure-8 the window gauge inherits
  // dead reckoning's own heading walk over its first 50 m, even with the true gyro bias: seed 303
  // of the sweep's drift8 kind (the same run), window 0.665 m, rotated -43 mrad about the start,
  // against -40 mrad for the truly calibrated dead reckoning's first 50 m. The joint optimum with
  // the start heading held (gauge = pinned) is the same shape (0.063 m after a rigid fit) turned
  // by 21 mrad: 0.348 m. Bounds: the shapes agree within 5 mm, the window's rotation within
  // 10 mrad of dead reckoning's, pinned at least 0.2 m better.
  const Dataset data = sim::simulate(sim::gyroDriftFigure8World(303, 6000));
  Path dead_reckoning{data.ground_truth.front()};
  double travelled_m = 0.0;
  size_t window = 0;
  for (Odometry odometry : data.odometry) {
    odometry.delta_heading_rad -= 0.01 * 0.2;  // the simulated bias over one 0.2 s step
    dead_reckoning.push_back(estimation::step(dead_reckoning.back(), odometry));
    travelled_m += std::hypot(odometry.forward_m, odometry.lateral_m);
    if (travelled_m <= 50.0) window = dead_reckoning.size();
  }
  const double dead_reckoning_rad = rotationAboutStart_rad(dead_reckoning, data.ground_truth, window);
  double error_m[2], shape_m[2], rotation_rad[2];
  for (int pinned = 0; pinned < 2; ++pinned) {
    SpectralBatchConfig config;
    config.init = SpectralBatchConfig::Init::kDeadReckoning;
    if (pinned) config.gauge = SpectralBatchConfig::Gauge::kPinned;
    SpectralBatchSlam slam(config);
    test::feed(data, slam);
    Path path;
    ASSERT_TRUE(slam.trajectory(true, &path));
    error_m[pinned] = test::meanError_m(path, data.ground_truth);
    shape_m[pinned] = test::rigidAlignedError_m(path, data.ground_truth);
    rotation_rad[pinned] = rotationAboutStart_rad(path, data.ground_truth, path.size());
  }
  std::printf("figure-8 seed 303: window %.3f m (shape %.3f, rotation %+.4f rad; dead reckoning's 50 m %+.4f), "
              "pinned %.3f m (shape %.3f, rotation %+.4f)\n",
              error_m[0], shape_m[0], rotation_rad[0], dead_reckoning_rad, error_m[1], shape_m[1], rotation_rad[1]);
  EXPECT_LT(shape_m[0], 0.1);
  EXPECT_NEAR(shape_m[0], shape_m[1], 0.005);
  EXPECT_NEAR(rotation_rad[0], dead_reckoning_rad, 0.01);
  EXPECT_LT(std::abs(rotation_rad[1]), std::abs(rotation_rad[0]));
  EXPECT_LT(error_m[1], error_m[0] - 0.2);
}

TEST(SpectralBatchSlam, HeavyOutliersInBothAnchors) {
  // 30 % of the ranges non-line-of-sight, 2-40 m long.
  const Dataset data = sim::simulate(sim::nlos30LawnMowerWorld(302, 1500));
  for (const char* anchor : {"start_pose", "beacons"}) {
    SpectralBatchConfig config;
    config.init = SpectralBatchConfig::Init::kDeadReckoning;
    setOptions(&config, addSpectralBatchOptions, {{"anchor", anchor}});
    SpectralBatchSlam slam(config);
    test::feed(data, slam);
    Path path;
    ASSERT_TRUE(slam.trajectory(true, &path));
    const double error_m = test::meanError_m(path, data.ground_truth);
    std::printf("30 %% NLOS, anchor %s: %.3f m (dead reckoning %.3f m)\n", anchor, error_m,
                deadReckoningError_m(data));
    EXPECT_LT(error_m, std::string(anchor) == "beacons" ? 0.3 : 1.0);
  }
}

TEST(SpectralBatchSlam, OneSidedNlosKeepsTheShape) {
  // 30 % NLOS ranges, all long (true + 2..40 m), 10 minutes (the held-out kind of issue 15),
  // anchor = start_pose, default keys. The default loss (cauchy) gives the gross outliers no
  // pull; huber's constant pull at its scale drags beacons and the path's edge towards the long
  // side. Measured on seed 301 (roam-sim's nlos command, seed 301): shape error after a rigid fit
  // 0.10 m with cauchy against 0.21 m with huber, full path 1.02 against 2.12 m (huber bent the
  // first lane by 2 m).
  const Dataset data = sim::simulate(sim::nlos30LawnMowerWorld(301, 3000));
  double shape_m[2] = {0.0, 0.0}, full_m[2] = {0.0, 0.0};
  for (int i = 0; i < 2; ++i) {
    SpectralBatchConfig config;
    config.init = SpectralBatchConfig::Init::kDeadReckoning;
    if (i == 1) config.loss = SpectralBatchConfig::Loss::kHuber;
    SpectralBatchSlam slam(config);
    test::feed(data, slam);
    Path path;
    ASSERT_TRUE(slam.trajectory(true, &path));
    shape_m[i] = test::rigidAlignedError_m(path, data.ground_truth);
    full_m[i] = test::meanError_m(path, data.ground_truth);
  }
  std::printf("30 %% NLOS seed 301, start pose: cauchy shape %.3f m full %.3f m; huber shape %.3f m full %.3f m\n",
              shape_m[0], full_m[0], shape_m[1], full_m[1]);
  EXPECT_LT(shape_m[0], 0.13);
  EXPECT_LT(full_m[0], 1.15);
  EXPECT_GT(shape_m[1], 1.5 * shape_m[0]);  // the mechanism: huber's pull is what bent it
}

TEST(SpectralBatchSlam, AnAnnealedSolveThatFitsAnNlosStretchLosesToTheFinalScaleAlone) {
  // NLOS in stretches (the seed sweep's nlos30-episodes, seed 311), surveyed beacons, started
  // from dead reckoning (4 m off). The annealing's wide first stage let ranges that agree with
  // each other, but not with the rest, bend 80 s of the path up to 7 m off, and the narrow stages
  // kept that basin. The same start solved at the final scale alone ends at a lower cost (the
  // same objective) and is kept (loss_anneal_check).
  sim::SimConfig world = sim::nlos30LawnMowerWorld(311, 3000);
  world.outlier_episode_s = 20.0;
  const Dataset data = sim::simulate(world);
  double error_m[2] = {0.0, 0.0}, cost[2] = {0.0, 0.0}, kept[2] = {0.0, 0.0};
  for (int i = 0; i < 2; ++i) {
    SpectralBatchConfig config;
    config.init = SpectralBatchConfig::Init::kDeadReckoning;
    config.anchor = SpectralBatchConfig::Anchor::kBeacons;
    config.loss_anneal_check = i == 1;
    SpectralBatchSlam slam(config);
    test::feed(data, slam);
    Path path;
    ASSERT_TRUE(slam.trajectory(true, &path));
    error_m[i] = test::meanError_m(path, data.ground_truth);
    cost[i] = slam.diagnostics().at("solver_final_cost");
    kept[i] = slam.diagnostics().at("solver_final_scale_kept");
  }
  std::printf("NLOS in stretches, seed 311, beacons: annealed %.3f m (cost %.1f), checked %.3f m (cost %.1f)\n",
              error_m[0], cost[0], error_m[1], cost[1]);
  EXPECT_GT(error_m[0], 0.4);  // the failure it is for: the test can fail
  EXPECT_LT(error_m[1], 0.2);
  EXPECT_LT(cost[1], cost[0]);
  EXPECT_EQ(kept[0], 0.0);
  EXPECT_EQ(kept[1], 1.0);
}

TEST(SpectralBatchSlam, SparseAuvLikeRunBothAnchors) {
  // Steps of 4.5 m every 3 s, one range every ~3 s to beacons 200 m out, 45 % of them off by
  // -150..100 m, stated sigma 0.75 m for 2 m of noise, odometry 15 % noisy and 3 % short.
  const Dataset data = sim::simulate(sim::auvLikeWorld(303, 300));
  const double dead_reckoning_m = deadReckoningError_m(data);
  for (const char* anchor : {"start_pose", "beacons"}) {
    for (bool fallback : {true, false}) {
      SpectralBatchConfig config;
      config.init = SpectralBatchConfig::Init::kDeadReckoning;
      setOptions(&config, addSpectralBatchOptions, {{"anchor", anchor}});
      config.fallback_deadreckoning = fallback;
      SpectralBatchSlam slam(config);
      if (std::string(anchor) == "start_pose" && !fallback) {
        // With the start pose as the only anchor the solve explains under half the ranges (a
        // wrong basin cannot be told apart): without the fallback the estimator must refuse.
        EXPECT_THROW(test::feed(data, slam), std::runtime_error);
        EXPECT_EQ(slam.state(), EstimatorState::kFailed);
        continue;
      }
      if (std::string(anchor) == "beacons" && !fallback) continue;
      test::feed(data, slam);
      EXPECT_EQ(slam.state(), EstimatorState::kFinished);
      Path path;
      ASSERT_TRUE(slam.trajectory(true, &path));
      const double error_m = test::meanError_m(path, data.ground_truth);
      std::printf("AUV-like, anchor %s: %.3f m (dead reckoning %.3f m)\n", anchor, error_m, dead_reckoning_m);
      if (std::string(anchor) == "beacons") {
        EXPECT_LT(error_m, 0.5 * dead_reckoning_m);
      } else {
        // The refused solve is replaced by dead reckoning itself, flagged in STATUS.
        EXPECT_EQ(slam.diagnostics().at("dead_reckoning_fallback"), 1.0);
        EXPECT_NEAR(error_m, dead_reckoning_m, 1e-6 * dead_reckoning_m);
      }
    }
  }
}

TEST(SpectralBatchSlam, SparseRangesFromTheStartPoseTakeTheHeadingAsStated) {
  // A GOATS-like AUV (7 s steps of 5 m, four beacons up to 500 m out, exact heading, 20 %
  // translation noise) with 30 % of its ranges outliers, odometry stating GOATS 16's covariance
  // (0.02 m, 0.002 rad per edge). From the start pose the wheel model's heading noise (0.022 rad
  // per step) lets the solve bend the first lane and carry the beacons with it; with the heading
  // as stated it follows the odometry's heading and the ranges place the rest.
  sim::SimConfig sim_config = sim::goatsLikeWorld(2012, 210);  // GOATS 16's stated covariance
  sim_config.outlier_fraction = 0.3;
  const Dataset data = sim::simulate(sim_config);
  const double dead_reckoning_m = deadReckoningError_m(data);
  double error_m[2];
  for (bool as_stated : {false, true}) {
    SpectralBatchConfig config;
    config.init = SpectralBatchConfig::Init::kDeadReckoning;
    config.sparse_heading_as_stated = as_stated;
    SpectralBatchSlam slam(config);
    test::feed(data, slam);
    Path path;
    ASSERT_TRUE(slam.trajectory(true, &path));
    error_m[as_stated] = test::meanError_m(path, data.ground_truth);
    EXPECT_EQ(slam.diagnostics().count("dead_reckoning_fallback") ? slam.diagnostics().at("dead_reckoning_fallback") : 0.0, 0.0);
    if (as_stated) {
      EXPECT_EQ(slam.diagnostics().at("heading_as_stated"), 1.0);
      EXPECT_EQ(slam.odometryCalibration().heading_rate_bias_rad_s, 0.0);
      const auto note = slam.diagnostics().lower_bound("note: took each odometry step's stated heading noise and held");
      ASSERT_NE(note, slam.diagnostics().end());
      EXPECT_NE(note->first.find("heading_rate_bias_max_drift_rad"), std::string::npos) << note->first;
    }
    std::printf("GOATS-like, 30 %% outliers, heading as stated %d: %.2f m (dead reckoning %.2f m)\n", as_stated,
                error_m[as_stated], dead_reckoning_m);
  }
  EXPECT_GT(error_m[0], 1.25 * dead_reckoning_m);  // the failure this rule is for
  EXPECT_LT(error_m[1], 0.8 * dead_reckoning_m);

  // At UWB rates the rule finds the ranges dense: a stated covariance changes nothing, bit for bit.
  sim::SimConfig dense_config = sim::gyroDriftFigure8World(201, 1500);
  dense_config.odo_sigma_reported_m = 0.001;
  dense_config.odo_heading_sigma_reported_rad = 0.0001;
  const Dataset dense = sim::simulate(dense_config);
  Path paths[2];
  for (bool as_stated : {false, true}) {
    SpectralBatchConfig config;
    config.init = SpectralBatchConfig::Init::kDeadReckoning;
    config.sparse_heading_as_stated = as_stated;
    SpectralBatchSlam slam(config);
    test::feed(dense, slam);
    ASSERT_TRUE(slam.trajectory(true, &paths[as_stated]));
    if (as_stated) {
      EXPECT_EQ(slam.diagnostics().at("heading_as_stated"), 0.0);
    }
  }
  ASSERT_EQ(paths[0].size(), paths[1].size());
  for (size_t k = 0; k < paths[0].size(); ++k) {
    EXPECT_EQ(paths[0][k].x_m, paths[1][k].x_m) << k;
    EXPECT_EQ(paths[0][k].heading_rad, paths[1][k].heading_rad) << k;
  }
}

// The seed sweep's radio-silences kind (2 % outliers U(5, 30) m, every beacon silent twice for
// 30 s) on its development seed 2005, where the spectral seed with surveyed beacons sits in a
// wrong basin: the odometry bent (cost 3167 against the bound of 540, one per two ranges) and 87 %
// of the ranges inliers.
sim::SimConfig radioSilencesWorld(uint64_t seed) {
  sim::SimConfig world = sim::nlos30LawnMowerWorld(seed, 3000);
  world.outlier_fraction = 0.02;
  world.outlier_min_m = sim::SimConfig().outlier_min_m;
  world.outlier_max_m = sim::SimConfig().outlier_max_m;
  world.range_gaps = {sim::parseRangeGap("150:30"), sim::parseRangeGap("400:30")};
  return world;
}

struct SeedResult {
  double error_m;
  double dead_reckoning_seed_solved;
  double init_spectral;
  Path path;
};

SeedResult runSpectralSeeded(const Dataset& data, const char* anchor, const char* dead_reckoning_seed) {
  SpectralBatchConfig config;
  setOptions(&config, addSpectralBatchOptions, {{"init", "spectral"}, {"anchor", anchor}});
  config.dead_reckoning_seed = std::string(dead_reckoning_seed) == "always"  // an internal constant
                                   ? SpectralBatchConfig::DeadReckoningSeed::kAlways
                                   : SpectralBatchConfig::DeadReckoningSeed::kWhenInDoubt;
  SpectralBatchSlam slam(config);
  test::feed(data, slam);
  SeedResult result;
  EXPECT_TRUE(slam.trajectory(true, &result.path));
  result.error_m = test::meanError_m(result.path, data.ground_truth);
  result.dead_reckoning_seed_solved = slam.diagnostics().at("dead_reckoning_seed_solved");
  result.init_spectral = slam.diagnostics().at("init_spectral");
  return result;
}

TEST(SpectralBatchSlam, ASpectralSeedInAWrongBasinIsInDoubtAndLosesToDeadReckoning) {
  if (!spectralSeedAvailable()) GTEST_SKIP() << "the spectral core is not built in";
  const Dataset data = sim::simulate(radioSilencesWorld(2005));
  const SeedResult doubt = runSpectralSeeded(data, "beacons", "when_in_doubt");
  const SeedResult always = runSpectralSeeded(data, "beacons", "always");
  std::printf("radio silences seed 2005, beacons: when_in_doubt %.3f m (dead-reckoning seed solved %g, spectral kept %g), "
              "always %.3f m\n",
              doubt.error_m, doubt.dead_reckoning_seed_solved, doubt.init_spectral, always.error_m);
  EXPECT_EQ(doubt.dead_reckoning_seed_solved, 1.0);
  EXPECT_EQ(doubt.init_spectral, 0.0);  // the dead-reckoning seed won
  EXPECT_LT(doubt.error_m, 0.2);
  EXPECT_EQ(doubt.error_m, always.error_m);
}

TEST(SpectralBatchSlam, ASpectralSeedNotInDoubtIsPublishedWithoutTheSecondSolve) {
  // Development seed 2001 of the same kind, both anchors: the spectral seed's solve fits the model
  // (odometry cost ~12 against the bound of 540, 98 % inliers), so the dead-reckoning seed is not solved;
  // solved (`always`) it ends at the same cost, and the published path agrees to a millimetre.
  if (!spectralSeedAvailable()) GTEST_SKIP() << "the spectral core is not built in";
  const Dataset data = sim::simulate(radioSilencesWorld(2001));
  for (const char* anchor : {"start_pose", "beacons"}) {
    const SeedResult doubt = runSpectralSeeded(data, anchor, "when_in_doubt");
    const SeedResult always = runSpectralSeeded(data, anchor, "always");
    double worst_m = 0.0;
    ASSERT_EQ(doubt.path.size(), always.path.size());
    for (size_t k = 0; k < doubt.path.size(); ++k)
      worst_m = std::max(worst_m, std::hypot(doubt.path[k].x_m - always.path[k].x_m, doubt.path[k].y_m - always.path[k].y_m));
    std::printf("radio silences seed 2001, %s: when_in_doubt %.3f m, always %.3f m, paths apart by at most %.2g m\n",
                anchor, doubt.error_m, always.error_m, worst_m);
    EXPECT_EQ(doubt.dead_reckoning_seed_solved, 0.0);
    EXPECT_EQ(always.dead_reckoning_seed_solved, 1.0);
    EXPECT_EQ(doubt.init_spectral, 1.0);
    EXPECT_LT(worst_m, 1e-3);
    EXPECT_LT(doubt.error_m, std::string(anchor) == "beacons" ? 0.2 : 1.0);
  }
}

}  // namespace
}  // namespace spectral_batch
}  // namespace roam
