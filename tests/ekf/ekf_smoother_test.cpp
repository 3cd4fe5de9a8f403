// The EKF's backward smoother (ekf_smoother.hpp): exact against a stochastic clone of a pose
// carried through the same filter, and on seeded gyro-drift runs through EkfSlam.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "ekf_config.hpp"
#include "ekf_filter.hpp"
#include "ekf_slam.hpp"
#include "ekf_smoother.hpp"
#include "feed.hpp"
#include "sim.hpp"

namespace roam {
namespace ekf {
namespace {

constexpr double kCloneTolerance = 1e-9;

SmootherNode nodeOf(const EkfFilter& filter, std::vector<SmootherOperation> before) {
  SmootherNode node;
  node.before = std::move(before);
  node.pose = filter.mean().head<3>();
  node.pose_rows = filter.covariance().topRows(3);
  return node;
}

// The clone tests' filter: a pose with its range bias and odometry calibration, and three beacons
// 0.36 m off the truth (beacon 0 with its own range offset, prior sigma first_offset_sigma_m).
const Eigen::Vector2d kBeacons[3] = {{10.0, 0.0}, {0.0, 10.0}, {-8.0, -6.0}};

EkfFilter threeBeaconFilter(double first_offset_sigma_m) {
  EkfFilter filter;
  EkfCalibrationPrior calibration;
  calibration.estimated = true;
  calibration.distance_scale_sigma = 0.02;
  calibration.heading_rate_bias_sigma_rad_s = 0.01;
  filter.reset(Eigen::Vector3d(0.0, 0.0, 0.1), Eigen::Vector3d(0.01, 0.01, 0.001).asDiagonal(), true, 0.05, 0.2,
               calibration);
  for (int i = 0; i < 3; ++i)
    filter.addBeacon(i, kBeacons[i] + Eigen::Vector2d(0.3, -0.2), 0.25 * Eigen::Matrix2d::Identity(), i == 0 ? first_offset_sigma_m : 0.0);
  return filter;
}

// A stochastic clone: the pose's (x, y) appended to the state as "beacon" kCloneId with the pose's
// covariance and cross-covariances. Nothing predicts or observes it, so the filter runs exactly as
// without it, and at the end it holds E[x, y | every range] at the step it was taken.
constexpr int kCloneId = 99;

void clonePose(EkfFilter* filter) {
  filter->addBeacon(kCloneId, filter->mean().head<2>(), filter->covariance().topLeftCorner<2, 2>(),
                    filter->covariance().topRows(2));
}

// The backward pass's node against the clone, to rounding; and the later ranges moved it.
void expectSmoothedIsTheClone(const Pose& smoothed, const SmootherNode& filtered, const EkfFilter& filter) {
  const int c = filter.beaconIndex(kCloneId);
  EXPECT_NEAR(smoothed.x_m, filter.mean()(c), kCloneTolerance);
  EXPECT_NEAR(smoothed.y_m, filter.mean()(c + 1), kCloneTolerance);
  for (int r = 0; r < 2; ++r)
    for (int q = 0; q < 2; ++q) EXPECT_NEAR(smoothed.covariance[3 * r + q], filter.covariance()(c + r, c + q), kCloneTolerance);
  EXPECT_GT(std::hypot(smoothed.x_m - filtered.pose.x(), smoothed.y_m - filtered.pose.y()), 1e-3);
}

TEST(EkfSmoother, EqualsAStochasticCloneOfThePose) {
  // A stochastic clone of the pose at node 15 (clonePose): at the end its mean and covariance are
  // E[x_15, y_15 | every range] under the filter's linearisation, what the backward pass must give
  // for node 15, to rounding.
  constexpr int kSteps = 40, kClone = 15;
  EkfFilter filter = threeBeaconFilter(0.0);
  const auto& beacons = kBeacons;
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, 0.3);
  std::vector<SmootherNode> nodes{nodeOf(filter, {})};
  Path path(1);
  Odometry odometry;
  odometry.forward_m = 0.5;
  odometry.lateral_m = 0.02;
  odometry.delta_heading_rad = 0.04;
  const Eigen::Matrix3d Q = Eigen::Vector3d(1e-4, 1e-4, 1e-5).asDiagonal();
  auto range = [&](int k) {
    const Eigen::Vector2d truth(0.5 * k, 0.02 * k * k);  // any ranges will do: a curve near the path
    return (beacons[k % 3] - truth).norm() + noise(rng);
  };
  double nis = 0.0;
  for (int k = 1; k <= kSteps; ++k) {
    std::vector<SmootherOperation> before;
    filter.record(&before);
    filter.predict(odometry, 0.5, Q, 1e-8);
    filter.updateRange(k % 3, range(k), 0.3, 1e9, &nis, 1.345);
    filter.updateRange((k + 1) % 3, range(k), 0.3, 1e9, &nis, 1.345);
    filter.record(nullptr);
    nodes.push_back(nodeOf(filter, std::move(before)));
    path.push_back(Pose{});
    if (k == kClone) clonePose(&filter);
  }
  std::vector<SmootherOperation> trailing;
  filter.record(&trailing);
  filter.updateRange(0, range(kSteps), 0.3, 1e9, &nis, 1.345);
  filter.record(nullptr);
  ASSERT_EQ(trailing.size(), 1u);

