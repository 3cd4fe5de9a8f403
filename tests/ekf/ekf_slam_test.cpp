// EkfSlam on seeded synthetic runs: exact recovery, consistency (NEES), the mirror wait,
// outlier gating, repeatability and config errors.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "ekf_config.hpp"
#include "ekf_slam.hpp"
#include "feed.hpp"
#include "sim.hpp"

namespace roam {
namespace ekf {
namespace {

constexpr double kRecoveryTolerance_m = 1e-6;  // the noise-free bound

sim::SimConfig noiseFreeLawnMower() {
  sim::SimConfig c;
  c.seed = 3;
  c.num_steps = 500;         // 100 s: a 20 m lane takes 100 steps, each half-turn ~39
  c.area_width_m = 20.0;
  c.area_height_m = 15.0;
  c.num_beacons = 4;
  c.schedule = sim::RangeSchedule::kRoundRobin;
  c.range_rate_hz = 2.0;
  return c;
}

double maxPathError(const Path& estimate, const Path& truth) {
  double worst_m = 0.0;
  EXPECT_EQ(estimate.size(), truth.size());
  for (size_t k = 0; k < std::min(estimate.size(), truth.size()); ++k) {
    EXPECT_EQ(estimate[k].utime, truth[k].utime);
    worst_m = std::max(worst_m, std::hypot(estimate[k].x_m - truth[k].x_m, estimate[k].y_m - truth[k].y_m));
    worst_m = std::max(worst_m, std::abs(wrapAngle(estimate[k].heading_rad - truth[k].heading_rad)));
  }
  return worst_m;
}

double maxBeaconError(const Map& estimate, const Map& truth) {
  double worst_m = 0.0;
  EXPECT_EQ(estimate.size(), truth.size());
  for (const Beacon& b : estimate) {
    for (const Beacon& t : truth)
      if (t.id == b.id) worst_m = std::max(worst_m, std::hypot(b.x_m - t.x_m, b.y_m - t.y_m));
  }
  return worst_m;
}

TEST(EkfSlam, NoiseFreeStartPoseRecoversPathAndBeacons) {
  const sim::SimRun run = sim::simulate(noiseFreeLawnMower());
  EkfSlam ekf(EkfConfig{});  // defaults: anchor = start_pose, shared range bias
  test::feed(run, ekf);
  Path path;
  ASSERT_TRUE(ekf.trajectory(true, &path));
  // Exact odometry integrates exactly; exact ranges give the exact beacon in the batch solve and
  // zero innovations afterwards, so nothing moves the state off the truth.
  EXPECT_LT(maxPathError(path, run.ground_truth), kRecoveryTolerance_m);
  EXPECT_LT(maxBeaconError(ekf.currentMap(), run.beacons), kRecoveryTolerance_m);
  EXPECT_NEAR(ekf.filter().scale(), 1.0, 1e-9);
  EXPECT_EQ(ekf.rangesRejected(), 0);
  EXPECT_EQ(ekf.diagnostics().at("beacons_initialised"), 4.0);
}

TEST(EkfSlam, NoiseFreeRangesBetweenStepsUseTheInterpolatedPose) {
  // Ranges stamped mid-step: the motion model moves straight along theta_k during step k, so
  // the true position at fraction a is p_k + a d_k (cos theta_k, sin theta_k).
  sim::SimRun run = sim::simulate(noiseFreeLawnMower());
  run.ranges.clear();
  const double fraction = 0.3;
  for (size_t k = 0; k + 1 < run.ground_truth.size(); ++k) {
    const Pose& p = run.ground_truth[k];
    const double d = run.odometry[k].forward_m;
    const Beacon& b = run.beacons[k % run.beacons.size()];
    Range r;
    r.utime = p.utime + static_cast<int64_t>(fraction * (run.odometry[k].utime - p.utime));
    r.beacon_id = b.id;
    r.range_m = std::hypot(b.x_m - (p.x_m + fraction * d * std::cos(p.heading_rad)),
                           b.y_m - (p.y_m + fraction * d * std::sin(p.heading_rad)));
    run.ranges.push_back(r);
  }
  EkfSlam ekf(EkfConfig{});
  test::feed(run, ekf);
  Path path;
  ASSERT_TRUE(ekf.trajectory(true, &path));
  EXPECT_LT(maxPathError(path, run.ground_truth), kRecoveryTolerance_m);
  EXPECT_LT(maxBeaconError(ekf.currentMap(), run.beacons), kRecoveryTolerance_m);
}

TEST(EkfSlam, NoiseFreeRangeBearingRecovers) {
  sim::SimConfig c = noiseFreeLawnMower();
  c.bearing = true;
  const sim::SimRun run = sim::simulate(c);
  EkfSlam ekf(EkfConfig{});
  test::feed(run, ekf);
  Path path;
  ASSERT_TRUE(ekf.trajectory(true, &path));
  EXPECT_LT(maxPathError(path, run.ground_truth), kRecoveryTolerance_m);
  EXPECT_LT(maxBeaconError(ekf.currentMap(), run.beacons), kRecoveryTolerance_m);
}

TEST(EkfSlam, NoiseFreeBeaconsAnchorRecovers) {
  const sim::SimRun run = sim::simulate(noiseFreeLawnMower());
  EkfConfig config;
  config.anchor = EkfConfig::Anchor::kBeacons;
  EkfSlam ekf(config);
  test::feed(run, ekf);
  Path path;
  ASSERT_TRUE(ekf.trajectory(true, &path));
  EXPECT_LT(maxPathError(path, run.ground_truth), kRecoveryTolerance_m);
  EXPECT_LT(maxBeaconError(ekf.currentMap(), run.beacons), kRecoveryTolerance_m);
}

// ---- consistency ----------------------------------------------------------------------------

// Noisy run whose noise the filter's config matches exactly (sim: sigma_d = rel d, constant
// heading sigma per step, Gaussian ranges), anchored on surveyed beacons that carry the stated
// survey error, with the start pose given with its stated error.
struct NoisyCase {
  sim::SimRun run;
  EkfConfig config;
};

NoisyCase noisyBeaconsCase(uint64_t seed, int num_steps = 300) {
  sim::SimConfig c;
  c.seed = seed;
  c.num_steps = num_steps;  // 300: 60 s
  c.path = sim::PathKind::kRandomWalk;
  c.area_width_m = 30.0;
  c.area_height_m = 30.0;
  c.num_beacons = 4;
  c.schedule = sim::RangeSchedule::kRoundRobin;
  c.range_rate_hz = 2.0;
  c.odo_distance_sigma_rel = 0.02;
  c.odo_heading_sigma_rad = 0.005;
  c.range_sigma_m = 0.3;
  NoisyCase out{sim::simulate(c), EkfConfig{}};
  out.config.anchor = EkfConfig::Anchor::kBeacons;
  out.config.odo_distance_sigma_rel = 0.02;
  out.config.odo_distance_sigma_m = 0.0;
  out.config.odo_heading_sigma_rel = 0.0;
  out.config.odo_heading_sigma_per_sqrt_m = 0.0;
  out.config.odo_heading_sigma_rad = 0.005;
  out.config.range_sigma_m = 0.3;
  // The consistency of the base filter against the simulated noise: no odometry calibration
  // (the simulation has none; calibration has its own tests below).
  out.config.estimate_odometry_calibration = false;
  // Survey and start errors drawn with the sigmas the filter is told.
  std::mt19937_64 rng(seed + 1000);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (Beacon& b : out.run.beacons) {
    b.x_m += out.config.beacon_sigma_m * normal(rng);
    b.y_m += out.config.beacon_sigma_m * normal(rng);
  }
  out.run.start.x_m += out.config.start_sigma_m * normal(rng);
  out.run.start.y_m += out.config.start_sigma_m * normal(rng);
  out.run.start.heading_rad += out.config.start_heading_sigma_rad * normal(rng);
  return out;
}

double poseNees(const Pose& estimate, const Pose& truth) {
  Eigen::Matrix3d P;
  for (int i = 0; i < 9; ++i) P(i / 3, i % 3) = estimate.covariance[i];
  const Eigen::Vector3d error(estimate.x_m - truth.x_m, estimate.y_m - truth.y_m,
                              wrapAngle(estimate.heading_rad - truth.heading_rad));
  return error.dot(P.ldlt().solve(error));
}

// Average over R = 50 runs of the 3-dof pose NEES at each step, and the fraction of steps whose
// average is inside the 95 % band: R * average ~ chi2(3 R = 150) if the filter is consistent,
// with quantiles 117.98 and 185.80 (Wilson-Hilferty: 150 (1 - 2/1350 -+ 1.96 sqrt(2/1350))^3),
// i.e. the band [2.360, 3.716] for the average.
struct NeesSummary {
  double mean = 0.0;
  double fraction_inside = 0.0;
};

NeesSummary poseNeesOver50Runs(const std::string& anchor) {
  constexpr int kRuns = 50;
  constexpr double kLow = 117.98 / kRuns, kHigh = 185.80 / kRuns;
  std::vector<double> sum;
  for (int seed = 1; seed <= kRuns; ++seed) {
    NoisyCase c = noisyBeaconsCase(static_cast<uint64_t>(seed));
    c.config.anchor = anchor == "beacons" ? EkfConfig::Anchor::kBeacons : EkfConfig::Anchor::kStartPose;
    if (anchor == "start_pose") c.run.start = c.run.ground_truth.front();
    EkfSlam ekf(c.config);
    test::feed(c.run, ekf);
    const Path& path = ekf.path();
    EXPECT_EQ(path.size(), c.run.ground_truth.size());
    sum.resize(path.size(), 0.0);
    for (size_t k = 1; k < path.size(); ++k) sum[k] += poseNees(path[k], c.run.ground_truth[k]);
  }
  NeesSummary out;
  int inside = 0;
  for (size_t k = 1; k < sum.size(); ++k) {  // step 0: the start pose (zero covariance)
    const double average = sum[k] / kRuns;
    inside += (average >= kLow && average <= kHigh) ? 1 : 0;
    out.mean += average / static_cast<double>(sum.size() - 1);
  }
  out.fraction_inside = static_cast<double>(inside) / static_cast<double>(sum.size() - 1);
  std::printf("anchor = %s: pose NEES mean %.3f (3 if consistent), fraction of steps inside [%.3f, %.3f]: %.3f\n",
              anchor.c_str(), out.mean, kLow, kHigh, out.fraction_inside);
  return out;
}

TEST(EkfSlam, PoseNeesInsideTheChiSquareBandOver50Runs) {
  // Measured: mean 2.70, 86 % of the 300 steps inside (slightly conservative: the scale and
  // offset states and the start prior are not exercised by the simulated ranges).
  constexpr double kMinFractionInside = 0.80;
  const NeesSummary beacons = poseNeesOver50Runs("beacons");
  EXPECT_GE(beacons.fraction_inside, kMinFractionInside);
}

TEST(EkfSlam, StartPosePoseNeesIsNearTheBand) {
  // Unknown beacons: measured mean 3.54, 70 % of steps inside the band — mildly overconfident
  // after beacons enter (the known EKF-SLAM inconsistency). Asserted: mean NEES within 1.5x of
  // the consistent value 3, and most steps inside.
  constexpr double kMaxMeanNees = 4.5;
  constexpr double kMinFractionInside = 0.60;
  const NeesSummary start_pose = poseNeesOver50Runs("start_pose");
  EXPECT_LT(start_pose.mean, kMaxMeanNees);
  EXPECT_GE(start_pose.fraction_inside, kMinFractionInside);
}

TEST(EkfSlam, StartPoseNoisyRunsBeatDeadReckoningWithAConsistentMap) {
  // Start-pose anchor, 4 unknown beacons, the stated noise, 180 s random walks (5 seeds).
  // Map consistency: a run's 4 beacon NEES values sum to chi2(8) if consistent; its 99.9 %
  // quantile is 26.12. Measured (seeds 1-5): EKF / dead-reckoning mean error 0.78, 0.32, 0.20,
  // 0.53, 0.51; NEES sums 69.5, 9.8, 4.2, 13.9, 5.3. Seed 1 (the largest early heading drift)
  // shows the known EKF-SLAM overconfidence in the frame's rotation, hence "4 of 5 runs".
  constexpr int kSeeds = 5;
  constexpr double kMaxMeanErrorRatio = 0.9;        // each run: EKF beats dead reckoning
  constexpr double kMaxAverageErrorRatio = 0.6;     // on average by a wide margin
  constexpr double kRunNeesSum999 = 26.12;
  constexpr int kMinConsistentRuns = 4;
  int consistent_runs = 0;
  double ratio_sum = 0.0;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    NoisyCase c = noisyBeaconsCase(static_cast<uint64_t>(seed), 900);
    c.run.start = c.run.ground_truth.front();
    c.config.anchor = EkfConfig::Anchor::kStartPose;
    EkfSlam ekf(c.config);
    test::feed(c.run, ekf);
    double ekf_sum_m = 0.0, dr_sum_m = 0.0;
    Pose dr = c.run.start;
    for (size_t k = 0; k < ekf.path().size(); ++k) {
      if (k > 0) {
        const Odometry& o = c.run.odometry[k - 1];
        dr.x_m += o.forward_m * std::cos(dr.heading_rad);
        dr.y_m += o.forward_m * std::sin(dr.heading_rad);
        dr.heading_rad += o.delta_heading_rad;
      }
      const Pose& truth = c.run.ground_truth[k];
      ekf_sum_m += std::hypot(ekf.path()[k].x_m - truth.x_m, ekf.path()[k].y_m - truth.y_m);
      dr_sum_m += std::hypot(dr.x_m - truth.x_m, dr.y_m - truth.y_m);
    }
    double nees = 0.0;
    for (const Beacon& b : ekf.currentMap()) {
      for (const Beacon& t : c.run.beacons) {
        if (t.id != b.id) continue;
        const Eigen::Vector2d e(b.x_m - t.x_m, b.y_m - t.y_m);
        Eigen::Matrix2d P;
        P << b.covariance[0], b.covariance[1], b.covariance[2], b.covariance[3];
        nees += e.dot(P.ldlt().solve(e));
      }
    }
    const double ratio = ekf_sum_m / dr_sum_m;
    std::printf("seed %d: ekf mean error %.3f m, dead reckoning %.3f m (ratio %.2f), beacon NEES sum %.2f\n", seed,
                ekf_sum_m / ekf.path().size(), dr_sum_m / ekf.path().size(), ratio, nees);
    EXPECT_EQ(ekf.currentMap().size(), 4u) << "seed " << seed;
    EXPECT_LT(ratio, kMaxMeanErrorRatio) << "seed " << seed;
    consistent_runs += nees < kRunNeesSum999 ? 1 : 0;
    ratio_sum += ratio;
  }
  EXPECT_LT(ratio_sum / kSeeds, kMaxAverageErrorRatio);
  EXPECT_GE(consistent_runs, kMinConsistentRuns);
}

// ---- the mirror wait -----------------------------------------------------------------------

TEST(EkfSlam, MirrorAmbiguousBeaconWaitsForTheTurn) {
  // The robot drives a 30 m straight lane along +x from the origin (150 steps of 0.2 m), then
  // turns left. A beacon at (15, 8) seen from the x axis has a mirror twin at (15, -8) that fits
  // every range equally well, so it must stay pending until the turn breaks the symmetry.
  sim::SimConfig c;
  c.seed = 5;
  c.num_steps = 260;
  c.area_width_m = 30.0;
  c.area_height_m = 10.0;
  c.lane_spacing_m = 5.0;
  Beacon beacon;
  beacon.id = 9;
  beacon.x_m = 15.0;
  beacon.y_m = 8.0;
  c.beacons = {beacon};
  c.range_sigma_m = 0.1;
  const sim::SimRun run = sim::simulate(c);
  constexpr size_t kStraightSteps = 150;
  constexpr size_t kHalfTurnSteps = 39;  // a half circle of radius 2.5 m in 0.2 m steps: 39.3

  EkfSlam ekf(EkfConfig{});
  ekf.setInitialPose(run.start);
  size_t r = 0;
  size_t initialised_at = 0;
  for (size_t k = 0; k < run.odometry.size(); ++k) {
    while (r < run.ranges.size() && run.ranges[r].utime < run.odometry[k].utime) ekf.addRange(run.ranges[r++]);
    ekf.addOdometry(run.odometry[k]);
    if (ekf.currentMap().empty()) {
      EXPECT_EQ(ekf.pendingBeacons().count(9), 1u);
    } else if (initialised_at == 0) {
      initialised_at = k + 1;
    }
  }
  std::printf("mirror-ambiguous beacon initialised after step %zu (turn starts after %zu)\n",
              initialised_at, kStraightSteps);
  EXPECT_GT(initialised_at, kStraightSteps);
  EXPECT_LE(initialised_at, kStraightSteps + kHalfTurnSteps);  // resolved during the turn
  ASSERT_EQ(ekf.currentMap().size(), 1u);
  // And on the right side of the lane (range noise 0.1 m: well within 0.5 m).
  constexpr double kBeaconTolerance_m = 0.5;
  EXPECT_NEAR(ekf.currentMap()[0].x_m, 15.0, kBeaconTolerance_m);
  EXPECT_NEAR(ekf.currentMap()[0].y_m, 8.0, kBeaconTolerance_m);
}

// ---- gating ---------------------------------------------------------------------------------

TEST(EkfSlam, OutlierIsGatedCountedAndChangesNothing) {
  NoisyCase c = noisyBeaconsCase(7);
  // One range late in the run, 20 m too long; the reference run simply lacks that range.
  const size_t kOutlier = c.run.ranges.size() / 2;
  sim::SimRun with_outlier = c.run, without = c.run;
  with_outlier.ranges[kOutlier].range_m += 20.0;
  without.ranges.erase(without.ranges.begin() + static_cast<long>(kOutlier));

  EkfSlam a(c.config), b(c.config);
  test::feed(with_outlier, a);
  test::feed(without, b);
  EXPECT_EQ(a.rangesRejected(), b.rangesRejected() + 1);
  EXPECT_EQ(a.rangesAccepted(), b.rangesAccepted());
  EXPECT_EQ(a.rejections().at("range: gated: Mahalanobis distance beyond gate_probability"),
            b.rejections().count("range: gated: Mahalanobis distance beyond gate_probability")
                ? b.rejections().at("range: gated: Mahalanobis distance beyond gate_probability") + 1
                : 1);
  // The range sits at a pose time, so no step is split: the two runs are identical.
  ASSERT_EQ(a.path().size(), b.path().size());
  for (size_t k = 0; k < a.path().size(); ++k) {
    EXPECT_EQ(a.path()[k].x_m, b.path()[k].x_m);
    EXPECT_EQ(a.path()[k].y_m, b.path()[k].y_m);
    EXPECT_EQ(a.path()[k].heading_rad, b.path()[k].heading_rad);
  }
}

// ---- repeatability and config ----------------------------------------------------------------

TEST(EkfSlam, RepeatRunsAreBitIdentical) {
  NoisyCase c = noisyBeaconsCase(11);
  c.config.anchor = EkfConfig::Anchor::kStartPose;
  EkfSlam a(c.config), b(c.config);
  test::feed(c.run, a);
  test::feed(c.run, b);
  ASSERT_EQ(a.path().size(), b.path().size());
  for (size_t k = 0; k < a.path().size(); ++k) {
    EXPECT_EQ(a.path()[k].x_m, b.path()[k].x_m);
    EXPECT_EQ(a.path()[k].covariance, b.path()[k].covariance);
  }
  EXPECT_EQ(a.filter().mean(), b.filter().mean());
}

TEST(EkfSlam, TheReRunHistoryKeepsASnapshotOnlyWhereAReRunCanStart) {
  // Start pose, 50 Hz odometry, 16 beacons ranged round robin at 5 Hz, 30 % of the ranges outliers:
  // beacons stay pending for seconds, holding the history (every step since the first pending
  // sighting). A re-run reads the snapshot (state and covariance) of step 0, of a pending
  // beacon's sighting or of the starvation trial's step only, so at most one step in ten (those
  // with a range) keeps one, plus those two.
  sim::SimConfig c = sim::nlos30LawnMowerWorld(5, 6000);
  c.dt_s = 0.02;
  c.num_beacons = 16;
  c.range_rate_hz = 5.0;
  c.odo_heading_sigma_rad = 0.00095;  // the same heading noise per second as at 5 Hz
  c.outlier_min_m = -30.0;
  c.outlier_max_m = 30.0;
  const sim::SimRun run = sim::simulate(c);
  EkfSlam ekf{EkfConfig{}};
  ekf.setInitialPose(run.start);
  size_t most_steps = 0, most_snapshots = 0;
  size_t r = 0;
  for (const Odometry& odometry : run.odometry) {
    while (r < run.ranges.size() && run.ranges[r].utime < odometry.utime) ekf.addRange(run.ranges[r++]);
    ekf.addOdometry(odometry);
    most_steps = std::max(most_steps, ekf.historySteps());
    most_snapshots = std::max(most_snapshots, ekf.historySnapshots());
  }
  ekf.finish();
  std::printf("history: up to %zu steps held, %zu snapshots kept, %zu beacons initialised\n", most_steps, most_snapshots,
              ekf.initialisations().size());
  EXPECT_GE(most_steps, 1000u);  // the history is held (so the bound below can fail)
  EXPECT_GE(most_snapshots, 10u);
  EXPECT_LE(most_snapshots, most_steps / 10 + 2);
  EXPECT_GE(ekf.initialisations().size(), 4u);  // re-runs from pending beacons' sightings were made
}

TEST(EkfConfig, BadValuesNameTheKey) {
  auto parse = [](KeyValues values) {
    EkfConfig config;
    Options options(std::move(values));
    addEkfOptions(options, &config);
    options.parse();
    return config;
  };
  EXPECT_EQ(parse({{"anchor", "beacons"}, {"range_sigma_m", "0.5"}}).range_sigma_m, 0.5);
  try {
    parse({{"anchor", "beacon"}});
    FAIL() << "expected a ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.key(), "anchor");
    EXPECT_NE(std::string(e.what()).find("did you mean 'beacons'"), std::string::npos) << e.what();
  }
  try {
    parse({{"range_sigma", "0.3"}});
    FAIL() << "expected a ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("range_sigma_m"), std::string::npos) << e.what();
  }
  try {
    parse({{"beacon_range_offset_sigma_m", "-1"}});
    FAIL() << "expected a ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.key(), "beacon_range_offset_sigma_m");
  }
  EXPECT_EQ(parse({{"beacon_range_offset_sigma_m", "0"}}).beacon_range_offset_sigma_m, 0.0);  // 0: off
  try {
    parse({{"gate_probability", "1.5"}});
    FAIL() << "expected a ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.key(), "gate_probability");
  }
  // The internal constants are not keys (README, "Internal constants").
  try {
    parse({{"init_max_ranges", "5"}});
    FAIL() << "expected a ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.key(), "init_max_ranges");
    EXPECT_NE(std::string(e.what()).find("unknown key"), std::string::npos) << e.what();
  }
  // A core built from a struct meets the same declared checks (checkConfig), naming the key.
  EkfConfig bad;
  bad.translation_noise_models = 0;
  try {
    EkfSlam ekf{bad};
    FAIL() << "expected a ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.key(), "translation_noise_models");
    EXPECT_STREQ(e.what(), "translation_noise_models: expected a value >= 1, got '0'");
  }
  bad = EkfConfig{};
  bad.range_bias = static_cast<EkfConfig::RangeBias>(5);
  EXPECT_THROW(EkfSlam{bad}, ConfigError);
}

}  // namespace
}  // namespace ekf
}  // namespace roam
