// Odometry through the shared motion model, gyro-bias / distance-scale calibration against the
// spectral solution, and honest refusals (no solution with the reason, nothing published).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "odometry_path.hpp"
#include "roam/estimation/motion_model.hpp"
#include "sim.hpp"
#include "spectral_slam.hpp"
#include "spectral_test_util.hpp"

namespace roam::spectral {
namespace {

using testing::feed;
using testing::pathErrors;

constexpr double kExact_m = 1e-12;
// gyroDriftWorld(), measured: b = 0.00982 / 0.00983 rad/s (true 0.01; beacons / start pose),
// s = 0.9985 (true 1); mean error 0.196 m (beacons; 0.270 m uncalibrated) and 0.230 m (start
// pose; 5.25 m uncalibrated). Without the bias: b within 2e-4, 0.196 m either way.
constexpr double kBiasTolerance_rad_s = 5e-4;
constexpr double kScaleTolerance = 0.01;
constexpr double kDriftBeaconsBound_m = 0.3;
constexpr double kDriftStartPoseBound_m = 0.5;

TEST(OdometryPath, LateralAndBackwardStepsFollowTheSharedMotionModel) {
  // From (1, 2, 0.5): forward -1 (backwards), lateral 0.5, turn 0.3 over 2 s.
  Pose start;
  start.utime = 0;
  start.x_m = 1.0;
  start.y_m = 2.0;
  start.heading_rad = 0.5;
  Odometry odometry;
  odometry.utime = 2000000;
  odometry.forward_m = -1.0;
  odometry.lateral_m = 0.5;
  odometry.delta_heading_rad = 0.3;
  OdometryPath path;
  path.reset(start);
  path.append(odometry);
  // x' = 1 + cos(0.5)(-1) - sin(0.5)(0.5), y' = 2 + sin(0.5)(-1) + cos(0.5)(0.5).
  EXPECT_NEAR(path.x_m[1], 1.0 - std::cos(0.5) - 0.5 * std::sin(0.5), kExact_m);
  EXPECT_NEAR(path.y_m[1], 2.0 - std::sin(0.5) + 0.5 * std::cos(0.5), kExact_m);
  EXPECT_NEAR(path.heading_rad[1], 0.8, kExact_m);
  EXPECT_NEAR(path.step_m[0], std::hypot(1.0, 0.5), kExact_m);  // distance travelled, not signed

  // Recalibrated with s = 1.1, b = 0.01 rad/s: (u, v, w) = (-1.1, 0.55, 0.3 - 0.02).
  path.recalibrate(1.1, {0.01});
  const Eigen::Vector3d expected = estimation::step(
      Eigen::Vector3d(1.0, 2.0, 0.5), Eigen::Vector3d(-1.1, 0.55, 0.28));
  EXPECT_NEAR(path.x_m[1], expected.x(), kExact_m);
  EXPECT_NEAR(path.y_m[1], expected.y(), kExact_m);
  EXPECT_NEAR(path.heading_rad[1], 0.78, kExact_m);
  EXPECT_NEAR(path.calibration.heading_rate_bias_rad_s, 0.01, kExact_m);
  ASSERT_EQ(path.odometry.size(), 1u);  // the raw increment is kept
  EXPECT_EQ(path.odometry[0].forward_m, -1.0);
}

// Lawn mower 40 x 30 m, 6 beacons, 2 Hz round robin, 0.3 m range noise, 2 % odometry, and a gyro
// bias of 0.01 rad/s (0.57 deg/s): 600 s of it turn dead reckoning by 6 rad.
sim::SimConfig gyroDriftWorld() {
  sim::SimConfig c;
  c.seed = 41;
  c.num_steps = 3000;
  c.dt_s = 0.2;
  c.path = sim::PathKind::kLawnMower;
  c.num_beacons = 6;
  c.schedule = sim::RangeSchedule::kRoundRobin;
  c.range_rate_hz = 2.0;
  c.range_sigma_m = 0.3;
  c.odo_distance_sigma_rel = 0.02;
  c.odo_heading_sigma_rad = 0.003;
  c.odo_heading_bias_radps = 0.01;
  return c;
}

TEST(SpectralCalibration, GyroBiasIsRecoveredAndRemoved) {
  const sim::SimRun run = sim::simulate(gyroDriftWorld());
  for (SpectralAnchor anchor : {SpectralAnchor::kBeacons, SpectralAnchor::kStartPose}) {
    double mean_m[2] = {-1.0, -1.0};  // calibrated, not (-1: no solution)
    for (bool calibrate : {true, false}) {
      SpectralConfig config;
      config.anchor = anchor;
      config.calibrate_odometry = calibrate;
      SpectralSlam slam(config);
      feed(slam, run, anchor == SpectralAnchor::kBeacons);
      slam.finish();
      if (!slam.solution()) continue;
      mean_m[calibrate ? 0 : 1] = pathErrors(slam.solution()->trajectory, run.ground_truth).mean_m;
      if (calibrate) {
        std::printf("anchor %d: b = %.5f rad/s, s = %.4f\n", static_cast<int>(anchor),
                    slam.solution()->calibration.heading_rate_bias_rad_s,
                    slam.solution()->calibration.distance_scale);
        EXPECT_NEAR(slam.solution()->calibration.heading_rate_bias_rad_s, 0.01, kBiasTolerance_rad_s);
        EXPECT_NEAR(slam.solution()->calibration.distance_scale, 1.0, kScaleTolerance);
      }
    }
    std::printf("anchor %d: calibrated %.3f m, uncalibrated %.3f m (-1: no solution)\n",
                static_cast<int>(anchor), mean_m[0], mean_m[1]);
    ASSERT_GE(mean_m[0], 0.0);
    if (anchor == SpectralAnchor::kStartPose) {
      EXPECT_GT(mean_m[1], 10.0 * mean_m[0]);
    }
    EXPECT_LT(mean_m[0], anchor == SpectralAnchor::kBeacons ? kDriftBeaconsBound_m : kDriftStartPoseBound_m);
  }
}

// A figure-8 (two circles) leaves a pencil of quadrics through the learned states; before the
// pencil's paraboloids were searched the start-pose upgrade refused (rank 7) or went 1.8-3.2 m off
// (rank 4). Measured on gyroDriftFigure8World seed 106 (4000 steps, 0.01 rad/s): 1.14 m at either
// rank, b = 0.00986 rad/s; what is left is the rotation from the first align_m,
// fitted to dead reckoning whose heading wanders (0.003 rad per step). Beacons: 0.21 m.
constexpr double kFigure8StartPoseBound_m = 1.5;
TEST(SpectralCalibration, GyroDriftFigure8IsSolvedFromTheStartPose) {
  const sim::SimRun run = sim::simulate(sim::gyroDriftFigure8World(106, 4000));
  for (int rank : {4, 7}) {
    SpectralConfig config;
    config.anchor = SpectralAnchor::kStartPose;
    config.rank = rank;
    SpectralSlam slam(config);
    feed(slam, run, false);
    slam.finish();
    ASSERT_TRUE(slam.solution().has_value()) << "rank " << rank << ": " << slam.lastRejection();
    const double mean_m = pathErrors(slam.solution()->trajectory, run.ground_truth).mean_m;
    std::printf("figure-8 rank %d start pose: %.3f m, b = %.5f rad/s\n", rank, mean_m,
                slam.solution()->calibration.heading_rate_bias_rad_s);
    EXPECT_LT(mean_m, kFigure8StartPoseBound_m) << "rank " << rank;
    EXPECT_NEAR(slam.solution()->calibration.heading_rate_bias_rad_s, 0.01, kBiasTolerance_rad_s);
  }
}

TEST(SpectralCalibration, NoBiasNoChange) {
  // The same world without a bias: b near zero and the path as good as without calibration.
  sim::SimConfig world = gyroDriftWorld();
  world.odo_heading_bias_radps = 0.0;
  const sim::SimRun run = sim::simulate(world);
  double mean_m[2];
  for (bool calibrate : {true, false}) {
    SpectralConfig config;
    config.calibrate_odometry = calibrate;
    SpectralSlam slam(config);
    feed(slam, run);
    slam.finish();
    ASSERT_TRUE(slam.solution().has_value());
    mean_m[calibrate ? 0 : 1] = pathErrors(slam.solution()->trajectory, run.ground_truth).mean_m;
    if (calibrate) {
      EXPECT_NEAR(slam.solution()->calibration.heading_rate_bias_rad_s, 0.0, kBiasTolerance_rad_s);
    }
  }
  std::printf("no bias: calibrated %.3f m, uncalibrated %.3f m\n", mean_m[0], mean_m[1]);
  EXPECT_LT(mean_m[0], mean_m[1] + 0.02);
}

TEST(SpectralOutliers, ThirtyPercentNlosWithinAMetreAcrossSeeds) {
  // roam-sim's heavy-NLOS run (lawn mower 40 x 30 m, 6 beacons, 2 Hz round robin, 0.3 m noise,
  // 30 % of the ranges 2-40 m long), four seeds. Measured, anchor = beacons (rank 7): 0.65 / 0.90
  // / 0.56 / 0.51 m (seeds 202 / 212 / 222 / 232; 3.03 / 2.15 / 0.56 / 2.54 m when the first
  // window that passed the self-check was taken); dead reckoning 1.75 / 1.23 / 2.07 / 2.12 m.
  // anchor = start_pose (rank 4), seeds 202 / 212: 0.86 / 0.97 m (2.75 / 1.81 before).
  // Bounds: issue 15's targets (1.0 m beacons, 1.5 m start pose).
  for (const uint64_t seed : {202u, 212u, 222u, 232u}) {
    const sim::SimRun run = sim::simulate(sim::nlos30LawnMowerWorld(seed, 3000));
    for (const bool start_pose : {false, true}) {
      if (start_pose && seed > 212u) continue;
      SpectralConfig config;
      if (start_pose) {
        config.anchor = SpectralAnchor::kStartPose;
        config.rank = 4;
      }
      SpectralSlam slam(config);
      feed(slam, run);
      slam.finish();
      ASSERT_TRUE(slam.solution().has_value()) << "seed " << seed << ": " << slam.lastRejection();
      const double mean_m = pathErrors(slam.solution()->trajectory, run.ground_truth).mean_m;
      std::printf("30 %% NLOS seed %u %s: %.3f m, window %.0f s\n", static_cast<unsigned>(seed),
                  start_pose ? "start pose" : "beacons", mean_m, slam.solution()->window_s);
      EXPECT_LT(mean_m, start_pose ? 1.5 : 1.0) << "seed " << seed;
    }
  }
}

// 30 % NLOS with imperfect odometry (the sweep's `nlosw` kind: gyro bias 0.005 rad/s, distance
// scale 0.97; dead reckoning ~20 m). The window retries reach 384 s, where one chunk is too few to
// calibrate again, so the raw odometry (turned 1.9 rad per window) left the windows unfit: seeds
// 303 / 403 had no start-pose solution, and 403 none with the beacons either. Each retry now also
// starts from the shorter windows' calibration; then the ranges far off the long-window solution
// are dropped and the run solved again from the base window (outlier_drop_sigmas). Measured
// (rank 7 beacons, rank 4 start pose): seed 303 0.40 / 2.05 m, seed 403 0.43 / 1.33 m (calibration
// carried only: 0.77 / 3.18, 0.66 / 3.88; before: 1.43 / -, - / -), b 0.0053 / 0.0055-0.0056 rad/s.
// What is left from the start pose is its rotation from the first align_m (4-5 degrees on seed
// 303). Rank 7 from the start pose on seed 310 found no paraboloid at its first window and
// refused; 0.87 m now.
TEST(SpectralOutliers, NlosWithGyroBiasAndShortOdometryIsSolved) {
  for (const uint64_t seed : {303u, 403u, 310u}) {
    sim::SimConfig world = sim::nlos30LawnMowerWorld(seed, 3000);
    world.odo_heading_bias_radps = 0.005;
    world.odo_distance_scale = 0.97;
    const sim::SimRun run = sim::simulate(world);
    for (const bool start_pose : {false, true}) {
      if (seed == 310u && !start_pose) continue;
      SpectralConfig config;
      if (start_pose) {
        config.anchor = SpectralAnchor::kStartPose;
        config.rank = seed == 310u ? 7 : 4;
      }
      SpectralSlam slam(config);
      feed(slam, run, !start_pose);
      slam.finish();
      ASSERT_TRUE(slam.solution().has_value()) << "seed " << seed << ": " << slam.lastRejection();
      const double mean_m = pathErrors(slam.solution()->trajectory, run.ground_truth).mean_m;
      const double bias = slam.solution()->calibration.heading_rate_bias_rad_s;
      std::printf("NLOS + gyro bias seed %u %s: %.3f m, b = %.5f rad/s, window %.0f s\n",
                  static_cast<unsigned>(seed), start_pose ? "start pose" : "beacons", mean_m, bias,
                  slam.solution()->window_s);
      EXPECT_NEAR(bias, 0.005, 0.0015) << "seed " << seed;
      EXPECT_LT(mean_m, start_pose ? 2.5 : 0.6) << "seed " << seed;
    }
  }
}

TEST(SpectralRefusal, AuvLikeSparseRunPublishesNothingAndSaysWhy) {
  // roam-sim's AUV-like run: 4 beacons 200 m out, one range every ~3 s (0.3 Hz round robin, so
  // one per beacon every ~13 s), 2 m noise, 45 % outliers from -150 to +100 m, 15 % odometry.
  // The windows cannot fit that: no solution, the reason in STATUS, no pose published.
  sim::SimConfig c = sim::auvLikeWorld(203, 500);
  c.range_sigma_reported_m = 0.0;  // no stated sigma: the estimator's configured one
  const sim::SimRun run = sim::simulate(c);
  // Online mode too: its self-check on the data so far holds every pose, so nothing goes out
  // before finish() refuses (it published the start pose and dead reckoning before).
  for (const bool online : {false, true}) {
  for (SpectralAnchor anchor : {SpectralAnchor::kBeacons, SpectralAnchor::kStartPose}) {
    SpectralConfig config;
    config.anchor = anchor;
    if (online) config.mode = SpectralMode::kOnline;
    SpectralSlam slam(config);
    feed(slam, run, anchor == SpectralAnchor::kBeacons);
    ASSERT_NO_THROW(slam.finish());
    EXPECT_EQ(slam.state(), EstimatorState::kFinished);
    EXPECT_FALSE(slam.solution().has_value());
    EXPECT_EQ(slam.lastRejection().rfind("data: spectral: ", 0), 0u) << slam.lastRejection();
    Path path;
    EXPECT_FALSE(slam.trajectory(true, &path));
    EXPECT_TRUE(slam.takePoses().empty()) << (online ? "online" : "batch");
  }
  }
}

TEST(SpectralRefusal, HalfTheRangesNlosWithSurveyedBeaconsIsANoSolutionNotAFailure) {
  // The seed sweep's nlos50 kind, seed 1009: half the ranges NLOS (2-40 m long), surveyed
  // beacons, rank 7. The learned states fit no positive state scale against the surveyed
  // beacons; that used to throw out of finish() as a failure of the estimator ("no positive
  // state scale", roam-run exit 1). It is a property of the data, like rank 4's refusal on the
  // same run (its windows' median residual is an outlier's): no solution, the reason in STATUS,
  // nothing published, in batch and online modes. (drop_range_jumps off: the refusal path itself.)
  const sim::SimRun run = sim::simulate(sim::nlos50LawnMowerWorld(1009, 3000));
  for (const bool online : {false, true}) {
    for (const int rank : {4, 7}) {
      SpectralConfig config;
      config.rank = rank;
      config.drop_range_jumps = false;
      if (online) config.mode = SpectralMode::kOnline;
      SpectralSlam slam(config);
      feed(slam, run, true);
      ASSERT_NO_THROW(slam.finish()) << "rank " << rank;
      EXPECT_EQ(slam.state(), EstimatorState::kFinished) << "rank " << rank;
      EXPECT_FALSE(slam.solution().has_value()) << "rank " << rank;
      EXPECT_EQ(slam.lastRejection().rfind("data: ", 0), 0u) << slam.lastRejection();
      std::printf("NLOS 50 %%, seed 1009, rank %d%s: %s\n", rank, online ? ", online" : "", slam.lastRejection().c_str());
      EXPECT_TRUE(slam.takePoses().empty());
    }
  }
}

// Half the ranges NLOS (the sweep's nlos50 kind, development seed 306): every window's median
// residual is an outlier's, so the run was refused in both anchors. Before refusing, the ranges in
// stretches entered by a jump up and left by a jump down beyond the distance travelled are left out
// (drop_range_jumps, range_jumps.hpp) and the run solved once more under the same self-check.
// Measured: beacons (rank 7) 0.175 m, start pose (rank 4) 0.348 m; dead reckoning 1.52 m. Bounds:
// issue 15's targets for 30 % NLOS (1.0 m beacons, 1.5 m start pose). Bit-identical when repeated.
TEST(SpectralOutliers, HalfTheRangesNlosIsSolvedWithoutTheirJumpStretchesWhereItWouldBeRefused) {
  const sim::SimRun run = sim::simulate(sim::nlos50LawnMowerWorld(306, 3000));
  for (const bool start_pose : {false, true}) {
    SpectralConfig config;
    if (start_pose) {
      config.anchor = SpectralAnchor::kStartPose;
      config.rank = 4;
    }
    SpectralConfig refusing = config;
    refusing.drop_range_jumps = false;
    SpectralSlam before(refusing);
    feed(before, run, !start_pose);
    before.finish();
    EXPECT_FALSE(before.solution().has_value());
    EXPECT_EQ(before.lastRejection().rfind("data: spectral: ", 0), 0u) << before.lastRejection();

    std::vector<Path> paths;
    for (int repeat = 0; repeat < 2; ++repeat) {
      SpectralSlam slam(config);
      feed(slam, run, !start_pose);
      slam.finish();
      ASSERT_TRUE(slam.solution().has_value()) << slam.lastRejection();
      const SpectralSolution& solution = *slam.solution();
      const double mean_m = pathErrors(solution.trajectory, run.ground_truth).mean_m;
      std::printf("NLOS 50 %%, seed 306, %s: %.3f m, %d of %zu ranges left out as jump stretches\n",
                  start_pose ? "start pose" : "beacons", mean_m, solution.jump_dropped_ranges, run.ranges.size());
      EXPECT_LT(mean_m, start_pose ? 1.5 : 1.0);
      EXPECT_GT(solution.jump_dropped_ranges, 0);
      EXPECT_LT(solution.jump_dropped_ranges, static_cast<int>(run.ranges.size()) / 2);
      paths.push_back(solution.trajectory);
    }
    ASSERT_EQ(paths[0].size(), paths[1].size());
    for (size_t k = 0; k < paths[0].size(); ++k) {
      ASSERT_EQ(paths[0][k].x_m, paths[1][k].x_m) << k;
      ASSERT_EQ(paths[0][k].y_m, paths[1][k].y_m) << k;
    }
  }
}

}  // namespace
}  // namespace roam::spectral
