// The final odometry smoothing of the spectral path (odometry_smoother.hpp): exact data stay
// exact, the frame is kept, and on gyro-drift figure-8s the path gets closer to the truth.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include <Eigen/Dense>

#include "odometry_smoother.hpp"
#include "spectral_slam.hpp"
#include "spectral_test_util.hpp"

namespace roam::spectral {
namespace {

using roam::testing::feed;
using roam::testing::pathErrors;

// A circle of 200 poses: exact odometry (0.2 m steps turning 0.02 rad) and its exact path.
void circle(OdometryPath* path, Path* exact, std::vector<double>* heading_rad) {
  Pose start;
  start.utime = 1000000;
  path->reset(start);
  for (int k = 0; k < 199; ++k) {
    Odometry odo;
    odo.utime = start.utime + (k + 1) * 200000;
    odo.forward_m = 0.2;
    odo.delta_heading_rad = 0.02;
    path->append(odo);
  }
  exact->assign(path->size(), Pose());
  heading_rad->assign(path->size(), 0.0);
  for (int k = 0; k < path->size(); ++k) {
    (*exact)[k].utime = path->utime[k];
    (*exact)[k].x_m = path->x_m[k];
    (*exact)[k].y_m = path->y_m[k];
    (*exact)[k].heading_rad = path->heading_rad[k];
    (*heading_rad)[k] = path->heading_rad[k];
  }
}

TEST(OdometrySmoother, ExactDataStayExact) {
  OdometryPath path;
  Path exact;
  std::vector<double> heading_rad;
  circle(&path, &exact, &heading_rad);
  std::vector<int> solved;
  for (int k = 10; k < 190; k += 3) solved.push_back(k);
  Path smoothed = exact;
  smoothWithOdometry(path, heading_rad, solved, 1.0, 0.5, SmootherNoise(), &smoothed);
  for (size_t k = 0; k < exact.size(); ++k) {
    EXPECT_NEAR(smoothed[k].x_m, exact[k].x_m, 1e-9) << k;
    EXPECT_NEAR(smoothed[k].y_m, exact[k].y_m, 1e-9) << k;
    EXPECT_EQ(smoothed[k].heading_rad, exact[k].heading_rad);
  }
}

TEST(OdometrySmoother, ExactDataStayExactWithHeadingCorrections) {
  OdometryPath path;
  Path exact;
  std::vector<double> heading_rad;
  circle(&path, &exact, &heading_rad);
  std::vector<int> solved;
  for (int k = 10; k < 190; k += 3) solved.push_back(k);
  SmootherNoise noise;
  noise.correct_headings = true;
  for (int64_t end_us : {int64_t{8000000}, INT64_MAX}) {
    noise.free_heading_end_us = end_us;
    Path smoothed = exact;
    smoothWithOdometry(path, heading_rad, solved, 1.0, 0.5, noise, &smoothed);
    for (size_t k = 0; k < exact.size(); ++k) {
      EXPECT_NEAR(smoothed[k].x_m, exact[k].x_m, 1e-9) << k;
      EXPECT_NEAR(smoothed[k].y_m, exact[k].y_m, 1e-9) << k;
    }
  }
}

// The turning headings off by 0.05 rad at the start, fading to 0 over the first 16 s (80 poses),
// as the one-sided local fit leaves them (README "Round 7b": 30-70 mrad on drift8), exact positions
// at every pose (sigma_p 0.42 m): held as given, the odometry bends the start; corrected within
// 16 s of the ends (correct_headings), the start follows the positions. Measured over the first
// 80 poses: 0.061 m as given, 0.012 m corrected; bound 0.3x, and > 0.03 m as given.
TEST(OdometrySmoother, HeadingCorrectionsAtTheEndsFollowThePositions) {
  OdometryPath path;
  Path exact;
  std::vector<double> heading_rad;
  circle(&path, &exact, &heading_rad);
  std::vector<double> biased = heading_rad;
  for (int k = 0; k < 80; ++k) biased[k] += 0.05 * (1.0 - k / 80.0);
  std::vector<int> solved;
  for (int k = 0; k < path.size(); ++k) solved.push_back(k);
  double start_m[2] = {0.0, 0.0};
  for (bool correct : {false, true}) {
    SmootherNoise noise;
    noise.correct_headings = correct;
    noise.free_heading_end_us = 16000000;
    Path smoothed = exact;
    smoothWithOdometry(path, biased, solved, 1.0, spectralPositionSigma(0.2, 1.0), noise, &smoothed);
    for (int k = 0; k < 80; ++k)
      start_m[correct ? 1 : 0] +=
          std::hypot(smoothed[k].x_m - exact[k].x_m, smoothed[k].y_m - exact[k].y_m) / 80.0;
  }
  std::printf("start headings 0.05 rad off: %.4f m as given, %.4f m corrected\n", start_m[0], start_m[1]);
  EXPECT_GT(start_m[0], 0.03);
  EXPECT_LT(start_m[1], 0.3 * start_m[0]);
}

TEST(OdometrySmoother, NoisyPositionsAreSmoothedAndTheFrameIsKept) {
  OdometryPath path;
  Path exact;
  std::vector<double> heading_rad;
  circle(&path, &exact, &heading_rad);
  // Every pose solved, each off by a fixed +-0.3 m pattern (zero mean, no net rotation).
  std::vector<int> solved;
  Path noisy = exact;
  double mean_error_m = 0.0;
  for (int k = 0; k < path.size(); ++k) {
    solved.push_back(k);
    noisy[k].x_m += (k % 2 == 0 ? 0.3 : -0.3);
    noisy[k].y_m += ((k / 2) % 2 == 0 ? 0.3 : -0.3);
    mean_error_m += std::hypot(noisy[k].x_m - exact[k].x_m, noisy[k].y_m - exact[k].y_m) / path.size();
  }
  Path smoothed = noisy;
  smoothWithOdometry(path, heading_rad, solved, 1.0, spectralPositionSigma(0.2, 1.0), SmootherNoise(), &smoothed);
  double cx_in = 0.0, cy_in = 0.0, cx_out = 0.0, cy_out = 0.0;
  for (int k = 0; k < path.size(); ++k) {
    cx_in += noisy[k].x_m;
    cy_in += noisy[k].y_m;
    cx_out += smoothed[k].x_m;
    cy_out += smoothed[k].y_m;
  }
  EXPECT_NEAR(cx_out, cx_in, 1e-6);
  EXPECT_NEAR(cy_out, cy_in, 1e-6);
  const double smoothed_m = pathErrors(smoothed, exact).mean_m;
  std::printf("alternating 0.3 m noise: %.3f m -> %.3f m\n", mean_error_m, smoothed_m);
  EXPECT_LT(smoothed_m, 0.1 * mean_error_m);
}

TEST(OdometrySmoother, RefusesMismatchedSizes) {
  OdometryPath path;
  Path exact;
  std::vector<double> heading_rad;
  circle(&path, &exact, &heading_rad);
  heading_rad.pop_back();
  EXPECT_THROW(smoothWithOdometry(path, heading_rad, {0, 1}, 1.0, 0.5, SmootherNoise(), &exact),
               std::invalid_argument);
  EXPECT_THROW(spectralPositionSigma(0.0, 1.0), std::invalid_argument);
}

// Gyro-drift figure-8s (the sweep's drift8 world, 3000 steps) with surveyed beacons, where the
// frame is fixed and what is left is the path's own shape: smoothing must help on every seed and
// rank. Measured (seeds 601 / 602 / 603, rank 4): 0.232 -> 0.185, 0.154 -> 0.121, 0.351 -> 0.215 m
// (ratios 0.80, 0.79, 0.61; rank 7 alike); bound: at most 0.85x unsmoothed on each.
constexpr double kSmoothedRatio = 0.85;
TEST(OdometrySmoother, GyroDriftFigure8sWithBeaconsGetCloserToTheTruth) {
  for (uint64_t seed : {601, 602, 603}) {
    const sim::SimRun run = sim::simulate(sim::gyroDriftFigure8World(seed, 3000));
    for (int rank : {4, 7}) {
      double mean_m[2] = {-1.0, -1.0};
      for (bool smooth : {true, false}) {
        SpectralConfig config;
        config.rank = rank;
        config.smooth_with_odometry = smooth;
        SpectralSlam slam(config);
        feed(slam, run, true);
        slam.finish();
        ASSERT_TRUE(slam.solution().has_value()) << seed << " rank " << rank << ": " << slam.lastRejection();
        mean_m[smooth ? 0 : 1] = pathErrors(slam.solution()->trajectory, run.ground_truth).mean_m;
        if (smooth) {
          EXPECT_GT(slam.solution()->smoothing_position_sigma_m, 0.0);
        } else {
          EXPECT_EQ(slam.solution()->smoothing_position_sigma_m, 0.0);
        }
      }
      std::printf("seed %d rank %d beacons: %.3f m smoothed, %.3f m not\n", static_cast<int>(seed), rank,
                  mean_m[0], mean_m[1]);
      EXPECT_LT(mean_m[0], kSmoothedRatio * mean_m[1]) << seed << " rank " << rank;
    }
  }
}

// Start pose (rank 4) on the start gauge's gyro-drift figure-8s (start_gauge_test.cpp, seeds
// 106-108): the headings that turn the odometry, corrected within W/2 of the path's ends
// (smoothing_corrects_headings, the default), against held as given. The start's bent first
// metres turn the whole path about the start (README "Round 7b"). Measured: 0.392 / 0.119 / 0.234
// m corrected, 0.589 / 0.335 / 0.236 as given (mean 0.25 vs 0.39); bounds: mean at most 0.8x, no
// seed more than 0.02 m worse.
TEST(OdometrySmoother, HeadingCorrectionsBringStartPoseFigure8sCloser) {
  double sum_m[2] = {0.0, 0.0};
  for (int seed : {106, 107, 108}) {
    const sim::SimRun run = sim::simulate(sim::gyroDriftFigure8World(seed, 4000));
    double mean_m[2] = {-1.0, -1.0};
    for (bool correct : {true, false}) {
      SpectralConfig config;
      config.anchor = SpectralAnchor::kStartPose;
      config.rank = 4;
      config.smoothing_corrects_headings = correct;
      config.smoothing_uses_ranges = false;  // the corrections as measured with the positions
      SpectralSlam slam(config);
      feed(slam, run, false);
      slam.finish();
      ASSERT_TRUE(slam.solution().has_value()) << "seed " << seed << ": " << slam.lastRejection();
      mean_m[correct ? 0 : 1] = pathErrors(slam.solution()->trajectory, run.ground_truth).mean_m;
      sum_m[correct ? 0 : 1] += mean_m[correct ? 0 : 1];
    }
    std::printf("seed %d start pose: %.3f m corrected, %.3f m as given\n", seed, mean_m[0], mean_m[1]);
    EXPECT_LT(mean_m[0], mean_m[1] + 0.02) << "seed " << seed;
  }
  EXPECT_LT(sum_m[0], 0.8 * sum_m[1]);
}

}  // namespace
}  // namespace roam::spectral

