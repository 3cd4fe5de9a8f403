// Odometry calibration (distance scale, heading-rate bias) and the adaptive noise of the ekf:
// the SE(2) step worked by hand, the zero-rate update at standstill, and seeded synthetic runs
// like the held-out ones (gyro drift on a figure-8, an AUV-like sparse run with outliers).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <utility>

#include "ekf_config.hpp"
#include "ekf_filter.hpp"
#include "ekf_slam.hpp"
#include "feed.hpp"
#include "roam/estimation/motion_model.hpp"
#include "sim.hpp"

namespace roam {
namespace ekf {
namespace {

constexpr double kExactFilter = 1e-12;

TEST(EkfCalibration, LateralStepWorkedByHand) {
  // Heading pi/2: forward 2 is +y, lateral 1 is -x: (1, 2) -> (1 - 1, 2 + 2) = (0, 4).
  EkfFilter filter;
  filter.reset(Eigen::Vector3d(1.0, 2.0, M_PI / 2), Eigen::Matrix3d::Zero(), false, 0.1, 0.5);
  Odometry odometry;
  odometry.forward_m = 2.0;
  odometry.lateral_m = 1.0;
  odometry.delta_heading_rad = 0.25;
  filter.predict(odometry, 1.0, Eigen::Matrix3d::Zero());
  EXPECT_NEAR(filter.mean()(0), 0.0, kExactFilter);
  EXPECT_NEAR(filter.mean()(1), 4.0, kExactFilter);
  EXPECT_NEAR(filter.mean()(2), M_PI / 2 + 0.25, kExactFilter);
}

TEST(EkfCalibration, CalibrationStatesScaleAndTurnTheStep) {
  // s = 1.1, b = 0.05 rad/s over dt = 2 s: forward 2 -> 2.2 along heading 0; turn 0.3 - 0.1 = 0.2.
  EkfFilter filter;
  EkfCalibrationPrior prior;
  prior.estimated = true;
  filter.reset(Eigen::Vector3d::Zero(), Eigen::Matrix3d::Zero(), true, 0.1, 0.5, prior);
  filter.recentreCalibration(1.1, 0.05);
  Odometry odometry;
  odometry.forward_m = 2.0;
  odometry.delta_heading_rad = 0.3;
  filter.predict(odometry, 2.0, Eigen::Matrix3d::Zero());
  EXPECT_NEAR(filter.mean()(0), 2.2, kExactFilter);
  EXPECT_NEAR(filter.mean()(1), 0.0, kExactFilter);
  EXPECT_NEAR(filter.mean()(2), 0.2, kExactFilter);
  // The heading's variance is the bias's times dt^2: 0.01^2 * 4; x's the scale's times 2^2.
  EXPECT_NEAR(filter.covariance()(2, 2), 4.0 * 1e-4, kExactFilter);
  EXPECT_NEAR(filter.covariance()(0, 0), 4.0 * 0.05 * 0.05, kExactFilter);
}

TEST(EkfCalibration, StandstillLearnsTheBiasAndDoesNotTurn) {
  // 100 steps of 0.2 s standing still with a gyro reporting 0.01 rad/s: the heading stays at
  // the start exactly (zero-rate update), and b -> 0.01 shrunk by its prior: each step observes
  // w = b dt with sigma_w = odo_heading_sigma_rad = 0.001, i.e. b with sigma 0.001 / 0.2 = 0.005
  // (information 4e4 each, 3.84e6 for the 96 from the 5th: the first 4 only confirm the
  // standstill, stationary_min_steps = 5), the prior 0 +- 0.01 (information 1e4):
  // b = 0.01 * 3.84e6 / (3.84e6 + 1e4) (the bias walk, 2e-11 per step, is negligible).
  EkfConfig config;
  EkfSlam ekf(config);
  Pose start;
  start.utime = 0;
  start.heading_rad = 0.3;
  ekf.setInitialPose(start);
  for (int k = 1; k <= 100; ++k) {
    Odometry odometry;
    odometry.utime = k * 200000;
    odometry.delta_heading_rad = 0.01 * 0.2;
    ekf.addOdometry(odometry);
  }
  ekf.finish();
  // The first 4 steps turned by w with b held at 0 (no range yet says whether the ranges could
  // observe it: gyro_bias_max_drift_rad); the confirmed standstill releases it, uncorrelated, so
  // the heading ends at 0.3 + 4 dt 0.01.
  const double b = 0.01 * 3.84e6 / (3.84e6 + 1e4);
  EXPECT_NEAR(ekf.filter().headingRateBias(), b, 1e-8);
  EXPECT_NEAR(ekf.path().back().heading_rad, 0.3 + 4 * 0.2 * 0.01, 1e-6);
  EXPECT_EQ(ekf.diagnostics().at("heading_rate_bias_estimated"), 1.0);
  EXPECT_EQ(ekf.diagnostics().at("stationary_bias_updates"), 96.0);
  EXPECT_EQ(ekf.diagnostics().lower_bound("note: "), ekf.diagnostics().lower_bound("note:~"));  // nothing to note
}

TEST(EkfCalibration, ASlowVehicleTurningIsNotStandingStill) {
  // An AUV drifting at 1.6 cm/s (below stationary_speed_mps) while turning at rates that change
  // by 0.005-0.01 rad/s from one 5 s step to the next (gyro noise 0.002 rad per step, i.e.
  // 4e-4 rad/s): never a standstill, so no zero-rate update, the bias stays at its prior and the
  // heading follows the reported turns.
  EkfConfig config;
  EkfSlam ekf(config);
  Pose start;
  ekf.setInitialPose(start);
  const double rates[] = {-0.011, 0.002, -0.003, -0.006, -0.0015, -0.0057, -0.0003, -0.0012};
  double heading = 0.0;
  for (int k = 0; k < 40; ++k) {
    Odometry odometry;
    odometry.utime = (k + 1) * 5000000;
    odometry.forward_m = 0.08;
    odometry.delta_heading_rad = rates[k % 8] * 5.0;
    heading += odometry.delta_heading_rad;
    ekf.addOdometry(odometry);
  }
  ekf.finish();
  EXPECT_EQ(ekf.diagnostics().at("stationary_bias_updates"), 0.0);
  EXPECT_EQ(ekf.filter().headingRateBias(), 0.0);
  EXPECT_NEAR(ekf.path().back().heading_rad, heading, kExactFilter);
}

using test::deadReckoningError;
using test::meanError;

// The development gyro-drift run (seed 201), 3000 steps of 0.2 s: 0.01 rad/s (0.57 deg/s) of bias.
sim::SimConfig gyroDriftFigure8() { return sim::gyroDriftFigure8World(201, 3000); }

TEST(EkfCalibration, GyroDriftFigure8StartPose) {
  // Measured: 0.25 m mean error with the bias recovered to 0.0097 rad/s (dead reckoning 22 m; 0.34 m
  // before the calibrated re-run initialised its beacons afresh).
  constexpr double kMaxMeanErrorM = 0.5;
  constexpr double kBiasToleranceRadS = 5e-4;
  const sim::SimRun run = sim::simulate(gyroDriftFigure8());
  EkfSlam ekf(EkfConfig{});
  test::feed(run, ekf);
  const double error_m = meanError(ekf.path(), run.ground_truth);
  std::printf("gyro drift, start pose: mean error %.3f m (dead reckoning %.2f m), b %.5f rad/s\n", error_m,
              deadReckoningError(run), ekf.filter().headingRateBias());
  EXPECT_LT(error_m, kMaxMeanErrorM);
  EXPECT_NEAR(ekf.filter().headingRateBias(), 0.01, kBiasToleranceRadS);

  EkfConfig off;
  off.estimate_odometry_calibration = false;
  EkfSlam plain(off);
  test::feed(run, plain);
  EXPECT_GT(meanError(plain.path(), run.ground_truth), 2.0 * error_m);  // the calibration is what helps
}

// The rotation about the start (radians, counter-clockwise) that best maps the estimated beacons
// onto the true ones: the frame error a start-pose run cannot revise.
double mapRotationAboutStartRad(const Map& estimated, const Map& truth, const Pose& start) {
  double cross = 0.0, dot = 0.0;
  for (const Beacon& e : estimated)
    for (const Beacon& t : truth)
      if (e.id == t.id) {
        const double ex = e.x_m - start.x_m, ey = e.y_m - start.y_m, tx = t.x_m - start.x_m, ty = t.y_m - start.y_m;
        cross += tx * ey - ty * ex;
        dot += tx * ex + ty * ey;
      }
  return std::atan2(cross, dot);
}

TEST(EkfCalibration, GyroDriftFigure8StartPoseFrameDoesNotDependOnTheBias) {
  // The calibrated re-run initialises its beacons afresh (EkfSlam::reinitialiseFromStart) when
  // the calibration found a bias. It
  // used to re-use the first pass's insertions, whose frame is turned by the bias the first pass
  // could not see yet (b held at 0 for its first 20 ranges), so each map came out turned with
  // the bias' sign. The same world with +0.01 and with -0.01 rad/s must now give the same frame;
  // what is left is the rotation the start heading and the early odometry leave (~1 degree, of
  // either sign). Seeds 301-306, 3000 steps; measured map rotation about the start (degrees),
  // +0.01 / -0.01: before +0.55 / -4.09, +0.70 / -1.19, -0.93 / -2.71, +1.61 / -0.57, +1.12 /
  // -1.06, +0.10 / -1.56 (mean error over the 12 runs 0.435 m); after -2.10 / -2.10, -0.35 /
  // -0.35, -2.48 / -2.45, +0.06 / +0.08, -0.69 / -0.69, -0.43 / -0.43 (0.357 m).
  constexpr double kMaxRotationDifferenceRad = 0.1 * M_PI / 180.0;
  constexpr double kMaxMeanErrorM = 0.4;
  constexpr int kSeeds = 6;
  double error_sum_m = 0.0;
  for (uint64_t seed = 301; seed < 301 + kSeeds; ++seed) {
    double rotation_rad[2] = {0.0, 0.0};
    for (int sign = 0; sign < 2; ++sign) {
      sim::SimConfig world = sim::gyroDriftFigure8World(seed, 3000);
      world.odo_heading_bias_radps = sign == 0 ? 0.01 : -0.01;
      const sim::SimRun run = sim::simulate(world);
      EkfSlam ekf(EkfConfig{});
      test::feed(run, ekf);
      rotation_rad[sign] = mapRotationAboutStartRad(ekf.currentMap(), run.beacons, run.start);
      EXPECT_EQ(ekf.diagnostics().at("calibration_reruns_reinitialised"), 1.0);  // a bias was found
      const double error_m = meanError(ekf.path(), run.ground_truth);
      error_sum_m += error_m;
      std::printf("gyro %+.2f rad/s seed %d: map turned %+.2f deg, mean error %.3f m, b %.5f rad/s\n",
                  world.odo_heading_bias_radps, static_cast<int>(seed), rotation_rad[sign] * 180.0 / M_PI, error_m,
                  ekf.filter().headingRateBias());
    }
    EXPECT_LT(std::abs(rotation_rad[0] - rotation_rad[1]), kMaxRotationDifferenceRad) << "seed " << seed;
  }
  std::printf("mean error over %d runs: %.3f m\n", 2 * kSeeds, error_sum_m / (2 * kSeeds));
  EXPECT_LT(error_sum_m / (2 * kSeeds), kMaxMeanErrorM);

  // Without a bias the calibration finds none (|b| inside the gate of its sigma): the re-run
  // keeps the first pass's beacons.
  sim::SimConfig world = sim::gyroDriftFigure8World(301, 3000);
  world.odo_heading_bias_radps = 0.0;
  const sim::SimRun run = sim::simulate(world);
  EkfSlam ekf(EkfConfig{});
  test::feed(run, ekf);
  EXPECT_EQ(ekf.diagnostics().at("calibration_reruns"), 1.0);
  EXPECT_EQ(ekf.diagnostics().at("calibration_reruns_reinitialised"), 0.0);
}

// A 60 x 40 m lawn mower with a drifting gyro (sim::longLanesWorld, seed 315), one of whose six
// beacons lies beyond the lanes' ends and is seen over too narrow an arc to be placed. The
// calibrated re-run waits for every pending beacon; it used to wait for that one for ever and
// never turn the map the bias had turned (2.52 m, as with no re-run at all).
TEST(EkfCalibration, ABeaconStillPendingDoesNotHoldBackTheCalibratedRerun) {
  // Measured: 1.03 m with the re-run made at the end of input, 2.52 m without any (dead reckoning
  // 13.8 m), 1.05 m with the re-run made at 200 s; over 20 such runs at 50 Hz odometry and 10 Hz
  // ranges the eleven it held back went from 1.92 to 0.86 m mean.
  const sim::SimRun run = sim::simulate(sim::longLanesWorld(315, 1500));
  EkfSlam ekf(EkfConfig{});
  test::feed(run, ekf);
  const double error_m = meanError(ekf.path(), run.ground_truth);
  std::printf("pending beacon, gyro drift, start pose: %.3f m (dead reckoning %.2f m)\n", error_m, deadReckoningError(run));
  EXPECT_EQ(ekf.diagnostics().at("beacons_pending"), 1.0);
  EXPECT_EQ(ekf.diagnostics().at("calibration_reruns"), 1.0);
  EXPECT_LT(error_m, 1.2);

  // The run through one config: its calibrated re-runs and its path's mean error.
  const auto rerunsAndError = [&run](const EkfConfig& config) {
    EkfSlam slam(config);
    test::feed(run, slam);
    return std::make_pair(slam.diagnostics().at("calibration_reruns"), meanError(slam.path(), run.ground_truth));
  };
  EkfConfig never;
  never.calib_rerun_fraction = 0.0;
  const auto [first_pass_reruns, first_pass_m] = rerunsAndError(never);
  EXPECT_EQ(first_pass_reruns, 0.0);
  std::printf("  without the re-run: %.3f m\n", first_pass_m);
  EXPECT_GT(first_pass_m, 2.0);

  // With the history bounded to 200 s, the re-run is made when that history is about to be freed
  // (the run lasts 300 s), not given up.
  EkfConfig short_history;
  short_history.init_window_s = 200.0;
  const auto [bounded_reruns, bounded_m] = rerunsAndError(short_history);
  EXPECT_EQ(bounded_reruns, 1.0);
  std::printf("  history bounded to 200 s: %.3f m\n", bounded_m);
  EXPECT_LT(bounded_m, 1.2);

  // Bit for bit on a repeat.
  EkfSlam again(EkfConfig{});
  test::feed(run, again);
  ASSERT_EQ(again.path().size(), ekf.path().size());
  for (size_t k = 0; k < ekf.path().size(); ++k) {
    ASSERT_EQ(again.path()[k].x_m, ekf.path()[k].x_m);
    ASSERT_EQ(again.path()[k].y_m, ekf.path()[k].y_m);
  }
}

TEST(EkfCalibration, ASlowUwbRobotEstimatesItsGyroBiasFromTheStartPose) {
  // A slow UWB robot (sim::slowUwbWorld, seed-sweep's slow-uwb): 1 s steps at 0.5 m/s, one range
  // every 2 s round robin over six beacons, a gyro drifting at 0.005 rad/s.
  // Ranges every 2 s: the bias prior turns the heading 0.01 x 3 x 2 = 0.06 rad between fixes,
  // under gyro_bias_max_drift_rad (0.08), so b is estimated. Held at 0 (the old 0.05) the
  // start-pose EKF lost the path (seed 310: 23.1 m; dead reckoning 21.7 m). Measured here:
  // seed 310 0.29 m, b 0.00478 rad/s (seeds 301-310: median 0.29, worst 0.88).
  const sim::SimRun run = sim::simulate(sim::slowUwbWorld(310, 2400));
  EkfConfig config;
  config.anchor = EkfConfig::Anchor::kStartPose;
  EkfSlam ekf(config);
  test::feed(run, ekf);
  const double error_m = meanError(ekf.path(), run.ground_truth);
  std::printf("slow UWB seed 310, start pose: mean error %.2f m (dead reckoning %.2f m), b %.5f rad/s\n", error_m,
              deadReckoningError(run), ekf.filter().headingRateBias());
  EXPECT_EQ(ekf.diagnostics().at("heading_rate_bias_estimated"), 1.0);
  EXPECT_NEAR(ekf.filter().headingRateBias(), 0.005, 0.0005);
  EXPECT_LT(error_m, 1.0);
  EXPECT_EQ(ekf.diagnostics().lower_bound("note: "), ekf.diagnostics().lower_bound("note:~"));  // nothing held
  // The old threshold holds it and loses the path: the test can fail.
  config.gyro_bias_max_drift_rad = 0.05;
  EkfSlam held(config);
  test::feed(run, held);
  EXPECT_GT(meanError(held.path(), run.ground_truth), 10.0);
  EXPECT_NE(held.diagnostics().lower_bound("note: held the heading-rate bias at 0"), held.diagnostics().end());
}

TEST(EkfCalibration, AuvSparseOutliersBeaconsBeatDeadReckoningOnEverySeedAndRepeat) {
  // The development AUV-like run: 3 s steps of 4.5 m, ranges of hundreds of metres, 45 % outliers
  // (-150..+100 m), true sigma 2 m stated as 0.75 m, odometry 15 % noisy and 3 % short; 4
  // beacons 200 m outside the area, and 6 beacons 50 m outside. Ranges every 3.3 s cannot observe
  // a gyro bias (0.01 rad/s x 10 s per position fix = 0.1 rad): the bias stays fixed at 0. Measured
  // (4 beacons, seeds 203, 301-305): 4.85, 5.29, 20.7, 6.24, 4.68, 7.97 m against dead reckoning
  // 16.6, 11.8, 19.3, 20.9, 18.3, 19.9 m (before: 11.5, 4.4, 28.6, 6.0, 12.4, 7.7, with 6
  // beacons up to 164 m); the target is <= 1.25 x dead reckoning.
  for (const uint64_t seed : {203, 301, 302, 303, 304, 305, 311, 313}) {
    sim::SimConfig world = sim::auvLikeWorld(seed, 500);
    if (seed > 310) {
      world.num_beacons = 6;
      world.beacon_margin_m = 50.0;
    }
    const sim::SimRun run = sim::simulate(world);
    EkfConfig config;
    config.anchor = EkfConfig::Anchor::kBeacons;
    EkfSlam ekf(config);
    test::feed(run, ekf);
    const double error_m = meanError(ekf.path(), run.ground_truth);
    const double dr_m = deadReckoningError(run);
    std::printf("AUV sparse seed %d, beacons: mean error %.2f m, dead reckoning %.2f m\n", static_cast<int>(seed),
                error_m, dr_m);
    EXPECT_LT(error_m, 1.1 * dr_m) << "seed " << seed;
    EXPECT_EQ(ekf.diagnostics().at("heading_rate_bias_estimated"), 0.0);
    EXPECT_EQ(ekf.filter().headingRateBias(), 0.0);
    // ... and the run says so (roam-run prints it with the key).
    const auto note = ekf.diagnostics().lower_bound("note: held the heading-rate bias at 0");
    ASSERT_NE(note, ekf.diagnostics().end());
    EXPECT_NE(note->first.find("more than gyro_bias_max_drift_rad (0.080)"), std::string::npos) << note->first;
    if (seed == 203) {
      EkfSlam again(config);
      test::feed(run, again);
      ASSERT_EQ(ekf.path().size(), again.path().size());
      for (size_t k = 0; k < ekf.path().size(); ++k) {
        EXPECT_EQ(ekf.path()[k].x_m, again.path()[k].x_m);  // bit-identical
        EXPECT_EQ(ekf.path()[k].y_m, again.path()[k].y_m);
      }
    }
  }
}

// Feeds a run from its start pose and scores the smoothed TRAJECTORY (full-path mean, m); NaN
// (which fails every bound) if the estimator has none.
double smoothedError(const sim::SimRun& run, EkfSlam& ekf) {
  test::feed(run, ekf);
  Path smoothed;
  if (!ekf.trajectory(true, &smoothed)) {
    ADD_FAILURE() << "no smoothed trajectory";
    return std::nan("");
  }
  return meanError(smoothed, run.ground_truth);
}

// The NLOS 30 % lawn mower with drifting odometry: 0.005 rad/s of gyro bias, odometry 3 % short.
sim::SimRun nlosDriftingOdometryRun(uint64_t seed) {
  sim::SimConfig world = sim::nlos30LawnMowerWorld(seed, 3000);
  world.odo_heading_bias_radps = 0.005;
  world.odo_distance_scale = 0.97;
  return sim::simulate(world);
}

TEST(EkfCalibration, NlosThirtyPercentWithDriftingOdometryInitialisesFromThePose) {
  // The development 30 % NLOS lawn-mower (ranges 2-40 m long) with worse odometry: 0.005 rad/s of
  // gyro bias and a 3 % short distance, from the start pose. Before, no beacon passed the batch
  // solve's checks (its chi2 with the outliers in) and the run was dead reckoning (21.0 / 21.5 m);
  // with the consensus sightings every beacon enters: measured 1.27 / 0.94 m (seeds 202 / 331;
  // seed 332 still initialises none, see the README); since round 5's outlier-robust
  // initialisation 1.15 / 2.57 m (331: its first beacons enter from poses 3-7 m off, the frame
  // rotated; the sweep seeds 301-306 / 401-410 went 1.68 / 5.17 -> 1.28 / 3.03 m on average).
  // Bound: 3.0 m (the dead reckoning is 21 m), every beacon, b within 1e-3.
  for (const uint64_t seed : {202, 331}) {
    const sim::SimRun run = nlosDriftingOdometryRun(seed);
    EkfSlam ekf{EkfConfig{}};
    test::feed(run, ekf);
    const double error_m = meanError(ekf.path(), run.ground_truth);
    std::printf("NLOS 30 %%, drifting odometry, seed %d, start pose: mean error %.2f m (dead reckoning %.2f m)\n",
                static_cast<int>(seed), error_m, deadReckoningError(run));
    EXPECT_LT(error_m, 3.0) << "seed " << seed;
    EXPECT_EQ(ekf.filter().beacons().size(), 6u);
    EXPECT_NEAR(ekf.filter().headingRateBias(), 0.005, 1e-3);
  }
}

}  // namespace
}  // namespace ekf
}  // namespace roam

