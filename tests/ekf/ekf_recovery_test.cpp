// The EKF's starvation recovery on trial (ekf_recovery.cpp), on seeded AUV-like runs with about
// half the ranges outliers: a widening that a run of gated outliers set off, on a filter that was
// not lost, is declined; one that finds a lost filter its way back is kept; the range counts
// follow the run that is kept; and the result repeats bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

#include "ekf_config.hpp"
#include "ekf_slam.hpp"
#include "feed.hpp"
#include "roam/estimation/motion_model.hpp"
#include "sim.hpp"

namespace roam {
namespace ekf {
namespace {

using test::deadReckoningError;
using test::meanError;

struct Outcome {
  double error_m = 0.0;  // the published TRAJECTORY's mean error
  Path trajectory;
  std::map<std::string, double> diagnostics;
  int64_t accepted = 0, rejected = 0;
};

Outcome runEkf(const sim::SimRun& run, const EkfConfig& config) {
  EkfSlam ekf(config);
  test::feed(run, ekf, true);
  Outcome outcome;
  EXPECT_TRUE(ekf.trajectory(true, &outcome.trajectory));
  outcome.error_m = meanError(outcome.trajectory, run.ground_truth);
  outcome.diagnostics = ekf.diagnostics();
  outcome.accepted = ekf.rangesAccepted();
  outcome.rejected = ekf.rangesRejected();
  return outcome;
}

EkfConfig surveyedBeacons(int trial_ranges = EkfConfig{}.recover_trial_ranges,
                          int consistent_gated = EkfConfig{}.recover_consistent_gated) {
  EkfConfig config;
  config.anchor = EkfConfig::Anchor::kBeacons;
  config.recover_trial_ranges = trial_ranges;
  config.recover_consistent_gated = consistent_gated;
  return config;
}

Outcome runWithSurveyedBeacons(const sim::SimRun& run, int trial_ranges,
                               int consistent_gated = EkfConfig{}.recover_consistent_gated) {
  return runEkf(run, surveyedBeacons(trial_ranges, consistent_gated));
}

TEST(EkfRecovery, AWideningOnAFilterThatWasNotLostIsDeclined) {
  // GOATS-like seed 313: at 1100-1107 s the filter fits its inliers to within 4 m, then eight
  // outliers come in a row (33-195 m short). Widened at once, the next outliers passed the
  // widened gate and moved it 44 m (8.92 m mean, 1.52 x dead reckoning). On trial, the run
  // without the widening explains the next ranges better and is kept. Measured: 3.23 m against
  // dead reckoning 5.86 m, with one widening declined and two (later, where it was lost) kept.
  // (At once is measured with the run of eight alone, the trigger it was found with; with
  // recover_consistent_gated as well it is 6.31 m.)
  const sim::SimRun run = sim::simulate(sim::goatsLikeWorld(313, 210));
  const double dr_m = deadReckoningError(run);
  const Outcome at_once = runWithSurveyedBeacons(run, 0, 0);
  const Outcome on_trial = runWithSurveyedBeacons(run, EkfConfig{}.recover_trial_ranges);
  std::printf("GOATS-like seed 313, beacons: widened at once %.2f m, on trial %.2f m, dead reckoning %.2f m\n",
              at_once.error_m, on_trial.error_m, dr_m);
  EXPECT_GT(at_once.error_m, 1.25 * dr_m);  // the failure the trial is for: the test can fail
  EXPECT_LT(on_trial.error_m, 0.7 * dr_m);
  EXPECT_GE(on_trial.diagnostics.at("starvation_recoveries_declined"), 1.0);
  EXPECT_EQ(at_once.diagnostics.at("starvation_recoveries_declined"), 0.0);
  // Every range is counted once, as the run that was kept had it.
  EXPECT_EQ(on_trial.accepted + on_trial.rejected, static_cast<int64_t>(run.ranges.size()));
  EXPECT_EQ(static_cast<double>(on_trial.rejected), on_trial.diagnostics.at("ranges_gated"));
  // And the decision repeats bit for bit.
  const Outcome again = runWithSurveyedBeacons(run, EkfConfig{}.recover_trial_ranges);
  ASSERT_EQ(again.trajectory.size(), on_trial.trajectory.size());
  for (size_t k = 0; k < again.trajectory.size(); ++k) {
    EXPECT_EQ(again.trajectory[k].x_m, on_trial.trajectory[k].x_m);
    EXPECT_EQ(again.trajectory[k].y_m, on_trial.trajectory[k].y_m);
  }
  EXPECT_EQ(again.rejected, on_trial.rejected);
}

TEST(EkfRecovery, AWideningThatFindsALostFilterItsWayBackIsKept) {
  // AUV-like seed 301 whose odometry reports no motion for steps 250-259 while the vehicle goes
  // on (a DVL that lost bottom lock and reports zeros): the filter is 45 m behind, sure of it,
  // gates every range, and only a widening brings it back. On trial the widened re-run explains the ranges after the trigger better
  // and is kept. Mean error from step 300 on, measured: 59.50 m never widened, 2.82 m widened at
  // once and 2.82 m on trial (the same path: the trial costs a lost filter nothing), all with
  // the run of eight alone; with recover_consistent_gated alone (a beacon's gated ranges that
  // repeat one innovation) 3.03 m; with both and the fit (the defaults) 2.72 m (2.97 before
  // round 28b).
  sim::SimRun run = sim::simulate(sim::auvLikeWorld(301, 500));
  for (size_t k = 250; k < 260; ++k) run.odometry[k].forward_m = run.odometry[k].lateral_m = 0.0;
  auto errorAfterGlitch = [&](int recover_after_gated, int trial_ranges, int consistent_gated = 0, bool fit = true) {
    EkfConfig config = surveyedBeacons(trial_ranges, consistent_gated);
    config.recover_after_gated = recover_after_gated;
    config.recover_consistent_fit = fit;
    const Outcome outcome = runEkf(run, config);
    const Path& path = outcome.trajectory;
    double sum = 0.0;
    for (size_t k = 300; k < path.size(); ++k)
      sum += std::hypot(path[k].x_m - run.ground_truth[k].x_m, path[k].y_m - run.ground_truth[k].y_m);
    return std::make_pair(sum / static_cast<double>(path.size() - 300), outcome.diagnostics);
  };
  const auto [never_m, never] = errorAfterGlitch(0, 0);
  const auto [at_once_m, at_once] = errorAfterGlitch(EkfConfig{}.recover_after_gated, 0);
  const auto [on_trial_m, on_trial] = errorAfterGlitch(EkfConfig{}.recover_after_gated, EkfConfig{}.recover_trial_ranges);
  // The consistency trigger alone, each run taken at its word (recover_consistent_fit off), as
  // round 20 measured it; the defaults have both triggers and the fit.
  const auto [consistent_m, consistent] = errorAfterGlitch(0, EkfConfig{}.recover_trial_ranges, EkfConfig{}.recover_consistent_gated, false);
  const auto [default_m, by_default] = errorAfterGlitch(EkfConfig{}.recover_after_gated, EkfConfig{}.recover_trial_ranges,
                                                        EkfConfig{}.recover_consistent_gated);
  std::printf("AUV-like seed 301, 10 steps without motion: never widened %.2f m, widened at once %.2f m, on trial %.2f m, "
              "by the consistency trigger alone %.2f m, the defaults %.2f m\n", never_m, at_once_m, on_trial_m, consistent_m, default_m);
  EXPECT_LT(consistent_m, 5.0);
  EXPECT_LT(default_m, 5.0);
  EXPECT_GT(never_m, 20.0);  // lost for good without a recovery: the test can fail
  EXPECT_LT(on_trial_m, 5.0);
  EXPECT_NEAR(on_trial_m, at_once_m, 0.5);
  EXPECT_GE(on_trial.at("starvation_recoveries"), 1.0);
  EXPECT_EQ(never.at("starvation_recoveries"), 0.0);
}

TEST(EkfRecovery, ABeaconWhoseGatedRangesRepeatOneInnovationFindsALostFilterItsWayBack) {
  // AUV-like seed 324 (the seed sweep's auv-sparse kind), surveyed beacons: by 150 s the filter
  // is 12 m off and sure of it (position sigma 2.5 m against 15 % odometry noise configured at
  // 2 %). Beacon 0's ranges are gated at -13.8, -12.3, -13.4, -12.0 m: one innovation, not
  // outliers. But a range to beacon 3 (the direction the filter is right in) or an outlier
  // that passes the gate comes between, so eight are never gated in a row; the heading then goes
  // 0.3-0.5 rad wrong and the path 160 m off. recover_consistent_gated widens at the fourth
  // agreeing gated range (on trial, like any widening). Measured: 65.67 m without it (110.45
  // before round 28b), 3.01 m with it, dead reckoning 19.04 m.
  const sim::SimRun run = sim::simulate(sim::auvLikeWorld(324, 500));
  const double dr_m = deadReckoningError(run);
  const Outcome without = runEkf(run, surveyedBeacons(EkfConfig{}.recover_trial_ranges, 0));
  const Outcome with = runEkf(run, surveyedBeacons());
  const double without_m = without.error_m, with_m = with.error_m;
  std::printf("AUV-like seed 324, beacons: without the consistency trigger %.2f m, with it %.2f m, dead reckoning %.2f m\n",
              without_m, with_m, dr_m);
  EXPECT_GT(without_m, 1.25 * dr_m);  // the failure it is for: the test can fail
  EXPECT_LT(with_m, 0.3 * dr_m);
  EXPECT_GE(with.diagnostics.at("starvation_recoveries"), 1.0);
}

// The seed sweep's nlos30-episodes: 30 % NLOS in stretches of 20 s on average.
sim::SimRun nlosInStretches(int seed) {
  sim::SimConfig world = sim::nlos30LawnMowerWorld(seed, 3000);
  world.outlier_episode_s = 20.0;
  return sim::simulate(world);
}

// The surveyed-beacon filter on one run with a rule turned off (first) and with the defaults.
template <typename TurnOff>
std::pair<Outcome, Outcome> withoutAndWith(const sim::SimRun& run, TurnOff turn_off) {
  EkfConfig off = surveyedBeacons();
  turn_off(off);
  return {runEkf(run, off), runEkf(run, surveyedBeacons())};
}

TEST(EkfRecovery, ABeaconOutOfSightForAWhileIsNotTakenForALostFilter) {
  // NLOS in stretches (the seed sweep's nlos30-episodes, seed 310): a beacon behind a wall for
  // ~20 s gives ~7 ranges in a row, each long by one excess, while the other beacons' ranges pass
  // with none. The consistency trigger took that for a lost filter and widened onto it (the trial
  // kept the widening: the blocked beacon's next ranges fit it). recover_consistent_fit asks
  // that one position error explain the repeated innovation and the other beacons' applied ones.
  const sim::SimRun run = nlosInStretches(310);
  const double dr_m = deadReckoningError(run);
  const auto [without, with] = withoutAndWith(run, [](EkfConfig& config) { config.recover_consistent_fit = false; });
  std::printf("NLOS in stretches, seed 310, beacons: the run alone %.2f m, one position error %.2f m, dead reckoning %.2f m\n",
              without.error_m, with.error_m, dr_m);
  EXPECT_GT(without.error_m, 1.5 * dr_m);  // the failure it is for: the test can fail
  EXPECT_LT(with.error_m, 0.5 * dr_m);
  EXPECT_GE(with.diagnostics.at("consistent_gated_runs_declined"), 1.0);
  EXPECT_EQ(without.diagnostics.at("consistent_gated_runs_declined"), 0.0);
}

TEST(EkfRecovery, ABeaconOffsetThatTookUpAnNlosStretchIsReopened) {
  // NLOS in stretches (the seed sweep's nlos30-episodes, seed 301): early in the run, while its
  // range offset's prior (1.5 m) still widens the gate, a stretch of one beacon's ranges long by
  // one excess agree with each other as a real offset would, and the offset takes the excess up.
  // Its line-of-sight ranges are then short by it, gated in a row, and the consistency trigger
  // widened the pose onto them (7 m off for 30 s). recover_offset_reopen re-opens that offset
  // instead, and its next range pulls it back.
  const sim::SimRun run = nlosInStretches(301);
  const double dr_m = deadReckoningError(run);
  const auto [without, with] = withoutAndWith(run, [](EkfConfig& config) { config.recover_offset_reopen = false; });
  auto largestOffset = [](const Outcome& outcome) {
    double largest_m = 0.0;
    for (const auto& [key, value] : outcome.diagnostics)
      if (key.rfind("range_offset_beacon_", 0) == 0) largest_m = std::max(largest_m, std::abs(value));
    return largest_m;
  };
  std::printf("NLOS in stretches, seed 301, beacons: pose widened %.2f m (largest beacon offset %.2f m), "
              "offset re-opened %.2f m (%.2f m), dead reckoning %.2f m\n",
              without.error_m, largestOffset(without), with.error_m, largestOffset(with), dr_m);
  EXPECT_GT(without.error_m, 0.5);  // the failure it is for: the test can fail
  EXPECT_GT(largestOffset(without), 2.5);
  EXPECT_LT(with.error_m, 0.15);
  EXPECT_LT(largestOffset(with), 1.0);
  EXPECT_GE(with.diagnostics.at("beacon_offsets_reopened"), 1.0);
  EXPECT_EQ(without.diagnostics.at("beacon_offsets_reopened"), 0.0);
}

TEST(EkfRecovery, AWideningThatWinsByChanceIsDeclined) {
  // NLOS in stretches, seed 1009 (the README sweep's), surveyed beacons. At 34 s a run of gated
  // ranges set off a trial on a filter 0.13 m off; the widened re-run scored the next 32 ranges
  // 1.7 nats better (it had found a stretch to fit) and was kept: 12-18 m off for the next minute,
  // the run 1.62 m, dead reckoning's. The widening must now pass a likelihood-ratio test at the
  // 5 % level (2 x 1.7 < 3.84): measured 0.12 m.
  const sim::SimRun run = nlosInStretches(1009);
  const double dr_m = deadReckoningError(run);
  const Outcome outcome = runEkf(run, surveyedBeacons());
  std::printf("NLOS in stretches, seed 1009, beacons: %.2f m (dead reckoning %.2f m), %.0f widenings declined\n", outcome.error_m,
              dr_m, outcome.diagnostics.at("starvation_recoveries_declined"));
  EXPECT_LT(outcome.error_m, 0.3);  // issue 15's 30 % NLOS target with beacons
  EXPECT_GT(dr_m, 1.5);
  EXPECT_GE(outcome.diagnostics.at("starvation_recoveries_declined"), 1.0);
}

TEST(EkfRecovery, BeaconsPlacedFromTheRangesNeverSetOffTheConsistencyTrigger) {
  // From the start pose a beacon that keeps gating one innovation is more likely off itself:
  // half the ranges NLOS, seed 307, set it off a dozen times (0.27 -> 1.53 m) before it was kept
  // to surveyed beacons. The start-pose run is the one without it, bit for bit.
  const sim::SimRun run = sim::simulate(sim::nlos50LawnMowerWorld(307, 3000));
  EkfConfig off;
  off.recover_consistent_gated = 0;
  const Path without = runEkf(run, off).trajectory, with = runEkf(run, EkfConfig{}).trajectory;
  ASSERT_EQ(without.size(), with.size());
  for (size_t k = 0; k < with.size(); ++k) {
    EXPECT_EQ(without[k].x_m, with[k].x_m);
    EXPECT_EQ(without[k].y_m, with[k].y_m);
  }
  EXPECT_LT(meanError(with, run.ground_truth), 0.5);
}

TEST(EkfRecovery, ATrialThatOutlastsItsRangesIsDecidedAndRepeats) {
  // With a trial longer than the ranges that come (recover_trial_ranges 100000), each trial holds
  // the history (snapshots released but for its first step) until init_window_s has passed or the
  // run ends, and is decided there. The counts still add up and the run repeats bit for bit.
  const sim::SimRun run = sim::simulate(sim::goatsLikeWorld(313, 210));
  const Outcome first = runWithSurveyedBeacons(run, 100000);
  const Outcome again = runWithSurveyedBeacons(run, 100000);
  std::printf("GOATS-like seed 313, trials of 100000 ranges: %.2f m\n", first.error_m);
  EXPECT_GE(first.diagnostics.at("starvation_recoveries") + first.diagnostics.at("starvation_recoveries_declined"), 1.0);
  EXPECT_EQ(first.accepted + first.rejected, static_cast<int64_t>(run.ranges.size()));
  EXPECT_TRUE(std::isfinite(first.error_m));
  ASSERT_EQ(again.trajectory.size(), first.trajectory.size());
  for (size_t k = 0; k < again.trajectory.size(); ++k) EXPECT_EQ(again.trajectory[k].x_m, first.trajectory[k].x_m);
}

TEST(EkfRecovery, WithoutAStarvationRunNothingChanges) {
  // A clean drifting figure-8 never gates eight in a row: the trial never opens and the result
  // is the one without it, bit for bit.
  const sim::SimRun run = sim::simulate(sim::gyroDriftFigure8World(201, 1500));
  const Outcome at_once = runWithSurveyedBeacons(run, 0);
  const Outcome on_trial = runWithSurveyedBeacons(run, EkfConfig{}.recover_trial_ranges);
  EXPECT_EQ(on_trial.diagnostics.at("starvation_recoveries"), 0.0);
  EXPECT_EQ(on_trial.diagnostics.at("starvation_recoveries_declined"), 0.0);
  ASSERT_EQ(at_once.trajectory.size(), on_trial.trajectory.size());
  for (size_t k = 0; k < at_once.trajectory.size(); ++k) EXPECT_EQ(at_once.trajectory[k].x_m, on_trial.trajectory[k].x_m);
}

TEST(EkfRecovery, ALostBeaconPlacedFromTheRangesIsMovedWhereItsGatedRangesPlaceIt) {
  // The racetrack with a drifting gyro, seed 302, from the start pose: the calibrated re-run
  // places beacon 2 (5 m beside the first straight, near its end) 7.5 m off, towards its mirror
  // image, and every later range to it is gated. Its gated ranges, solved alone once 12 come in
  // a row, place it on the right side, and it is moved there (lost_beacon_gated_ranges).
  const sim::SimRun run = sim::simulate(sim::racetrackWorld(302, 6500));
  EkfConfig off;
  off.lost_beacon_gated_ranges = 0;
  const Outcome before = runEkf(run, off);
  const Outcome after = runEkf(run, EkfConfig{});
  const Outcome again = runEkf(run, EkfConfig{});
  std::printf("lost beacon: gated %.0f -> %.0f of %zu, moved %.0f, error %.2f -> %.2f m\n",
              before.diagnostics.at("ranges_gated"), after.diagnostics.at("ranges_gated"), run.ranges.size(),
              after.diagnostics.at("beacons_moved"), before.error_m, after.error_m);
  EXPECT_EQ(before.diagnostics.at("beacons_moved"), 0.0);
  EXPECT_GT(before.diagnostics.at("ranges_gated"), 200.0);
  EXPECT_EQ(after.diagnostics.at("beacons_moved"), 1.0);
  EXPECT_LT(after.diagnostics.at("ranges_gated"), 30.0);
  EXPECT_LT(after.error_m, before.error_m - 0.3);
  ASSERT_EQ(after.trajectory.size(), again.trajectory.size());
  for (size_t k = 0; k < after.trajectory.size(); ++k) {
    EXPECT_EQ(after.trajectory[k].x_m, again.trajectory[k].x_m) << k;
    EXPECT_EQ(after.trajectory[k].y_m, again.trajectory[k].y_m) << k;
  }
}

TEST(EkfRecovery, ABeaconPlacedAtItsMirrorImageIsMovedBack) {
  // 30 % NLOS in stretches, seed 312, from the start pose: beacon 0 (9.6 m below the first lane)
  // enters at its mirror image across the lawn mower, 30 m off, and its ranges are gated from
  // then on (29 in a row by 227 s). Solved alone they place it within a metre of the truth.
  sim::SimConfig world = sim::nlos30LawnMowerWorld(312, 3000);
  world.outlier_episode_s = 20.0;
  const sim::SimRun run = sim::simulate(world);
  const Beacon* truth = nullptr;
  for (const Beacon& b : run.beacons)
    if (b.id == 0) truth = &b;
  ASSERT_NE(truth, nullptr);
  auto beaconError = [&](const EkfConfig& config, double* error_m, std::map<std::string, double>* diagnostics) {
    EkfSlam ekf(config);
    test::feed(run, ekf, true);
    Path trajectory;
    ASSERT_TRUE(ekf.trajectory(true, &trajectory));
    *error_m = meanError(trajectory, run.ground_truth);
    *diagnostics = ekf.diagnostics();
    for (const Beacon& b : ekf.currentMap())
      if (b.id == 0) (*diagnostics)["beacon_0_error_m"] = std::hypot(b.x_m - truth->x_m, b.y_m - truth->y_m);
  };
  EkfConfig off;
  off.lost_beacon_gated_ranges = 0;
  double before_m = 0.0, after_m = 0.0;
  std::map<std::string, double> before, after;
  beaconError(off, &before_m, &before);
  beaconError(EkfConfig{}, &after_m, &after);
  std::printf("mirror: beacon 0 %.1f -> %.2f m off, moved %.0f, gated %.0f -> %.0f, path %.2f -> %.2f m\n",
              before.at("beacon_0_error_m"), after.at("beacon_0_error_m"), after.at("beacons_moved"),
              before.at("ranges_gated"), after.at("ranges_gated"), before_m, after_m);
  EXPECT_GT(before.at("beacon_0_error_m"), 20.0);
  EXPECT_EQ(after.at("beacons_moved"), 1.0);
  EXPECT_LT(after.at("beacon_0_error_m"), 1.0);
  EXPECT_LT(after_m, 0.5);
  EXPECT_GT(before_m, 1.5);
}

}  // namespace
}  // namespace ekf
}  // namespace roam