namespace roam::spectral {
namespace {

// Mean distance of the path's first `poses` poses from the truth after the rigid motion that best
// fits the path's poses from `from` on onto the truth: how far the start is off the rest.
double startOffRest_m(const Path& path, const Path& truth, int from, int poses) {
  const int T = static_cast<int>(std::min(path.size(), truth.size()));
  Eigen::Vector2d mp = Eigen::Vector2d::Zero(), mq = Eigen::Vector2d::Zero();
  for (int k = from; k < T; ++k) {
    mp += Eigen::Vector2d(path[k].x_m, path[k].y_m);
    mq += Eigen::Vector2d(truth[k].x_m, truth[k].y_m);
  }
  mp /= T - from;
  mq /= T - from;
  double dot = 0.0, cross = 0.0;
  for (int k = from; k < T; ++k) {
    const Eigen::Vector2d a = Eigen::Vector2d(path[k].x_m, path[k].y_m) - mp;
    const Eigen::Vector2d b = Eigen::Vector2d(truth[k].x_m, truth[k].y_m) - mq;
    dot += a.dot(b);
    cross += a(0) * b(1) - a(1) * b(0);
  }
  const double angle = std::atan2(cross, dot), c = std::cos(angle), s = std::sin(angle);
  double sum_m = 0.0;
  for (int k = 0; k < poses; ++k) {
    const Eigen::Vector2d a = Eigen::Vector2d(path[k].x_m, path[k].y_m) - mp;
    const Eigen::Vector2d moved(c * a(0) - s * a(1) + mq(0), s * a(0) + c * a(1) + mq(1));
    sum_m += (moved - Eigen::Vector2d(truth[k].x_m, truth[k].y_m)).norm();
  }
  return sum_m / poses;
}

// Start pose (rank 4) on the sweep's drifting-gyro figure-8 (gyroDriftFigure8World, 6000 steps;
// own seeds 111-114): the smoother with the ranges to the re-fitted map (smoothing_uses_ranges,
// the default) against the spectral positions. At the path's ends the positions are one window's
// edge fit, off by an error smooth over ~W/2 (from the range noise: it stays with noise-free
// headings), which pose 0 carries into the start-pose gauge (README "Round 8"). Checked: the
// first 100 poses against the rest (rigid fit from pose 300 on) and the full path's mean error;
// the mean over the seeds at most 0.45 m (the positions gave 0.54).
TEST(OdometrySmoother, RangesBringStartPoseFigure8sCloser) {
  double sum_m[2] = {0.0, 0.0}, start_m[2] = {0.0, 0.0};
  for (int seed : {111, 112, 113, 114}) {
    const sim::SimRun run = sim::simulate(sim::gyroDriftFigure8World(seed, 6000));
    double mean_m[2] = {-1.0, -1.0}, off_m[2] = {-1.0, -1.0};
    for (bool use_ranges : {true, false}) {
      SpectralConfig config;
      config.anchor = SpectralAnchor::kStartPose;
      config.rank = 4;
      config.smoothing_uses_ranges = use_ranges;
      SpectralSlam slam(config);
      feed(slam, run, false);
      slam.finish();
      ASSERT_TRUE(slam.solution().has_value()) << "seed " << seed << ": " << slam.lastRejection();
      const int i = use_ranges ? 0 : 1;
      EXPECT_EQ(slam.solution()->smoothing_range_sigma_m > 0.0, use_ranges) << "seed " << seed;
      mean_m[i] = pathErrors(slam.solution()->trajectory, run.ground_truth).mean_m;
      off_m[i] = startOffRest_m(slam.solution()->trajectory, run.ground_truth, 300, 100);
      sum_m[i] += mean_m[i];
      start_m[i] += off_m[i];
    }
    std::printf("seed %d start pose: ranges %.3f m (start off the rest %.3f), positions %.3f m (%.3f)\n", seed,
                mean_m[0], off_m[0], mean_m[1], off_m[1]);
    EXPECT_LT(mean_m[0], mean_m[1] + 0.02) << "seed " << seed;
  }
  std::printf("sums: ranges %.3f (%.3f), positions %.3f (%.3f)\n", sum_m[0], start_m[0], sum_m[1], start_m[1]);
  // Measured: ranges 0.152 / 0.269 / 0.506 / 0.563 m (mean 0.37), positions 0.191 / 0.653 /
  // 0.692 / 0.635 (mean 0.54, what the smoother gave before); first 100 poses off the rest 0.396
  // vs 0.567 summed.
  EXPECT_LT(sum_m[0], 4 * 0.45);
  EXPECT_LT(sum_m[0], 0.8 * sum_m[1]);
  EXPECT_LT(start_m[0], 0.85 * start_m[1]);
}

// The same world with ranges 7 % long (Plaza 1's ranges against its odometry's path, README
// "Round 8") and a 0.3 m offset: the smoother's range model removes one scale for every beacon
// and an offset per beacon, with the map re-fitted, so the start-pose path stays as good as with
// true ranges. Raw ranges to the learned map put Plaza 1 at 1.8-3.3 m.
TEST(OdometrySmoother, RangeScaleAndOffsetAreRemoved) {
  for (int seed : {111, 112}) {
    sim::SimConfig world = sim::gyroDriftFigure8World(seed, 6000);
    const sim::SimRun clean = sim::simulate(world);
    world.range_scale = 1.07;
    world.range_offset_m = 0.3;
    const sim::SimRun scaled = sim::simulate(world);
    double mean_m[2] = {-1.0, -1.0}, sigma_m[2] = {0.0, 0.0};
    for (int i = 0; i < 2; ++i) {
      SpectralConfig config;
      config.anchor = SpectralAnchor::kStartPose;
      config.rank = 4;
      SpectralSlam slam(config);
      const sim::SimRun& run = i == 0 ? clean : scaled;
      feed(slam, run, false);
      slam.finish();
      ASSERT_TRUE(slam.solution().has_value()) << "seed " << seed << ": " << slam.lastRejection();
      mean_m[i] = pathErrors(slam.solution()->trajectory, run.ground_truth).mean_m;
      sigma_m[i] = slam.solution()->smoothing_range_sigma_m;
    }
    std::printf("seed %d start pose: %.3f m true ranges, %.3f m scaled (sigma_r %.3f / %.3f)\n", seed, mean_m[0],
                mean_m[1], sigma_m[0], sigma_m[1]);
    EXPECT_GT(sigma_m[1], 0.0) << "seed " << seed;
    EXPECT_LT(sigma_m[1], 1.5 * sigma_m[0]) << "seed " << seed;
    // Measured 0.152 -> 0.172 m (seed 111), 0.269 -> 0.361 (112); sigma_r unchanged (0.27, 0.32).
    EXPECT_LT(mean_m[1], mean_m[0] + 0.15) << "seed " << seed;
    EXPECT_LT(mean_m[1], 0.5) << "seed " << seed;
  }
}

}  // namespace
}  // namespace roam::spectral