namespace roam {
namespace ekf {
namespace {

TEST(EkfCalibration, NlosDriftingOdometryJointBiasInitialisesTheBeacons) {
  // NLOS 30 % with 0.005 rad/s gyro bias and 3 % short odometry, seed 332: before the first
  // beacon the dead-reckoned path curls with the bias, each beacon's own solve (bias estimated
  // with it) stays poorly constrained, and no beacon ever entered (dead reckoning, 20 m). The
  // joint solve of the pending beacons' sightings estimates the curl (jointHeadingBias): 0.66 m.
  const sim::SimRun run = nlosDriftingOdometryRun(332);
  EkfSlam ekf{EkfConfig{}};
  test::feed(run, ekf);
  const double error_m = meanError(ekf.path(), run.ground_truth);
  std::printf("NLOS 30 %%, drifting odometry, seed 332, start pose: mean error %.2f m (dead reckoning %.2f m)\n", error_m,
              deadReckoningError(run));
  EXPECT_EQ(ekf.filter().beacons().size(), 6u);
  EXPECT_LT(error_m, 1.0);  // measured 0.66 m; issue 15's target
  EXPECT_NEAR(ekf.filter().headingRateBias(), 0.005, 1e-3);
}

TEST(EkfCalibration, AJointBiasThatOnlyFitsAnNlosStretchIsRefused) {
  // 30 % NLOS in stretches (one excess held for ~20 s per beacon), clean odometry, seed 1008 (the
  // README sweep's nlos30-episodes), start pose. The pending beacons' joint solve kept a stretch
  // whose ranges agree with each other and bent the dead-reckoned path to fit it: db 0.0076 rad/s
  // on odometry with no bias, chi2 82.5 for 36 dof. The first beacon entered 9.2 m off and the run
  // ended 9.23 m off (dead reckoning 1.83 m). A joint whose chi2 is beyond its gate is now refused:
  // measured 0.42 m, the bias found at -4.7e-4 rad/s.
  sim::SimConfig world = sim::nlos30LawnMowerWorld(1008, 3000);
  world.outlier_episode_s = 20.0;
  const sim::SimRun run = sim::simulate(world);
  EkfSlam ekf{EkfConfig{}};
  const double error_m = smoothedError(run, ekf);
  std::printf("NLOS 30 %% in stretches, seed 1008, start pose: trajectory mean error %.2f m (dead reckoning %.2f m), "
              "%.0f joint solves refused\n",
              error_m, deadReckoningError(run), ekf.diagnostics().at("joint_bias_misfits"));
  EXPECT_GT(ekf.diagnostics().at("joint_bias_misfits"), 0.0);
  EXPECT_EQ(ekf.filter().beacons().size(), 6u);
  EXPECT_LT(error_m, 0.6);
  EXPECT_LT(error_m, 0.5 * deadReckoningError(run));
  EXPECT_NEAR(ekf.filter().headingRateBias(), 0.0, 1e-3);
}

TEST(EkfCalibration, NlosDriftingOdometryFreshRerunHoldsTheBiasNearTheFirstPass) {
  // NLOS 30 % with 0.005 rad/s gyro bias and 3 % short odometry (the sweep's nlosw), seeds 408 /
  // 409: the calibrated re-run initialises every beacon afresh. With b released at its prior
  // (0.01 rad/s) the re-run's first beacon alone held the frame for tens of seconds and single
  // ranges to it swung b and the heading: the path curled up to 9.6 m off, the next beacons were
  // solved from those poses (7.6 m off) and the smoothed path was 2.28 / 1.74 m (first pass,
  // before the re-run: 0.78 / 1.0 m). b now enters the fresh re-run within the gate of the first
  // pass's posterior: measured 1.29 / 1.11 m. Bound 1.5 m.
  for (const uint64_t seed : {408, 409}) {
    const sim::SimRun run = nlosDriftingOdometryRun(seed);
    EkfSlam ekf{EkfConfig{}};
    const double error_m = smoothedError(run, ekf);
    std::printf("NLOS 30 %%, drifting odometry, seed %d, start pose: trajectory mean error %.2f m (dead reckoning %.2f m)\n",
                static_cast<int>(seed), error_m, deadReckoningError(run));
    EXPECT_EQ(ekf.diagnostics().at("calibration_reruns_reinitialised"), 1.0) << "seed " << seed;
    EXPECT_EQ(ekf.filter().beacons().size(), 6u) << "seed " << seed;
    EXPECT_LT(error_m, 1.5) << "seed " << seed;
    EXPECT_NEAR(ekf.filter().headingRateBias(), 0.005, 1e-3) << "seed " << seed;
  }
}

TEST(EkfCalibration, NlosDriftingOdometryFreshRerunKeepsTheFirstPassOutliersOut) {
  // nlosw seed 301 (30 % NLOS, 0.005 rad/s gyro bias, 3 % short odometry): the first pass leaves
  // beacon 2's NLOS range at the end of its narrow arc out (0.2 m off), but the calibrated
  // re-run, solving it afresh from 16 sightings, kept that range (its deleted residual 3.2 sigma,
  // inside the gate) and placed the beacon 5.2 m off: smoothed path 2.74 m, the map turned 5.7
  // degrees. The re-run's solves now leave out the ranges the first pass's left out: measured
  // 1.27 m (its rest is the 3 % odometry scale the range scale absorbs). Bound 1.5 m.
  const sim::SimRun run = nlosDriftingOdometryRun(301);
  EkfSlam ekf{EkfConfig{}};
  const double error_m = smoothedError(run, ekf);
  std::printf("NLOS 30 %%, drifting odometry, seed 301, start pose: trajectory mean error %.2f m (dead reckoning %.2f m)\n",
              error_m, deadReckoningError(run));
  EXPECT_EQ(ekf.diagnostics().at("calibration_reruns_reinitialised"), 1.0);
  EXPECT_EQ(ekf.filter().beacons().size(), 6u);
  EXPECT_LT(error_m, 1.5);
}

TEST(EkfCalibration, NlosThirtyPercentStartPoseInitialisesOnTheInliers) {
  // 30 % NLOS (ranges 2-40 m long), start pose: the seeds that diverged. Seed 302 initialised its
  // first beacon from a consensus holding 34 outliers in 134 ranges (scale 1.31, offset 5.6 m,
  // 11 m off) and every beacon after it 40-65 m off: 38.3 m. Seeds 305 / 306 re-applied the
  // NLOS ranges of a well-initialised beacon right after its weak-prior insertion and then
  // initialised the others from poses 6-40 m off: 4.43 / 3.88 m. Now the batch solve keeps the
  // ranges its own solution explains (robust scale), rejects a range bias outside its prior's
  // gate and a solution that jumps with one range, and the ranges it left out are not re-applied:
  // measured 0.27 / 0.52 / 0.45 m. Bound 1.0 m (issue 15's target), every beacon initialised.
  for (const uint64_t seed : {302, 305, 306}) {
    const sim::SimRun run = sim::simulate(sim::nlos30LawnMowerWorld(seed, 3000));
    EkfSlam ekf{EkfConfig{}};
    test::feed(run, ekf);
    const double error_m = meanError(ekf.path(), run.ground_truth);
    std::printf("NLOS 30 %%, seed %d, start pose: mean error %.2f m (dead reckoning %.2f m), %g ranges left out at initialisation\n",
                static_cast<int>(seed), error_m, deadReckoningError(run),
                ekf.diagnostics().at("ranges_excluded_at_initialisation"));
    EXPECT_LT(error_m, 1.0) << "seed " << seed;
    EXPECT_EQ(ekf.filter().beacons().size(), 6u) << "seed " << seed;
    EXPECT_GT(ekf.diagnostics().at("ranges_excluded_at_initialisation"), 0.0) << "seed " << seed;
    // Every beacon entered: each range is counted once, accepted or rejected, none as unused.
    EXPECT_EQ(ekf.rangesAccepted() + ekf.rangesRejected(), static_cast<int64_t>(run.ranges.size())) << "seed " << seed;
    for (const auto& [reason, count] : ekf.rejections())
      EXPECT_EQ(reason.find("never initialised"), std::string::npos) << reason << " x " << count;
  }
}

TEST(EkfCalibration, HalfTheRangesNlosStillInitialiseEveryBeaconFromThePose) {
  // The 30 % NLOS lawn mower with half its ranges NLOS (2-40 m long), from the start pose. The
  // consensus used to widen every range's tolerance by the range scale's prior (10 % of the
  // range: 5 m for a 50 m NLOS range), so most outliers agreed, every solve failed its checks and
  // no beacon ever entered: the run was dead reckoning (1.89 / 0.82 m on seeds 301 / 302). The
  // scale, one unknown per beacon, is now tried as hypotheses across its prior: measured
  // 1.05 / 0.23 m, every beacon in. Bound: every beacon, and under 0.75 x dead reckoning.
  for (const uint64_t seed : {301, 302}) {
    const sim::SimRun run = sim::simulate(sim::nlos50LawnMowerWorld(seed, 3000));
    EkfSlam ekf{EkfConfig{}};
    const double error_m = smoothedError(run, ekf);
    std::printf("NLOS 50 %%, seed %d, start pose: trajectory mean error %.2f m (dead reckoning %.2f m)\n",
                static_cast<int>(seed), error_m, deadReckoningError(run));
    EXPECT_EQ(ekf.filter().beacons().size(), 6u) << "seed " << seed;
    EXPECT_LT(error_m, 0.75 * deadReckoningError(run)) << "seed " << seed;
  }
}

TEST(EkfCalibration, NlosThirtyPercentStartPoseNarrowArcIsNotPlacedByOneRange) {
  // 30 % NLOS, start pose, seed 301 (the sweep's nlos-301): beacon 2 is seen over a narrow arc
  // whose far end is one NLOS range (4.1 m long; later a second, 3.6 m, at the same end). With it
  // the arc passes init_min_angle_rad and the solve, which fits it within the noise model, put
  // the beacon 5.3 m off; the map turned 5.5 degrees about the start (smoothed path 2.83 m, 0.11 m
  // after a rigid fit). Each range is now judged against the solve of the others (deleted
  // residual, also with the solve's most informative range left out): the beacon waits until the
  // inliers alone place it, 0.8 m off; measured 0.98 m (1.11 with the early window solve of round
  // 7c, which keeps the map's rotation about the start); 1.27 m since round 19's consensus tries
  // the range scale as hypotheses (the first beacons enter from other ranges; the map turned 57
  // mrad about the start against 50, 0.10 m after a rigid fit). Bound 1.4 m, beacon 2 within 1.5 m.
  const sim::SimRun run = sim::simulate(sim::nlos30LawnMowerWorld(301, 3000));
  EkfSlam ekf{EkfConfig{}};
  const double error_m = smoothedError(run, ekf);
  std::printf("NLOS 30 %%, seed 301, start pose: trajectory mean error %.2f m (dead reckoning %.2f m)\n", error_m,
              deadReckoningError(run));
  EXPECT_LT(error_m, 1.4);
  ASSERT_EQ(ekf.filter().beacons().size(), 6u);
  for (const Beacon& truth : run.beacons) {
    for (const Beacon& estimate : ekf.currentMap()) {
      if (estimate.id == truth.id && truth.id == 2) {
        EXPECT_LT(std::hypot(estimate.x_m - truth.x_m, estimate.y_m - truth.y_m), 1.5);
      }
    }
  }
}

TEST(EkfCalibration, NlosThirtyPercentStartPoseEarlyWindowFixesTheFrame) {
  // 30 % NLOS, start pose, seed 303 (the sweep's nlos-303): its beacons were multilaterated from
  // dead-reckoned poses, 1.3 m off on average, and the map turned 2.2 degrees about the start
  // (smoothed path 1.02 m). The early window solved jointly (init_window_solve, path and map,
  // ekf_window_init.cpp) refutes the dead-reckoned path (gain beyond its gate) and the beacons
  // enter at its map: measured 0.41 m. Seed 302's window does not pass its gate: identical run.
  auto run_once = [](uint64_t seed, bool window, double* applied) {
    const sim::SimRun run = sim::simulate(sim::nlos30LawnMowerWorld(seed, 3000));
    EkfConfig config;
    config.init_window_solve = window;
    EkfSlam ekf{config};
    test::feed(run, ekf);
    Path smoothed;
    EXPECT_TRUE(ekf.trajectory(true, &smoothed));
    *applied = ekf.diagnostics().at("window_solve_applied");
    return meanError(smoothed, run.ground_truth);
  };
  double applied = 0.0, applied_off = 0.0, applied_again = 0.0;
  const double with_m = run_once(303, true, &applied);
  const double without_m = run_once(303, false, &applied_off);
  std::printf("NLOS 30 %%, seed 303, start pose: trajectory mean error %.3f m with the window solve, %.3f m without\n",
              with_m, without_m);
  EXPECT_EQ(applied, 1.0);
  EXPECT_EQ(applied_off, 0.0);
  EXPECT_LT(with_m, 0.6);
  EXPECT_GT(without_m, 0.9);
  EXPECT_EQ(run_once(303, true, &applied_again), with_m);  // bit-identical on a repeat
  const double kept_m = run_once(302, true, &applied);
  EXPECT_EQ(applied, 0.0);
  EXPECT_EQ(kept_m, run_once(302, false, &applied_off));
}

TEST(EkfCalibration, AuvStartPoseThatInitialisesNoBeaconSaysWhyInStatus) {
  // From the start pose the AUV-like run (seed 203) initialises no beacon: its ranges to each
  // beacon (2 m noise, 45 % outliers, poses drifting metres between them) never pass the batch
  // solve's checks, so the run is dead reckoning. STATUS says so, beacon by beacon, under the
  // check each one's last solve failed: measured 1 ambiguous (mirror), 1 narrow angle, 2 poorly
  // constrained, none for lack of ranges.
  const sim::SimRun run = sim::simulate(sim::auvLikeWorld(203, 500));
  EkfSlam ekf{EkfConfig{}};
  test::feed(run, ekf);
  const auto& status = ekf.diagnostics();
  EXPECT_EQ(status.at("beacons_initialised"), 0.0);
  EXPECT_EQ(status.at("beacons_pending"), 4.0);
  double reasons = 0.0;
  for (const char* key : {"beacons_pending_too_few_ranges", "beacons_pending_short_baseline", "beacons_pending_no_solution",
                          "beacons_pending_ambiguous", "beacons_pending_narrow_angle", "beacons_pending_poorly_constrained"})
    reasons += status.at(key);
  EXPECT_EQ(reasons, 4.0);  // every pending beacon has one reason
  EXPECT_EQ(status.at("beacons_pending_too_few_ranges"), 0.0);
  EXPECT_EQ(status.at("beacons_pending_poorly_constrained"), 2.0);
  EXPECT_NEAR(meanError(ekf.path(), run.ground_truth), deadReckoningError(run), 1e-9);
  // No range was used, and each is rejected under its beacon's failed check, whose reason names
  // the config key (roam-run's end-of-run warning prints "look at key init_max_sigma_m").
  EXPECT_EQ(ekf.rangesAccepted(), 0);
  EXPECT_EQ(ekf.rangesRejected(), static_cast<int64_t>(run.ranges.size()));
  int64_t never_initialised = 0;
  for (const auto& [reason, count] : ekf.rejections())
    if (reason.find("beacon never initialised") != std::string::npos) never_initialised += count;
  EXPECT_EQ(never_initialised, static_cast<int64_t>(run.ranges.size()));
  EXPECT_GT(ekf.rejections().count("range: beacon never initialised: its solve stayed too uncertain (init_max_sigma_m)"), 0u);
}

}  // namespace
}  // namespace ekf
}  // namespace roam

