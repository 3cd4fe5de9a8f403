// Bad ranges (README "Bad input"): each is rejected before any estimator sees it, counted by
// reason in STATUS_<NAME> and in the end summary; everything else is processed as usual.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "hardening_util.hpp"
#include "roam/range_t.hpp"

namespace roam {
namespace hardening {
namespace {

constexpr int kEvery = 10;  // every 10th range is damaged

// Runs the damaged input and the clean one; checks the rejections of `reason` per plugin.
void expectRangesRejected(const std::string& name, const std::vector<double>& values, const std::string& reason,
                          const std::string& plugin_keys = "") {
  Events events = cleanEvents();
  const RunResult clean = runEveryPlugin(name + "_clean", events, plugin_keys);
  int damaged = 0;
  Events bad = events;
  const auto ranges = indicesOf(bad, "RANGE");
  for (size_t k = 0; k < ranges.size(); k += kEvery) {
    const double value = values[(k / kEvery) % values.size()];
    modify<roam::range_t>(&bad[ranges[k]], [&](roam::range_t& m) { m.range = value; });
    ++damaged;
  }
  ASSERT_EQ(damaged, 12);  // 120 ranges (60 s at 2 Hz): the 1st, 11th, ..., 111th
  const RunResult result = runEveryPlugin(name, bad, plugin_keys);
  expectSafeRun(result, countByChannel(bad));
  for (const auto& plugin : pluginsInBuild()) {
    SCOPED_TRACE("plugin " + plugin);
    const Status& status = result.status.at(plugin);
    EXPECT_EQ(status.value("rejected range: " + reason), damaged);
    EXPECT_GE(status.ranges_rejected, damaged);
    // Odometry is untouched: every step the clean run took is taken.
    EXPECT_EQ(status.odometry_accepted, clean.status.at(plugin).odometry_accepted);
    const std::string line = result.summaryLine(plugin);
    EXPECT_NE(line.find("ranges " + std::to_string(status.ranges_rejected) + "/"), std::string::npos) << line;
  }
  // Dead reckoning ignores ranges: its path is the clean run's, bit for bit.
  ASSERT_EQ(result.poses.at("deadreckoning").size(), 301u);
  EXPECT_EQ(result.poses.at("deadreckoning").back().x_m, clean.poses.at("deadreckoning").back().x_m);
  EXPECT_EQ(result.poses.at("deadreckoning").back().y_m, clean.poses.at("deadreckoning").back().y_m);
}

TEST(BadRange, NaNIsRejectedAsNotFinite) {
  expectRangesRejected("range_nan", {std::numeric_limits<double>::quiet_NaN()}, "not finite");
}

TEST(BadRange, InfiniteIsRejectedAsNotFinite) {
  expectRangesRejected("range_inf", {std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()},
                       "not finite");
}

TEST(BadRange, NegativeIsRejectedAsNotPositive) {
  expectRangesRejected("range_negative", {-3.5, -1e-9}, "not positive");
}

TEST(BadRange, ZeroIsRejectedAsNotPositive) {
  expectRangesRejected("range_zero", {0.0, -0.0}, "not positive");
}

TEST(BadRange, ImplausiblyLargeIsRejectedByDefaultMaxRange) {
  // The SDK's max_range_m defaults to 1000 m: 655.35 m passes, these do not.
  expectRangesRejected("range_huge", {1000.001, 1e9, std::numeric_limits<double>::max()}, "longer than max_range_m");
}

TEST(BadRange, LongerThanAConfiguredMaxRangeIsRejected) {
  // The clean ranges of this run are shorter than 60 m, so max_range_m = 60 rejects only the
  // damaged ones.
  double longest_m = 0.0;
  Events events = cleanEvents();
  for (size_t i : indicesOf(events, "RANGE")) {
    modify<roam::range_t>(&events[i], [&](roam::range_t& m) { longest_m = std::max(longest_m, m.range); });
  }
  ASSERT_LT(longest_m, 60.0);
  expectRangesRejected("range_configured", {60.5, 100.0}, "longer than max_range_m", "max_range_m = 60\n");
}

TEST(BadRange, RangesToUnknownBeaconsNeverBreakAnEstimator) {
  // Beacon 99 is not among the surveyed BEACONS (ids 0..3). SLAM estimators may map it as a
  // new beacon, others count and ignore it: either way nothing fails and odometry goes on.
  Events events = cleanEvents();
  const RunResult clean = runEveryPlugin("unknown_beacon_clean", events);
  const auto ranges = indicesOf(events, "RANGE");
  for (size_t k = 0; k < ranges.size(); k += 5) {
    modify<roam::range_t>(&events[ranges[k]], [](roam::range_t& m) { m.beacon_id = 99; });
  }
  const RunResult result = runEveryPlugin("unknown_beacon", events);
  expectSafeRun(result, countByChannel(events));
  for (const auto& plugin : pluginsInBuild()) {
    SCOPED_TRACE("plugin " + plugin);
    EXPECT_EQ(result.status.at(plugin).odometry_accepted, clean.status.at(plugin).odometry_accepted);
  }
  EXPECT_EQ(result.poses.at("deadreckoning").size(), 301u);
}

}  // namespace
}  // namespace hardening
}  // namespace roam
