// The ekf plugin through its C ABI (loaded the way roam-run loads it): config errors name the
// key; a noise-free run is recovered; diagnostics and gating reach the status.
#include <gtest/gtest.h>

#include <cmath>

#include "plugin_library.hpp"
#include "roam/plugin_shim.hpp"
#include "sim.hpp"

namespace roam {
namespace {

constexpr double kRecoveryTolerance_m = 1e-6;

std::shared_ptr<runtime::PluginLibrary> openEkf() {
  return runtime::PluginLibrary::open(ROAM_EKF_PLUGIN_DIR, "ekf");
}

TEST(EkfPlugin, RejectsABadKeyByName) {
  auto library = openEkf();
  EXPECT_STREQ(library->descriptor().name, "ekf");
  try {
    runtime::PluginInstance instance(library, "ekf", {{"anchor", "beacon"}});
    FAIL() << "expected a PluginConfigError";
  } catch (const runtime::PluginConfigError& e) {
    EXPECT_EQ(e.key(), "anchor");
  }
  try {
    runtime::PluginInstance instance(library, "ekf", {{"range_sigma_m", "-1"}});
    FAIL() << "expected a PluginConfigError";
  } catch (const runtime::PluginConfigError& e) {
    EXPECT_EQ(e.key(), "range_sigma_m");
  }
}

TEST(EkfPlugin, TakesTheSensorsNoiseUnlessItsSectionSetsIt) {
  // roam-run hands [sensors] to every estimator as "sensors.<key>" (roam/sensor_noise.hpp).
  auto library = openEkf();
  auto valueOf = [](const KeyValues& values, const std::string& key) {
    for (const auto& [k, v] : values)
      if (k == key) return v;
    return std::string("(missing)");
  };
  runtime::PluginInstance shared(library, "ekf", {{"sensors.range_sigma_m", "0.7"}, {"sensors.bearing_sigma_rad", "0.1"}});
  EXPECT_EQ(valueOf(shared.effectiveConfig(), "range_sigma_m"), "0.7");
  EXPECT_EQ(valueOf(shared.effectiveConfig(), "bearing_sigma_rad"), "0.1");
  runtime::PluginInstance own(library, "ekf", {{"sensors.range_sigma_m", "0.7"}, {"range_sigma_m", "0.3"}});
  EXPECT_EQ(valueOf(own.effectiveConfig(), "range_sigma_m"), "0.3");
  EXPECT_EQ(valueOf(own.effectiveConfig(), "odo_distance_sigma_rel"), "0.02");
}

TEST(EkfPlugin, NoiseFreeRunThroughTheAbi) {
  sim::SimConfig c;
  c.seed = 3;
  c.num_steps = 500;
  c.area_width_m = 20.0;
  c.area_height_m = 15.0;
  c.schedule = sim::RangeSchedule::kRoundRobin;
  const sim::SimRun run = sim::simulate(c);
  // One 20 m outlier on a range late in the run, when every beacon is in the state.
  std::vector<Range> ranges = run.ranges;
  ranges[ranges.size() - 10].range_m += 20.0;

  runtime::PluginInstance ekf(openEkf(), "ekf", {{"anchor", "start_pose"}});
  ASSERT_TRUE(ekf.setInitialPose(shim::toC(run.start)));
  size_t r = 0;
  for (const Odometry& o : run.odometry) {
    while (r < ranges.size() && ranges[r].utime < o.utime) {
      const Range& range = ranges[r++];
      roam_range c_range{range.utime, range.beacon_id, 0, range.range_m, range.sigma_m, 0.0};
      ASSERT_TRUE(ekf.addRange(c_range));
    }
    ASSERT_TRUE(ekf.addOdometry(roam::shim::toC(o)));
  }
  ASSERT_TRUE(ekf.finish());
  std::vector<roam_pose> poses;
  ASSERT_TRUE(ekf.pollPoses(&poses));
  EXPECT_EQ(poses.size(), run.ground_truth.size());  // the start pose, then one per step
  bool available = false;
  std::vector<roam_pose> path;
  ASSERT_TRUE(ekf.pollTrajectory(true, &available, &path));
  ASSERT_TRUE(available);
  ASSERT_EQ(path.size(), run.ground_truth.size());
  for (size_t k = 0; k < path.size(); ++k) {
    EXPECT_NEAR(path[k].x_m, run.ground_truth[k].x_m, kRecoveryTolerance_m);
    EXPECT_NEAR(path[k].y_m, run.ground_truth[k].y_m, kRecoveryTolerance_m);
  }
  bool changed = false;
  std::vector<roam_beacon> map;
  ASSERT_TRUE(ekf.pollMap(&changed, &map));
  EXPECT_EQ(map.size(), 4u);
  for (const roam_beacon& b : map) EXPECT_TRUE(std::isfinite(b.covariance[0]));

  const auto status = ekf.status();
  EXPECT_EQ(status.ranges_rejected, 1);
  EXPECT_EQ(status.last_rejection, "range: gated: Mahalanobis distance beyond gate_probability");
  std::map<std::string, double> diagnostics;
  for (size_t i = 0; i < status.keys.size(); ++i) diagnostics[status.keys[i]] = status.values[i];
  EXPECT_EQ(diagnostics.at("beacons_initialised"), 4.0);
  EXPECT_EQ(diagnostics.at("ranges_gated"), 1.0);
  EXPECT_NEAR(diagnostics.at("range_scale"), 1.0, 1e-9);
}

}  // namespace
}  // namespace roam