namespace roam {
namespace ekf {
namespace {

// Adds to every range its beacon's own offset, |offset| uniform in [min_m, max_m], random sign
// (the sim's draw, from the stream `seed`).
void addPerBeaconOffsets(sim::SimRun* run, uint64_t seed, double min_m, double max_m) {
  const std::map<int, double> offset_m = sim::beaconOffsets(seed, min_m, max_m, run->beacons);
  for (Range& range : run->ranges) range.range_m += offset_m.at(range.beacon_id);
}

// Mean error with surveyed beacons, per-beacon offset states with the given prior sigma (0: none).
double beaconsError(const sim::SimRun& run, double offset_sigma_m) {
  EkfConfig config;
  config.anchor = EkfConfig::Anchor::kBeacons;
  config.beacon_range_offset_sigma_m = offset_sigma_m;
  EkfSlam ekf(config);
  test::feed(run, ekf);
  EXPECT_EQ(ekf.filter().beaconOffsetIndex(run.beacons.front().id) >= 0, offset_sigma_m > 0.0);
  return meanError(ekf.path(), run.ground_truth);
}

TEST(EkfCalibration, GoatsLikeAuvWithPerBeaconRangeOffsetsStaysBelowDeadReckoning) {
  // The development AUV-like run as GOATS 16 has it: every beacon's ranges carry their own offset
  // of 1-2 m (random sign; a transponder's turn-around delay) and the odometry heading is nearly
  // exact (0.0005 rad per step). Surveyed beacons, per-beacon offset states (the default, 1.5 m)
  // against none. Measured over seeds 501-516 (x dead reckoning): 0.16-1.06 with the states,
  // 0.20-0.98 without; summed error 99.4 m against 92.8 m. With an earlier draw of the same
  // offsets (sign drawn before magnitude) the sums were 101.2 against 104.1 m: on these runs
  // (2 m range noise, 45 % outliers, 15 % odometry) the offsets are a small part of the error and
  // the states neither help nor hurt reliably; what holds on every seed is the bound, 1.25 x DR.
  // The states pay off where ranges are clean (UWB anchor delays, below).
  for (uint64_t seed = 501; seed <= 516; ++seed) {
    sim::SimConfig world = sim::auvLikeWorld(seed, 500);
    world.odo_heading_sigma_rad = 0.0005;
    sim::SimRun run = sim::simulate(world);
    addPerBeaconOffsets(&run, seed, 1.0, 2.0);
    const double dr_m = deadReckoningError(run);
    const double with_m = beaconsError(run, EkfConfig{}.beacon_range_offset_sigma_m), without_m = beaconsError(run, 0.0);
    std::printf("GOATS-like AUV seed %d: per-beacon offsets %.2f m, none %.2f m, dead reckoning %.2f m\n",
                static_cast<int>(seed), with_m, without_m, dr_m);
    EXPECT_LT(with_m, 1.25 * dr_m) << "seed " << seed;
    EXPECT_LT(without_m, 1.25 * dr_m) << "seed " << seed;
  }
}

TEST(EkfCalibration, UwbAnchorDelaysArePerBeaconOffsets) {
  // The development gyro-drift figure-8 (UWB-like: 0.3 m range noise) with each anchor's own delay,
  // 0.2-0.5 m: with surveyed beacons and no per-beacon states the shared offset cannot explain
  // them (only their mean) and the path bends between beacons. Measured (seeds 201-203): 0.174 /
  // 0.176 / 0.172 m with the states, 0.348 / 0.388 / 0.383 m without; with an earlier draw
  // of the offsets 0.179 / 0.177 / 0.173 against 0.259 / 0.295 / 0.190 (the shared offset takes
  // the draws' mean: the less they differ, the less the states add). Without offsets in the data
  // the states cost ~0.01 m.
  double sum_with_m = 0.0, sum_without_m = 0.0;
  for (const uint64_t seed : {201, 202, 203}) {
    sim::SimRun run = sim::simulate(sim::gyroDriftFigure8World(seed, 3000));
    addPerBeaconOffsets(&run, seed, 0.2, 0.5);
    const double with_m = beaconsError(run, EkfConfig{}.beacon_range_offset_sigma_m), without_m = beaconsError(run, 0.0);
    std::printf("UWB figure-8 seed %d, anchor delays: per-beacon offsets %.3f m, none %.3f m\n", static_cast<int>(seed),
                with_m, without_m);
    EXPECT_LT(with_m, 0.22) << "seed " << seed;
    EXPECT_LT(with_m, without_m) << "seed " << seed;
    sum_with_m += with_m;
    sum_without_m += without_m;
  }
  EXPECT_LT(sum_with_m, 0.8 * sum_without_m);
}

}  // namespace
}  // namespace ekf
}  // namespace roam