  expectSmoothedIsTheClone(smoothPath(path, nodes, trailing)[kClone], nodes[kClone], filter);
}

TEST(EkfSmoother, ABeaconTakenOutOfTheStateKeepsTheCloneExact) {
  // The same stochastic clone at node 15, and at node 25 beacon 0 (the first in the state, so every
  // index after it moves) is taken out (removeBeacon: the EKF's re-placement of a lost beacon);
  // the ranges after it are to beacons 1 and 2. The filter after a removal is the marginal of
  // the rest, so the clone is still E[x_15, y_15 | every range applied], and the backward pass
  // must carry its adjoint across the removal to the same answer.
  constexpr int kSteps = 40, kClone = 15, kRemove = 25;
  EkfFilter filter = threeBeaconFilter(1.5);
  const auto& beacons = kBeacons;
  std::mt19937_64 rng(11);
  std::normal_distribution<double> noise(0.0, 0.3);
  std::vector<SmootherNode> nodes{nodeOf(filter, {})};
  Path path(1);
  Odometry odometry;
  odometry.forward_m = 0.5;
  odometry.delta_heading_rad = 0.04;
  const Eigen::Matrix3d Q = Eigen::Vector3d(1e-4, 1e-4, 1e-5).asDiagonal();
  auto range = [&](int id, int k) { return (beacons[id] - Eigen::Vector2d(0.5 * k, 0.02 * k * k)).norm() + noise(rng); };
  double nis = 0.0;
  for (int k = 1; k <= kSteps; ++k) {
    std::vector<SmootherOperation> before;
    filter.record(&before);
    if (k == kRemove) {
      const Eigen::Vector2d beacon_2 = filter.mean().segment<2>(filter.beaconIndex(2));
      const double predicted = filter.predictRange(2, nullptr);
      const int size = filter.size();
      filter.removeBeacon(0);
      ASSERT_FALSE(filter.hasBeacon(0));
      ASSERT_EQ(filter.size(), size - 3);  // its position and its own offset
      EXPECT_EQ(filter.mean().segment<2>(filter.beaconIndex(2)), beacon_2);
      EXPECT_EQ(filter.predictRange(2, nullptr), predicted);
    }
    filter.predict(odometry, 0.5, Q, 1e-8);
    const int first = k < kRemove ? k % 3 : 1 + k % 2;
    filter.updateRange(first, range(first, k), 0.3, 1e9, &nis, 1.345);
    filter.updateRange(k < kRemove ? (k + 1) % 3 : 2, range(2, k), 0.3, 1e9, &nis, 1.345);
    filter.record(nullptr);
    nodes.push_back(nodeOf(filter, std::move(before)));
    path.push_back(Pose{});
    if (k == kClone) clonePose(&filter);
  }
  expectSmoothedIsTheClone(smoothPath(path, nodes, {})[kClone], nodes[kClone], filter);
}

using test::meanError;

TEST(EkfSmoother, SmoothedTrajectoryOnGyroDriftFigure8) {
  // Seeds 301-303 (3000 steps, 0.01 rad/s gyro bias), both anchors. The smoother removes the
  // filter's lag (a pose is estimated from the ranges before and after it): the error after a
  // rigid fit, on the sweep's drift8 seeds, 0.15 -> 0.07 m (as the batch solution); the rotation
  // about the start, which a start-pose run takes from its first metres, it does not remove.
  // Measured mean error (m), filtered -> smoothed: start pose 0.616 -> 0.574, 0.158 -> 0.105,
  // 0.530 -> 0.535 (round 6's fresh re-run with b held near the first pass: before, 0.598 ->
  // 0.560, 0.168 -> 0.119, 0.744 -> 0.732; these seeds' frames are turned by ~2, 0.4, ~2
  // degrees, which the smoother leaves, so from the start pose it may not gain: bound +0.01 m);
  // beacons 0.183 -> 0.075, 0.185 -> 0.090, 0.174 -> 0.077 (strictly better).
  for (const auto anchor : {EkfConfig::Anchor::kStartPose, EkfConfig::Anchor::kBeacons}) {
    for (uint64_t seed = 301; seed <= 303; ++seed) {
      const sim::SimRun run = sim::simulate(sim::gyroDriftFigure8World(seed, 3000));
      EkfConfig config;
      config.anchor = anchor;
      EkfSlam ekf(config);
      test::feed(run, ekf);
      Path smoothed;
      ASSERT_TRUE(ekf.trajectory(true, &smoothed));
      ASSERT_EQ(smoothed.size(), ekf.path().size());
      const double filtered_m = meanError(ekf.path(), run.ground_truth);
      const double smoothed_m = meanError(smoothed, run.ground_truth);
      std::printf("%s seed %d: filtered %.3f m, smoothed %.3f m\n",
                  anchor == EkfConfig::Anchor::kStartPose ? "start pose" : "beacons", static_cast<int>(seed), filtered_m,
                  smoothed_m);
      EXPECT_LT(smoothed_m, filtered_m + (anchor == EkfConfig::Anchor::kStartPose ? 0.01 : 0.0)) << "seed " << seed;
      if (anchor == EkfConfig::Anchor::kStartPose) {
        // The start pose has no variance: the smoother cannot move it.
        EXPECT_EQ(smoothed.front().x_m, run.start.x_m);
        EXPECT_EQ(smoothed.front().y_m, run.start.y_m);
      }
      // Every smoothed position variance is at most the filtered one (it has more ranges).
      for (size_t k = 0; k < smoothed.size(); ++k)
        ASSERT_LE(smoothed[k].covariance[0] + smoothed[k].covariance[4],
                  ekf.path()[k].covariance[0] + ekf.path()[k].covariance[4] + 1e-12) << "pose " << k;

      config.smooth_trajectory = false;
      EkfSlam plain(config);
      test::feed(run, plain);
      Path filtered;
      ASSERT_TRUE(plain.trajectory(true, &filtered));
      ASSERT_EQ(filtered.size(), ekf.path().size());
      for (size_t k = 0; k < filtered.size(); ++k) {
        ASSERT_EQ(filtered[k].x_m, ekf.path()[k].x_m);  // recording changes nothing in the filter
        ASSERT_EQ(filtered[k].y_m, ekf.path()[k].y_m);
      }
    }
  }
}

TEST(EkfSmoother, LiveRequestsSmoothTheLastLagAndTheEndSmoothsAll) {
  // The host asks for TRAJECTORY every trajectory_interval_s (10 s of data) in live mode. With
  // smooth_live_lag_s the backward pass covers the last 60 s (and every pose since the previous
  // request); older poses keep their last published values. Against the whole pass at every
  // request (smooth_live_lag_s = 0): the last 60 s are identical bit for bit, the older poses
  // within decimetres (measured below), and after the end of input both paths are the
  // whole pass, identical bit for bit. Start pose too: its calibrated re-run cuts the nodes, and
  // the request after it must pass over the whole path again.
  for (const auto anchor : {EkfConfig::Anchor::kBeacons, EkfConfig::Anchor::kStartPose}) {
    const sim::SimRun run = sim::simulate(sim::gyroDriftFigure8World(302, 2000));  // 400 s
    EkfConfig config;
    config.anchor = anchor;
    EkfSlam lagged(config);
    config.smooth_live_lag_s = 0.0;
    EkfSlam whole(config);
    for (EkfSlam* ekf : {&lagged, &whole}) {
      ekf->setInitialPose(run.start);
      ekf->setBeacons(run.beacons);
    }
    const int64_t lag_us = 60'000'000, interval_us = 10'000'000;
    int64_t next_request_us = run.start.utime + interval_us;
    double largest_old_m = 0.0, largest_gap_m = -1.0;
    int requests = 0;
    size_t r = 0;
    for (const Odometry& odometry : run.odometry) {
      for (; r < run.ranges.size() && run.ranges[r].utime < odometry.utime; ++r)
        for (EkfSlam* ekf : {&lagged, &whole}) ekf->addRange(run.ranges[r]);
      for (EkfSlam* ekf : {&lagged, &whole}) ekf->addOdometry(odometry);
      if (odometry.utime < next_request_us) continue;
      next_request_us += interval_us;
      ++requests;
      Path live, all;
      ASSERT_TRUE(lagged.trajectory(true, &live));
      ASSERT_TRUE(whole.trajectory(true, &all));
      ASSERT_EQ(live.size(), all.size());
      largest_gap_m = std::max(largest_gap_m, meanError(live, run.ground_truth) - meanError(all, run.ground_truth));
      for (size_t k = 0; k < all.size(); ++k) {
        if (all[k].utime >= all.back().utime - lag_us) {
          ASSERT_EQ(live[k].x_m, all[k].x_m) << "pose " << k << " of " << all.size();
          ASSERT_EQ(live[k].y_m, all[k].y_m) << "pose " << k << " of " << all.size();
        } else {
          largest_old_m = std::max(largest_old_m, std::hypot(live[k].x_m - all[k].x_m, live[k].y_m - all[k].y_m));
        }
      }
    }
    std::printf("%s: %d live requests, older poses at most %.4f m from the whole pass, mean error at most "
                "%.4f m above it\n",
                anchor == EkfConfig::Anchor::kStartPose ? "start pose" : "beacons", requests, largest_old_m,
                largest_gap_m);
    EXPECT_EQ(requests, 40);
    // Measured: older poses at most 0.15 m (beacons) and 0.19 m (start pose) from the whole
    // pass; the live path's mean error at most 0.002 and 0.047 m above the whole pass's (about
    // as often below it). The lag did cut the pass short, and cost nothing a viewer would see.
    EXPECT_GT(largest_old_m, 0.0);
    EXPECT_LT(largest_old_m, 0.25);
    EXPECT_LT(largest_gap_m, 0.06);
    for (; r < run.ranges.size(); ++r)
      for (EkfSlam* ekf : {&lagged, &whole}) ekf->addRange(run.ranges[r]);
    Path final_lagged, final_whole;
    lagged.finish();
    whole.finish();
    ASSERT_TRUE(lagged.trajectory(true, &final_lagged));
    ASSERT_TRUE(whole.trajectory(true, &final_whole));
    ASSERT_EQ(final_lagged.size(), final_whole.size());
    for (size_t k = 0; k < final_whole.size(); ++k) {
      ASSERT_EQ(final_lagged[k].x_m, final_whole[k].x_m) << "pose " << k;
      ASSERT_EQ(final_lagged[k].y_m, final_whole[k].y_m) << "pose " << k;
    }
  }
}

TEST(EkfSmoother, AMemoryBoundLeavesTheOldestPosesFilteredAndTheRestExact) {
  // smooth_max_memory_mb: past it the oldest nodes are released. A pose's smoothed value depends
  // only on the operations after it, so the poses still held must be bit-identical to the whole
  // pass, and the released ones the filtered path's. 1000 steps with beacons hold ~1.5 MB; 0.4 MB
  // keeps roughly the last quarter (measured: 728 of 1001 poses released).
  const sim::SimRun run = sim::simulate(sim::gyroDriftFigure8World(301, 1000));
  EkfConfig config;
  config.anchor = EkfConfig::Anchor::kBeacons;
  EkfSlam whole(config);
  test::feed(run, whole);
  config.smooth_max_memory_mb = 0.4;
  EkfSlam bounded(config);
  test::feed(run, bounded);
  Path all, part;
  ASSERT_TRUE(whole.trajectory(true, &all));
  ASSERT_TRUE(bounded.trajectory(true, &part));
  ASSERT_EQ(all.size(), part.size());
  const double released = bounded.diagnostics().at("smoother_unsmoothed_poses");
  const size_t first = static_cast<size_t>(released);
  std::printf("released %zu of %zu poses\n", first, part.size());
  EXPECT_GT(first, part.size() / 4);
  EXPECT_LT(first, part.size() - part.size() / 10);
  for (size_t k = 0; k < part.size(); ++k) {
    const Pose& expected = k < first ? bounded.path()[k] : all[k];
    ASSERT_EQ(part[k].x_m, expected.x_m) << "pose " << k;
    ASSERT_EQ(part[k].y_m, expected.y_m) << "pose " << k;
  }
  EXPECT_NE(all[first / 2].x_m, bounded.path()[first / 2].x_m);  // smoothing moved the released poses
}

}  // namespace
}  // namespace ekf
}  // namespace roam
