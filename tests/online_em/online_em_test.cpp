// Tests of the online EM SLAM core (Le Corff, Fort & Moulines 2011) on seeded synthetic runs.
#include <algorithm>
#include <cmath>
#include <cstdlib>

#include <memory>

#include <gtest/gtest.h>

#include "feed.hpp"
#include "online_em_slam.hpp"
#include "particle_motion.hpp"
#include "roam/estimation/motion_model.hpp"
#include "roam/options.hpp"
#include "sim.hpp"

namespace roam {
namespace {

using online_em_test::deadReckoningError;
using online_em_test::feed;
using online_em_test::mapError;
using online_em_test::meanError;
using online_em::addOnlineEmOptions;
using online_em::OnlineEmConfig;
using online_em::OnlineEmSlam;

// Noise-free data: the particles move with ~1e-7 m of proposal noise per step, so the filtered
// path and the map may differ from the truth only by accumulated rounding and that noise.
constexpr double kExactPath_m = 1e-4;
constexpr double kExactMap_m = 1e-4;

// A lawn-mower run over a 30 x 20 m area with 4 beacons around it, Plaza-like rates:
// 5 Hz odometry at 1 m/s, round-robin ranges at 2 Hz.
sim::SimConfig plazaLike(int steps, uint64_t seed) {
  sim::SimConfig c;
  c.seed = seed;
  c.num_steps = steps;
  c.path = sim::PathKind::kLawnMower;
  c.area_width_m = 30.0;
  c.area_height_m = 20.0;
  c.schedule = sim::RangeSchedule::kRoundRobin;
  c.range_rate_hz = 2.0;
  c.beacons = {{0, -8.0, -6.0, {}}, {1, 38.0, -5.0, {}}, {2, 36.0, 27.0, {}}, {3, -6.0, 26.0, {}}};
  return c;
}

// Plaza-like noise: 2 % odometry distance, 0.005 rad heading per step, 0.5 m ranges that are
// 5 % long (the scale the estimator must learn).
sim::SimConfig noisyPlazaLike(int steps, uint64_t seed) {
  sim::SimConfig c = plazaLike(steps, seed);
  c.odo_distance_sigma_rel = 0.02;
  c.odo_heading_sigma_rad = 0.005;
  c.range_sigma_m = 0.5;
  c.range_scale = 1.05;
  return c;
}

OnlineEmConfig noiseFreeConfig(const std::string& anchor) {
  OnlineEmConfig c;
  setOptions(&c, addOnlineEmOptions, {{"anchor", anchor}});
  c.odo_distance_sigma_rel = 0.0;
  c.odo_distance_sigma_m = 1e-7;
  c.odo_heading_sigma_rad = 1e-8;
  c.distance_scale_particle_sigma = 0.0;  // no proposal noise at all
  return c;
}

double maxPathError(const Path& path, const Path& truth) {
  double worst = 0.0;
  EXPECT_EQ(path.size(), truth.size());
  for (size_t k = 0; k < std::min(path.size(), truth.size()); ++k)
    worst = std::max(worst, std::hypot(path[k].x_m - truth[k].x_m, path[k].y_m - truth[k].y_m));
  return worst;
}

TEST(OnlineEmNoiseFree, ExactMapStaysFixedAndPathIsExact) {
  const Dataset data = sim::simulate(plazaLike(600, 3));
  OnlineEmSlam slam(noiseFreeConfig("beacons"));
  feed(data, slam);
  // Every range is h(x_true, m_true): linearised at the true map, z = J m^ and the M-step
  // returns m^, scale 1, offset 0 (up to the 1e-7 m proposal noise).
  EXPECT_LT(maxPathError(slam.filteredPath(), data.ground_truth), kExactPath_m);
  const Map map = slam.currentMap();
  ASSERT_EQ(map.size(), 4u);
  for (size_t i = 0; i < map.size(); ++i) {
    EXPECT_NEAR(map[i].x_m, data.beacons[i].x_m, kExactMap_m);
    EXPECT_NEAR(map[i].y_m, data.beacons[i].y_m, kExactMap_m);
  }
  EXPECT_NEAR(slam.rangeScale(), 1.0, 1e-6);
  EXPECT_NEAR(slam.rangeOffset(), 0.0, 1e-4);
  // In roam-run's order a range stamped at the last odometry time comes after that step and
  // waits for a step that never comes (rejected, and counted as ranges_after_last_odometry); every
  // other is used.
  int64_t after_last = 0;
  for (const Range& r : data.ranges) after_last += r.utime >= data.odometry.back().utime ? 1 : 0;
  EXPECT_EQ(slam.rangesAccepted(), static_cast<int64_t>(data.ranges.size()) - after_last);
  EXPECT_EQ(slam.rangesRejected(), after_last);  // "after the last odometry step"
  EXPECT_EQ(after_last, 1);
}

TEST(OnlineEmNoiseFree, StartPoseMultilaterationRecoversTheMap) {
  const Dataset data = sim::simulate(plazaLike(600, 3));
  OnlineEmSlam slam(noiseFreeConfig("start_pose"));
  feed(data, slam);
  // Multilateration from exact positions and ranges is exact (Gauss-Newton to 1e-9), and the
  // EM then stays at the exact map as above.
  EXPECT_LT(maxPathError(slam.filteredPath(), data.ground_truth), kExactPath_m);
  EXPECT_LT(mapError(slam.currentMap(), data.beacons), kExactMap_m);
}

TEST(OnlineEmNoiseFree, ALandmarkNeverInitialisedHasItsRangesRejectedWithTheKey) {
  // A fifth beacon 2 km away: the 30 x 20 m lawn mower spans ~0.5 degrees seen from it, under
  // init_min_spread_fraction (0.05 of the median range: 100 m of spread), so it never enters the
  // map. Its ranges were never used: each is rejected under that check, naming the key (roam-run's
  // end-of-run warning then says "look at key init_min_spread_fraction"), and every other range
  // is accepted. The four near beacons' map is exact as without it.
  sim::SimConfig world = plazaLike(600, 3);
  world.beacons.push_back({4, 2000.0, 10.0, {}});
  const Dataset data = sim::simulate(world);
  OnlineEmSlam slam(noiseFreeConfig("start_pose"));
  feed(data, slam);
  int64_t far = 0, after_last = 0;
  for (const Range& r : data.ranges) {
    if (r.utime >= data.odometry.back().utime) {
      ++after_last;
    } else if (r.beacon_id == 4) {
      ++far;
    }
  }
  ASSERT_GT(far, 40);  // a fifth of the 2 Hz round robin over 120 s
  EXPECT_EQ(slam.rangesRejected(), far + after_last);  // and the range after the last step
  EXPECT_EQ(slam.rangesAccepted(), static_cast<int64_t>(data.ranges.size()) - far - after_last);
  EXPECT_EQ(slam.rejections().at("range: after the last odometry step"), after_last);
  const std::string reason =
      "range: landmark never initialised: its ranging positions span too narrow an angle seen from it "
      "(init_min_spread_fraction)";
  ASSERT_EQ(slam.rejections().count(reason), 1u);
  EXPECT_EQ(slam.rejections().at(reason), far);
  EXPECT_EQ(slam.diagnostics().at("landmarks_never_initialised"), 1.0);
  const Map map = slam.currentMap();
  ASSERT_EQ(map.size(), 4u);
  EXPECT_LT(mapError(map, Map(data.beacons.begin(), data.beacons.begin() + 4)), kExactMap_m);
  // Without the far beacon nothing is rejected but the range after the last step.
  OnlineEmSlam near(noiseFreeConfig("start_pose"));
  feed(sim::simulate(plazaLike(600, 3)), near);
  EXPECT_EQ(near.rangesRejected(), after_last);
  EXPECT_EQ(near.diagnostics().at("landmarks_never_initialised"), 0.0);
}

TEST(OnlineEmNoiseFree, RangesBetweenOdometryStepsUseTheInterpolatedPose) {
  // A 1 m/s path (0.2 m steps) with a quarter turn; ranges stamped mid-step are computed from
  // the true position interpolated at their time. Scored at the step's end pose instead, they
  // would be up to 0.1 m off and the map would not be exact.
  Dataset data;
  data.start.utime = 0;
  data.beacons = {{0, 5.0, 8.0, {}}, {1, 12.0, -4.0, {}}, {2, -3.0, -6.0, {}}};
  Pose p = data.start;
  data.ground_truth.push_back(p);
  for (int k = 0; k < 300; ++k) {
    Odometry o;
    o.utime = (k + 1) * 200000;
    o.forward_m = 0.2;
    o.delta_heading_rad = (k / 50) % 2 == 1 ? M_PI / 100.0 : 0.0;
    Pose next = p;
    next.utime = o.utime;
    next.x_m += 0.2 * std::cos(p.heading_rad);
    next.y_m += 0.2 * std::sin(p.heading_rad);
    next.heading_rad += o.delta_heading_rad;
    const Beacon& b = data.beacons[k % 3];
    Range r;
    r.utime = p.utime + 70000;  // 35 % into the step
    r.beacon_id = b.id;
    r.range_m = std::hypot(b.x_m - (p.x_m + 0.35 * (next.x_m - p.x_m)), b.y_m - (p.y_m + 0.35 * (next.y_m - p.y_m)));
    data.ranges.push_back(r);
    data.odometry.push_back(o);
    data.ground_truth.push_back(next);
    p = next;
  }
  OnlineEmSlam slam(noiseFreeConfig("start_pose"));
  feed(data, slam);
  EXPECT_LT(maxPathError(slam.filteredPath(), data.ground_truth), kExactPath_m);
  EXPECT_LT(mapError(slam.currentMap(), data.beacons), kExactMap_m);
}

// Runs the first `steps` odometry steps of `data` (with their ranges); returns the map error.
double mapErrorAfter(const Dataset& data, OnlineEmSlam& slam, size_t* next_odometry, size_t* next_range,
                     size_t steps) {
  for (; *next_odometry < std::min(steps, data.odometry.size()); ++*next_odometry) {
    const Odometry& o = data.odometry[*next_odometry];
    while (*next_range < data.ranges.size() && data.ranges[*next_range].utime <= o.utime)
      slam.addRange(data.ranges[(*next_range)++]);
    slam.addOdometry(o);
  }
  return mapError(slam.currentMap(), data.beacons);
}

TEST(OnlineEmNoisy, MapErrorFallsAndScaleIsLearned) {
  const Dataset data = sim::simulate(noisyPlazaLike(2500, 11));
  OnlineEmConfig config;  // defaults: anchor = start_pose, 100 particles
  OnlineEmSlam slam(config);
  slam.setInitialPose(data.start);
  size_t o = 0, r = 0;
  const double early_m = mapErrorAfter(data, slam, &o, &r, 500);
  const double late_m = mapErrorAfter(data, slam, &o, &r, data.odometry.size());
  slam.finish();
  std::printf("map error after 500 steps %.3f m, after %zu steps %.3f m; path mean %.3f m; scale %.4f\n",
              early_m, data.odometry.size(), late_m, meanError(slam.filteredPath(), data.ground_truth),
              slam.rangeScale());
  // Measured (seed 11): 0.57 m after 500 steps, 0.52 m at the end, path mean 0.54 m, scale
  // 1.049; bounds with ~50 % margin.
  EXPECT_LT(late_m, early_m);
  EXPECT_LT(late_m, 0.8);
  EXPECT_NEAR(slam.rangeScale(), 1.05, 0.01);
  EXPECT_LT(meanError(slam.filteredPath(), data.ground_truth), 0.8);
}

TEST(OnlineEmNoisy, SurveyedBeaconsGiveSubMetrePath) {
  const Dataset data = sim::simulate(noisyPlazaLike(2000, 5));
  OnlineEmConfig config;
  config.anchor = OnlineEmConfig::Anchor::kBeacons;
  OnlineEmSlam slam(config);
  feed(data, slam);
  const double mean_m = meanError(slam.filteredPath(), data.ground_truth);
  std::printf("beacons: path mean %.3f m, map %.3f m, scale %.4f, distance scale %.4f\n", mean_m,
              mapError(slam.currentMap(), data.beacons), slam.rangeScale(), slam.odometryCalibration().distance_scale);
  // Measured (seed 5): path mean 0.48 m, map 0.18 m, range scale 1.064, distance scale 0.990
  // (without the per-particle scale spread: 0.63 m, 1.054, 0.997). With 4 beacons outside the
  // area the two scales trade against each other by ~1-2 %.
  EXPECT_LT(mean_m, 0.7);
  EXPECT_LT(mapError(slam.currentMap(), data.beacons), 0.5);
  EXPECT_NEAR(slam.rangeScale(), 1.05, 0.02);
  EXPECT_NEAR(slam.odometryCalibration().distance_scale, 1.0, 0.03);
}

TEST(OnlineEmNoisy, RangeBearingWithMixtureNoise) {
  sim::SimConfig s = plazaLike(1500, 21);
  s.odo_distance_sigma_rel = 0.02;
  s.odo_heading_sigma_rad = 0.005;
  s.bearing = true;
  s.bearing_sigma_rad = M_PI / 60.0;
  s.range_sigma_m = 0.5;  // the paper's mixture: 80 % sigma 0.5 m, 20 % 2.5 m
  s.mixture_weight1 = 0.2;
  s.range_sigma1_m = 2.5;
  const Dataset data = sim::simulate(s);
  OnlineEmConfig config;
  config.range_bearing_cov = 0.0;  // the simulator draws range and bearing independently
  OnlineEmSlam slam(config);
  feed(data, slam);
  const double mean_m = meanError(slam.filteredPath(), data.ground_truth);
  std::printf("range-bearing: path mean %.3f m, map %.3f m\n", mean_m, mapError(slam.currentMap(), data.beacons));
  // Measured (seed 21): path mean 0.31 m, map 0.42 m.
  EXPECT_LT(mean_m, 0.6);
  EXPECT_LT(mapError(slam.currentMap(), data.beacons), 0.8);
}

// Gyro drift on a figure-8 (the kind of issue 15's held-out run): 0.01 rad/s of heading-rate
// bias, 2 % distance noise, 0.003 rad heading noise per step, 6 beacons at 2 Hz.
sim::SimConfig gyroDriftFigure8(int steps, uint64_t seed) { return sim::gyroDriftFigure8World(seed, steps); }

TEST(OnlineEmCalibration, GyroBiasIsLearnedAndTheStartFrameCorrected) {
  const Dataset data = sim::simulate(gyroDriftFigure8(2500, 7));
  OnlineEmSlam slam{OnlineEmConfig{}};  // defaults: start_pose, calibrate_odometry = true
  feed(data, slam);
  OnlineEmConfig off;
  off.calibrate_odometry = false;
  OnlineEmSlam uncalibrated(off);
  feed(data, uncalibrated);
  const double mean_m = meanError(slam.filteredPath(), data.ground_truth);
  const double off_m = meanError(uncalibrated.filteredPath(), data.ground_truth);
  std::printf("gyro drift: bias %.5f rad/s, scale %.4f, path mean %.3f m (uncalibrated %.3f m)\n",
              slam.odometryCalibration().heading_rate_bias_rad_s, slam.odometryCalibration().distance_scale,
              mean_m, off_m);
  // The simulator adds the bias to the reported turn, so b = +0.01 rad/s; the scale is 1.
  // Measured (seed 7): b 0.0094 rad/s, s 0.994, path 1.01 m against 19.1 m uncalibrated
  // (1.45 m before the calibrated re-run).
  EXPECT_NEAR(slam.odometryCalibration().heading_rate_bias_rad_s, 0.01, 0.001);
  EXPECT_NEAR(slam.odometryCalibration().distance_scale, 1.0, 0.02);
  EXPECT_LT(mean_m, 0.5 * off_m);
  EXPECT_DOUBLE_EQ(uncalibrated.odometryCalibration().heading_rate_bias_rad_s, 0.0);
}

// A slow UWB robot (sim::slowUwbWorld: 1 s steps at 0.5 m/s, one range every 2 s, 0.005 rad/s
// of gyro bias): 0.01 x 3 x 2 s = 0.06 rad between fixes, under heading_rate_bias_max_drift_rad
// (0.08), so b is estimated. Held at 0 (the old 0.05) online EM followed its dead reckoning in
// both anchors (seed 310: 21.7 / 21.2 m, dead reckoning 21.7). With b estimated but the heading
// noise per step (0.005 rad, below the robot's 0.0067) 1.83 / 2.02 m; with the 1 s step's share
// of the heading noise per second (odo_heading_step_max_s, 0.01 rad) 0.90 / 0.68 m, b
// 0.0048 rad/s.
TEST(OnlineEmCalibration, ASlowUwbRobotEstimatesItsGyroBias) {
  const Dataset data = sim::simulate(sim::slowUwbWorld(310, 2400));
  for (const std::string anchor : {"start_pose", "beacons"}) {
    OnlineEmConfig config;
    setOptions(&config, addOnlineEmOptions, {{"anchor", anchor}});
    OnlineEmSlam slam(config);
    feed(data, slam);
    const double mean_m = meanError(slam.filteredPath(), data.ground_truth);
    std::printf("slow UWB seed 310, %s: path mean %.2f m, b %.5f rad/s\n", anchor.c_str(), mean_m,
                slam.odometryCalibration().heading_rate_bias_rad_s);
    EXPECT_EQ(slam.diagnostics().at("heading_rate_bias_estimated"), 1.0);
    EXPECT_NEAR(slam.odometryCalibration().heading_rate_bias_rad_s, 0.005, 0.0005);
    EXPECT_LT(mean_m, 1.4);
  }
}

// The heading noise per step is stated for steps of odo_heading_step_min_s to _max_s (0.15-0.25
// s); a shorter step gets its share of the same random walk, a longer one too where the ranges
// re-fix the heading (share_long_steps), else the per-step sigma; a step of unknown length and
// a bound of 0 get the per-step sigma.
TEST(OnlineEmMotion, HeadingNoiseIsSharedOutOverShortAndLongSteps) {
  OnlineEmConfig c;
  c.odo_heading_sigma_rad = 0.005;
  c.odo_heading_step_min_s = 0.2;
  c.odo_heading_step_max_s = 0.25;
  for (const bool share : {false, true}) {
    EXPECT_DOUBLE_EQ(online_em::headingSigma_rad(c, 0.05, share), 0.0025);
    EXPECT_DOUBLE_EQ(online_em::headingSigma_rad(c, 0.199, share), 0.005 * std::sqrt(0.199 / 0.2));
    EXPECT_DOUBLE_EQ(online_em::headingSigma_rad(c, 0.2, share), 0.005);
    EXPECT_DOUBLE_EQ(online_em::headingSigma_rad(c, 0.25, share), 0.005);
    EXPECT_DOUBLE_EQ(online_em::headingSigma_rad(c, 0.0, share), 0.005);
  }
  EXPECT_DOUBLE_EQ(online_em::headingSigma_rad(c, 1.0, false), 0.005);
  EXPECT_DOUBLE_EQ(online_em::headingSigma_rad(c, 1.0, true), 0.01);
  c.odo_heading_step_min_s = 0.0;
  c.odo_heading_step_max_s = 0.0;
  EXPECT_DOUBLE_EQ(online_em::headingSigma_rad(c, 0.05, true), 0.005);
  EXPECT_DOUBLE_EQ(online_em::headingSigma_rad(c, 1.0, true), 0.005);
  // And the particles' increment covariance carries it.
  c.odo_heading_step_min_s = 0.2;
  c.odo_heading_step_max_s = 0.25;
  online_em::ParticleMotion motion(c);
  Odometry step;
  step.forward_m = 0.05;
  EXPECT_DOUBLE_EQ(motion.noiseCovariance(step, 0.05)(2, 2), 0.0025 * 0.0025);
  EXPECT_DOUBLE_EQ(motion.noiseCovariance(step, 1.0)(2, 2), 0.005 * 0.005);
  motion.shareHeadingNoiseOverLongSteps(true);
  EXPECT_DOUBLE_EQ(motion.noiseCovariance(step, 1.0)(2, 2), 0.01 * 0.01);
}

// What the heading noise per step tells the M-step about the heading-rate bias: each step's turn
// weighs dt^2 / sigma^2. With sigma per step whatever the rate (odo_heading_step_min_s = 0, the
// model before round 11) 20 Hz odometry told a quarter as much per second as 5 Hz odometry with the
// same gyro, so the bias stayed unsure and the calibrated re-run (at 5e-4 rad/s) came four times
// later or not at all (the drifting figure-8 at 20 Hz from the start pose, 20 minutes, six
// seeds: 1.13 m; with the share 0.31 m; 5 Hz 0.68 m). The same 5 minutes at 5 Hz and at 20 Hz
// (same noise per second) now know b about equally well.
TEST(OnlineEmCalibration, FastOdometryTellsAsMuchAboutTheBiasPerSecond) {
  auto biasSigma = [](double dt_s, double min_step_s) {
    sim::SimConfig world = gyroDriftFigure8(static_cast<int>(std::lround(300.0 / dt_s)), 11);
    world.dt_s = dt_s;
    world.odo_heading_sigma_rad = 0.003 * std::sqrt(dt_s / 0.2);
    world.odo_distance_sigma_rel = 0.02 * std::sqrt(0.2 / dt_s);
    const Dataset data = sim::simulate(world);
    OnlineEmConfig config;
    config.odo_heading_step_min_s = min_step_s;
    OnlineEmSlam slam(config);
    feed(data, slam);
    EXPECT_NEAR(slam.odometryCalibration().heading_rate_bias_rad_s, 0.01, 0.002);
    return slam.diagnostics().at("heading_rate_bias_sigma_rad_s");
  };
  const double sigma_5hz = biasSigma(0.2, 0.15);
  const double sigma_20hz = biasSigma(0.05, 0.15);
  const double sigma_20hz_per_step = biasSigma(0.05, 0.0);
  std::printf("b sigma after 300 s: 5 Hz %.3g, 20 Hz %.3g (per step whatever the rate: %.3g) rad/s\n", sigma_5hz,
              sigma_20hz, sigma_20hz_per_step);
  EXPECT_LT(sigma_20hz, 1.3 * sigma_5hz);
  EXPECT_GT(sigma_20hz_per_step, 1.6 * sigma_5hz);
}

// Calibrated re-run (start pose): once b is known, the filter restarts from the start with the
// learned calibration, so the first landmarks are placed from a calibrated path and the frame
// is right; without it only the approximate frame correction is left.
// The same run with the defaults and with calibrated_rerun = false (the frame correction only).
struct RerunComparison {
  std::unique_ptr<OnlineEmSlam> slam, correction_only;
  double mean_m = 0.0, off_m = 0.0;
};
// The defaults against `off` (default: no calibrated re-run at all).
OnlineEmConfig noCalibratedRerun() {
  OnlineEmConfig off;
  off.calibrated_rerun = false;
  return off;
}
RerunComparison compareCalibratedRerun(const Dataset& data, const OnlineEmConfig& off = noCalibratedRerun()) {
  RerunComparison c;
  c.slam = std::make_unique<OnlineEmSlam>(OnlineEmConfig{});
  feed(data, *c.slam);
  c.correction_only = std::make_unique<OnlineEmSlam>(off);
  feed(data, *c.correction_only);
  c.mean_m = meanError(c.slam->filteredPath(), data.ground_truth);
  c.off_m = meanError(c.correction_only->filteredPath(), data.ground_truth);
  return c;
}

TEST(OnlineEmCalibration, CalibratedRerunFixesTheStartFrame) {
  const Dataset data = sim::simulate(gyroDriftFigure8(3500, 11));
  const RerunComparison c = compareCalibratedRerun(data);
  const OnlineEmSlam& slam = *c.slam;
  const OnlineEmSlam& correction_only = *c.correction_only;
  const double mean_m = c.mean_m, off_m = c.off_m;
  const auto& d = slam.diagnostics();
  ASSERT_TRUE(d.count("calibrated_rerun_bias_rad_s"));
  EXPECT_FALSE(correction_only.diagnostics().count("calibrated_rerun_bias_rad_s"));
  std::printf("re-run: at b %.5f rad/s, final b %.5f, path mean %.3f m (frame correction only %.3f m)\n",
              d.at("calibrated_rerun_bias_rad_s"), slam.odometryCalibration().heading_rate_bias_rad_s, mean_m,
              off_m);
  EXPECT_NEAR(d.at("calibrated_rerun_bias_rad_s"), 0.01, 0.001);
  EXPECT_NEAR(slam.odometryCalibration().heading_rate_bias_rad_s, 0.01, 0.001);
  // The path is whole (one pose per step plus the start), published online as before.
  EXPECT_EQ(slam.filteredPath().size(), correction_only.filteredPath().size());
  // Measured (seed 11): re-run at b 0.0100 rad/s, path 0.28 m against 1.57 m.
  EXPECT_LT(mean_m, 0.6);
  EXPECT_LT(mean_m, 0.5 * off_m);
}

// A 60 x 40 m lawn mower with a drifting gyro (sim::longLanesWorld): the landmarks enter only after the
// first 60 m lane, and b's sigma stays above rerun_bias_sigma_fraction to the end, so the
// calibrated re-run never came and the frame correction, a rigid fit about the window's centroid,
// stayed in effect with the start pose moved metres off the start. At the end of input the re-run
// is made with b as learned over the run.
TEST(OnlineEmCalibration, AFrameCorrectionLeftAtTheEndIsReplacedByTheCalibratedRerun) {
  const Dataset data = sim::simulate(sim::longLanesWorld(302, 1500));
  const RerunComparison c = compareCalibratedRerun(data);
  const OnlineEmSlam& slam = *c.slam;
  const OnlineEmSlam& correction_only = *c.correction_only;
  const double mean_m = c.mean_m, off_m = c.off_m;
  const Pose& first = correction_only.filteredPath().front();
  std::printf("end re-run: path %.3f m (frame correction only %.3f m, its first pose %.2f m off the start)\n", mean_m,
              off_m, std::hypot(first.x_m - data.start.x_m, first.y_m - data.start.y_m));
  const auto& d = slam.diagnostics();
  ASSERT_TRUE(d.count("calibrated_rerun_inputs"));
  EXPECT_EQ(d.at("calibrated_rerun_inputs"), static_cast<double>(data.odometry.size() + data.ranges.size()));  // at the end
  EXPECT_EQ(slam.filteredPath().front().x_m, data.start.x_m);
  EXPECT_EQ(slam.filteredPath().front().y_m, data.start.y_m);
  EXPECT_GT(std::hypot(first.x_m - data.start.x_m, first.y_m - data.start.y_m), 1.0);
  // Measured (seed 302): 0.24 m against 4.62 m, that path's first pose 8.48 m off the start.
  EXPECT_LT(mean_m, 0.5);
  EXPECT_LT(mean_m, 0.5 * off_m);
}

// The same long lanes, seed 305: no frame correction was in effect, and b's sigma stayed above
// rerun_bias_sigma_fraction, so no re-run came at all. The particles had turned with the bias
// for the first lane before it was learned and followed their dead reckoning to the end, though
// b was learned to within 25 %. At the end of input the re-run is made where the learned b is
// significant (rerun_end_bias_sigmas); where there is no bias it is not.
TEST(OnlineEmCalibration, ASignificantBiasLearnedWithoutARerunIsRerunAtTheEnd) {
  const Dataset data = sim::simulate(sim::longLanesWorld(305, 1500));
  OnlineEmConfig no_end_rerun;
  no_end_rerun.rerun_end_bias_sigmas = 0.0;
  const RerunComparison c = compareCalibratedRerun(data, no_end_rerun);
  const auto& d = c.slam->diagnostics();
  const double b_rad_s = c.slam->odometryCalibration().heading_rate_bias_rad_s;
  std::printf("end re-run at b %.5f rad/s (sigma %.5f): path %.3f m (without it %.3f m)\n", b_rad_s,
              d.at("heading_rate_bias_sigma_rad_s"), c.mean_m, c.off_m);
  EXPECT_FALSE(c.correction_only->diagnostics().count("calibrated_rerun_inputs"));
  EXPECT_FALSE(c.correction_only->diagnostics().count("frame_correction_rad") &&
               c.correction_only->diagnostics().at("frame_correction_rad") != 0.0);
  ASSERT_TRUE(d.count("calibrated_rerun_inputs"));
  EXPECT_EQ(d.at("calibrated_rerun_inputs"), static_cast<double>(data.odometry.size() + data.ranges.size()));
  EXPECT_NEAR(d.at("calibrated_rerun_bias_rad_s"), 0.005, 0.0015);
  // Measured (seed 305): b 0.0039 rad/s at 6.1 sigma; path 0.59 m against 12.50 m.
  EXPECT_LT(c.mean_m, 1.0);
  EXPECT_LT(c.mean_m, 0.2 * c.off_m);

  // No bias (30 % NLOS, clean odometry): the learned b is within the test, no re-run is made.
  const Dataset clean = sim::simulate(sim::nlos30LawnMowerWorld(302, 1500));
  OnlineEmSlam slam{OnlineEmConfig{}};  // defaults: start_pose, calibrate_odometry = true
  feed(clean, slam);
  const auto& dc = slam.diagnostics();
  std::printf("no bias: b %.5f rad/s, sigma %.5f\n", slam.odometryCalibration().heading_rate_bias_rad_s,
              dc.at("heading_rate_bias_sigma_rad_s"));
  EXPECT_LT(std::abs(slam.odometryCalibration().heading_rate_bias_rad_s), 3.0 * dc.at("heading_rate_bias_sigma_rad_s"));
  EXPECT_FALSE(dc.count("calibrated_rerun_inputs"));
}

// 30 % non-line-of-sight ranges, 2-40 m long (issue 15's heavy-outlier kind), lawn mower.
TEST(OnlineEmOutliers, ThirtyPercentNlosRangesInBothAnchors) {
  const Dataset data = sim::simulate(sim::nlos30LawnMowerWorld(302, 1500));
  for (const std::string anchor : {"beacons", "start_pose"}) {
    OnlineEmConfig config;
    setOptions(&config, addOnlineEmOptions, {{"anchor", anchor}});
    OnlineEmSlam slam(config);
    feed(data, slam);
    const double mean_m = meanError(slam.filteredPath(), data.ground_truth);
    const double map_m = mapError(slam.currentMap(), data.beacons);
    std::printf("NLOS 30 %%, %s: path mean %.3f m, map %.3f m\n", anchor.c_str(), mean_m, map_m);
    // Measured (seed 12): beacons 0.16 m path, 0.04 m map; start pose 0.94 m path, 1.26 m map.
    // Bounds: issue 15's targets for the path, 0.5 m (beacons) and 1.5 m (start pose); the map
    // with ~50 % margin.
    EXPECT_LT(mean_m, anchor == "beacons" ? 0.5 : 1.5);
    EXPECT_LT(map_m, anchor == "beacons" ? 0.3 : 2.0);
  }
}

// The AUV-like world (logs/synthetic/auv-sparse: seed 108, dead reckoning 25.6 m) with the
// mixture in theta (the default): the outlier weight and the inlier sigma are learned from 45 %
// outliers (-150 to +100 m) and 2 m range noise stated as 0.75 m.
TEST(OnlineEmOutliers, AuvMixtureIsLearned) {
  const Dataset data = sim::simulate(sim::auvLikeWorld(108, 500));
  OnlineEmSlam slam{OnlineEmConfig{}};
  feed(data, slam);
  const double mean_m = meanError(slam.filteredPath(), data.ground_truth);
  std::printf("AUV, start pose, mixture learned: path mean %.2f m, outlier weight %.3f, inlier sigma %.2f sr\n",
              mean_m, slam.outlierWeight(), slam.inlierSigmaScale());
  // Measured (seed 108): 9.9 m, outlier weight 0.57 (true 0.45: the residuals carry the
  // particles' spread of metres too), inlier scale 2.15 sr (true 2 / 0.75 = 2.7 sr). Bounds: the weight well above the configured 0.2, the inlier scale above 1.5.
  EXPECT_GT(slam.outlierWeight(), 0.3);
  EXPECT_GT(slam.inlierSigmaScale(), 1.5);
  // Off, the same run: the configured mixture stays, and the path is worse.
  OnlineEmConfig off;
  setOptions(&off, addOnlineEmOptions, {{"estimate_mixture", "false"}});
  off.outlier_model = OnlineEmConfig::OutlierModel::kGaussian;
  OnlineEmSlam fixed{off};
  feed(data, fixed);
  EXPECT_EQ(fixed.outlierWeight(), 1.0 - off.mixture_weight0);
  EXPECT_GT(meanError(fixed.filteredPath(), data.ground_truth), mean_m);
}

// Issue 15's AUV target: within 1.25 x dead reckoning in both anchors with the defaults, on
// AUV-like runs (odometry 15 % noisy and 3 % short, ranges every 3.3 s, 45 % outliers).
// Before round 4's defaults (heading-rate bias estimated from these sparse ranges, Gaussian
// outlier tail, mixture fixed) seed 108 from the start pose was 48.4 m (1.9 x).
TEST(OnlineEmOutliers, AuvLikeRunsWithinDeadReckoningBound) {
  for (const uint64_t seed : {108u, 203u}) {
    const Dataset data = sim::simulate(sim::auvLikeWorld(seed, 500));
    const double dr_m = deadReckoningError(data);
    for (const std::string anchor : {"start_pose", "beacons"}) {
      OnlineEmConfig config;
      setOptions(&config, addOnlineEmOptions, {{"anchor", anchor}});
      OnlineEmSlam slam(config);
      feed(data, slam);
      const double mean_m = meanError(slam.filteredPath(), data.ground_truth);
      std::printf("AUV seed %d, %s: path mean %.2f m, dead reckoning %.2f m (%.2f x), b %g\n", static_cast<int>(seed),
                  anchor.c_str(), mean_m, dr_m, mean_m / dr_m, slam.odometryCalibration().heading_rate_bias_rad_s);
      // Measured: 108: 9.85 / 3.82 m (DR 25.6); 203: 11.7 / 16.9 m (DR 16.6).
      EXPECT_LT(mean_m, 1.25 * dr_m);
      // The odometry is 15 % noisy against the configured 2 %: the translation noise is inflated.
      EXPECT_GT(slam.diagnostics().at("motion_noise_scale"), 1.5);
      // Ranges every 3.3 s: the bias is not observable and stays 0, and the run says so.
      EXPECT_EQ(slam.odometryCalibration().heading_rate_bias_rad_s, 0.0);
      EXPECT_EQ(slam.diagnostics().at("heading_rate_bias_estimated"), 0.0);
      const auto note = slam.diagnostics().lower_bound("note: held the heading-rate bias at 0");
      ASSERT_NE(note, slam.diagnostics().end());
      EXPECT_NE(note->first.find("more than heading_rate_bias_max_drift_rad (0.080)"), std::string::npos) << note->first;
    }
  }
  // The old defaults on seed 108 from the start pose break the bound (the test can fail).
  const Dataset data = sim::simulate(sim::auvLikeWorld(108, 500));
  OnlineEmConfig old;
  setOptions(&old, addOnlineEmOptions, {{"estimate_mixture", "false"}});
  old.outlier_model = OnlineEmConfig::OutlierModel::kGaussian;
  old.heading_rate_bias_max_drift_rad = 0.0;
  OnlineEmSlam slam(old);
  feed(data, slam);
  EXPECT_GT(meanError(slam.filteredPath(), data.ground_truth), 1.25 * deadReckoningError(data));
  // Seed 302 with surveyed beacons and the paper's range model (no per-beacon offsets, which
  // alone would hold it at 16 m; the per-particle scale spread is off at these range rates
  // anyway): the configured 2 % noise loses the vehicle (38.9 m, DR 19.3 m); adapted to the
  // ranges' innovations, 3.3 m.
  const Dataset auv302 = sim::simulate(sim::auvLikeWorld(302, 500));
  const double dr302_m = deadReckoningError(auv302);
  for (const bool adapt : {false, true}) {
    OnlineEmConfig config;
    setOptions(&config, addOnlineEmOptions,
               {{"anchor", "beacons"}, {"estimate_beacon_range_offsets", "false"}});
    config.distance_scale_particle_sigma = 0.0;  // internal constants
    config.adapt_motion_noise = adapt;
    OnlineEmSlam run(config);
    feed(auv302, run);
    const double mean_m = meanError(run.filteredPath(), auv302.ground_truth);
    std::printf("AUV seed 302, beacons, adapt_motion_noise %d: %.2f m (DR %.2f m)\n", adapt, mean_m, dr302_m);
    if (adapt)
      EXPECT_LT(mean_m, 0.5 * dr302_m);
    else
      EXPECT_GT(mean_m, 1.25 * dr302_m);
  }
}

TEST(OnlineEmDeterminism, SameInputSameOutput) {
  const Dataset data = sim::simulate(noisyPlazaLike(400, 2));
  OnlineEmSlam a{OnlineEmConfig{}}, b{OnlineEmConfig{}};
  feed(data, a);
  feed(data, b);
  ASSERT_EQ(a.filteredPath().size(), b.filteredPath().size());
  for (size_t k = 0; k < a.filteredPath().size(); ++k) {
    EXPECT_EQ(a.filteredPath()[k].x_m, b.filteredPath()[k].x_m);
    EXPECT_EQ(a.filteredPath()[k].y_m, b.filteredPath()[k].y_m);
    EXPECT_EQ(a.filteredPath()[k].heading_rad, b.filteredPath()[k].heading_rad);
  }
  const Map ma = a.currentMap(), mb = b.currentMap();
  ASSERT_EQ(ma.size(), mb.size());
  for (size_t i = 0; i < ma.size(); ++i) EXPECT_EQ(ma[i].x_m, mb[i].x_m);
  // Another seed draws other particles.
  OnlineEmConfig other;
  other.seed = 2;
  OnlineEmSlam c(other);
  feed(data, c);
  EXPECT_NE(a.filteredPath().back().x_m, c.filteredPath().back().x_m);
}

TEST(OnlineEmConfig, BadValuesNameTheKey) {
  auto parse = [](KeyValues values) {
    OnlineEmConfig config;
    Options options(std::move(values));
    addOnlineEmOptions(options, &config);
    options.parse();
    return config;
  };
  try {
    parse({{"num_particles", "1"}});
    FAIL() << "num_particles = 1 accepted";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.key(), "num_particles");
  }
  try {
    parse({{"step_alpha", "0.5"}});  // alpha must be in (1/2, 1]
    FAIL() << "step_alpha = 0.5 accepted";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.key(), "step_alpha");
  }
  try {
    parse({{"num_particle", "10"}});
    FAIL() << "unknown key accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("num_particles"), std::string::npos) << e.what();
  }
  EXPECT_THROW(parse({{"anchor", "gps"}}), ConfigError);
  try {
    parse({{"range_bearing_cov", "1"}});  // |rho| >= sr * sb: R is not positive definite
    FAIL() << "range_bearing_cov = 1 accepted";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.key(), "range_bearing_cov");
    EXPECT_STREQ(e.what(),
                 "expected range_bearing_cov^2 < (range_sigma_m * bearing_sigma_rad)^2 (R positive definite), "
                 "got range_bearing_cov = 1, range_sigma_m = 0.5, bearing_sigma_rad = 0.05235987755982988");
  }
  // A core built from a struct meets the same declared checks, naming the key.
  OnlineEmConfig bad;
  bad.range_bearing_cov = 1.0;
  try {
    OnlineEmSlam slam{bad};
    FAIL() << "range_bearing_cov = 1 accepted";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.key(), "range_bearing_cov");
  }
  bad = OnlineEmConfig{};
  bad.num_particles = 1;
  try {
    OnlineEmSlam slam{bad};
    FAIL() << "num_particles = 1 accepted";
  } catch (const ConfigError& e) {
    EXPECT_STREQ(e.what(), "num_particles: expected a value >= 2, got '1'");
  }
  EXPECT_EQ(parse({{"num_particles", "50"}}).num_particles, 50);
}

}  // namespace
}  // namespace roam
