// Bad odometry and bad timing (README "Bad input"): NaN steps, jumps faster than max_speed_mps,
// zero-distance steps, time going backwards, duplicate events.
#include <gtest/gtest.h>

#include <limits>

#include "hardening_util.hpp"
#include "roam/odometry_t.hpp"
#include "roam/range_t.hpp"

namespace roam {
namespace hardening {
namespace {

TEST(BadOdometry, NaNStepsAreRejectedAsNotFinite) {
  Events events = cleanEvents();
  const auto steps = indicesOf(events, "ODOMETRY");
  ASSERT_EQ(steps.size(), 300u);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  modify<roam::odometry_t>(&events[steps[50]], [&](roam::odometry_t& m) { m.delta_distance = nan; });
  modify<roam::odometry_t>(&events[steps[150]], [&](roam::odometry_t& m) { m.delta_heading = nan; });
  modify<roam::odometry_t>(&events[steps[250]], [&](roam::odometry_t& m) {
    m.delta_distance = std::numeric_limits<double>::infinity();
  });
  const RunResult result = runEveryPlugin("odometry_nan", events);
  expectSafeRun(result, countByChannel(events));
  for (const auto& plugin : pluginsInBuild()) {
    SCOPED_TRACE("plugin " + plugin);
    const Status& status = result.status.at(plugin);
    EXPECT_EQ(status.value("rejected odometry: not finite"), 3);
    EXPECT_GE(status.odometry_rejected, 3);
    EXPECT_NE(result.summaryLine(plugin).find("odometry " + std::to_string(status.odometry_rejected) + "/300 rejected"),
              std::string::npos) << result.summaryLine(plugin);
  }
  EXPECT_EQ(result.status.at("deadreckoning").odometry_accepted, 297);
  EXPECT_EQ(result.poses.at("deadreckoning").size(), 298u);  // the start pose + 297 steps
}

TEST(BadOdometry, AJumpFasterThanMaxSpeedIsRejected) {
  // An extra 50 m step at the time of step 100 (the steps are 0.2 m; max_speed_mps is 30 m/s by
  // default, over max(dt, 1 s) = 1 s here): rejected; the path is the clean one.
  Events events = cleanEvents();
  const RunResult clean = runEveryPlugin("odometry_jump_clean", events);
  const auto steps = indicesOf(events, "ODOMETRY");
  Event jump = events[steps[100]];
  modify<roam::odometry_t>(&jump, [](roam::odometry_t& m) { m.delta_distance = 50.0; });
  events.insert(events.begin() + static_cast<long>(steps[100]) + 1, jump);
  const RunResult result = runEveryPlugin("odometry_jump", events);
  expectSafeRun(result, countByChannel(events));
  const Status& dr = result.status.at("deadreckoning");
  EXPECT_EQ(dr.value("rejected odometry: faster than max_speed_mps"), 1);
  EXPECT_EQ(dr.odometry_accepted, 300);
  ASSERT_EQ(result.poses.at("deadreckoning").size(), 301u);
  EXPECT_EQ(result.poses.at("deadreckoning").back().x_m, clean.poses.at("deadreckoning").back().x_m);
  EXPECT_EQ(result.poses.at("deadreckoning").back().y_m, clean.poses.at("deadreckoning").back().y_m);
  for (const auto& plugin : pluginsInBuild()) {
    SCOPED_TRACE("plugin " + plugin);
    // Every estimator saw one step more than the clean run; none took more steps than it did.
    const Status& status = result.status.at(plugin);
    EXPECT_EQ(status.odometry_accepted + status.odometry_rejected,
              clean.status.at(plugin).odometry_accepted + clean.status.at(plugin).odometry_rejected + 1);
  }

}

TEST(BadOdometry, ZeroDistanceStepsAreOrdinarySteps) {
  // The robot stands still for 40 steps (100..139) while ranges keep coming: nothing divides
  // by a zero speed, every step is accepted, the dead-reckoned pose does not move.
  Events events = cleanEvents();
  const auto steps = indicesOf(events, "ODOMETRY");
  for (size_t k = 100; k < 140; ++k) {
    modify<roam::odometry_t>(&events[steps[k]], [](roam::odometry_t& m) {
      m.delta_distance = 0.0;
      m.delta_heading = 0.0;
    });
  }
  const RunResult result = runEveryPlugin("odometry_zero", events);
  expectSafeRun(result, countByChannel(events));
  const Status& dr = result.status.at("deadreckoning");
  EXPECT_EQ(dr.odometry_accepted, 300);
  EXPECT_EQ(dr.odometry_rejected, 0);
  const Path& path = result.poses.at("deadreckoning");
  ASSERT_EQ(path.size(), 301u);
  EXPECT_EQ(path[101].x_m, path[140].x_m);  // pose k+1 ends step k
  EXPECT_EQ(path[101].y_m, path[140].y_m);
}

TEST(BadTiming, InputsSwappedWithinTheReorderWindowAreFedInTimeOrder) {
  // Steps 120 and 121 swapped, and ranges 30 and 31: the later of each pair arrives first, 0.2 s
  // and 0.5 s ahead of the other, inside reorder_window_s (1 s). The host feeds them in time order:
  // nothing is skipped, and every estimator publishes what it publishes from the clean log.
  Events events = cleanEvents();
  const RunResult clean = runEveryPlugin("swapped_clean", events);
  const auto steps = indicesOf(events, "ODOMETRY");
  std::swap(events[steps[120]], events[steps[121]]);
  const auto ranges = indicesOf(events, "RANGE");
  std::swap(events[ranges[30]], events[ranges[31]]);
  const RunResult result = runEveryPlugin("swapped", events);
  expectSafeRun(result, countByChannel(events));
  EXPECT_EQ(result.output.find("went backwards"), std::string::npos) << result.output;
  EXPECT_EQ(result.output.find("fed late"), std::string::npos) << result.output;
  for (const auto& plugin : pluginsInBuild()) {
    SCOPED_TRACE("plugin " + plugin);
    EXPECT_EQ(result.status.at(plugin).value("input skipped: out of order"), 0);
    const Path& a = result.poses.at(plugin);
    const Path& b = clean.poses.at(plugin);
    ASSERT_EQ(a.size(), b.size());
    for (size_t k = 0; k < a.size(); ++k) {
      ASSERT_EQ(a[k].x_m, b[k].x_m) << k;  // bit-identical
      ASSERT_EQ(a[k].y_m, b[k].y_m) << k;
    }
  }
  EXPECT_EQ(result.status.at("deadreckoning").odometry_accepted, 300);
}

TEST(BadTiming, TimeGoingBackwardsIsSkippedAndCounted) {
  // The same swaps fed in arrival order (reorder_window_s = 0): the earlier of each pair goes
  // back in time on its channel and is skipped.
  Events events = cleanEvents();
  const auto steps = indicesOf(events, "ODOMETRY");
  std::swap(events[steps[120]], events[steps[121]]);
  const auto ranges = indicesOf(events, "RANGE");
  std::swap(events[ranges[30]], events[ranges[31]]);
  const RunResult result = runEveryPlugin("time_backwards", events, "", "reorder_window_s = 0\n");
  expectSafeRun(result, countByChannel(events));
  EXPECT_NE(result.output.find("roam-run: warning: ODOMETRY: utime went backwards"), std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find(", 2 out of order (skipped)"), std::string::npos) << result.output;
  for (const auto& plugin : pluginsInBuild()) {
    SCOPED_TRACE("plugin " + plugin);
    EXPECT_EQ(result.status.at(plugin).value("input skipped: out of order"), 2);
  }
  EXPECT_EQ(result.status.at("deadreckoning").odometry_accepted, 299);
}

TEST(BadTiming, AStepBehindItsChannelBeyondTheReorderWindowIsSkipped) {
  // Step 120 logged after step 130 (2 s later, beyond the 1 s window): by the time it arrives
  // steps up to 125 have been fed, so it goes back on its channel and is skipped and counted.
  Events events = cleanEvents();
  const auto steps = indicesOf(events, "ODOMETRY");
  const Event late = events[steps[120]];
  events.erase(events.begin() + static_cast<long>(steps[120]));
  events.insert(events.begin() + static_cast<long>(steps[130]), late);  // steps[130] moved down by one
  const RunResult result = runEveryPlugin("step_beyond_window", events);
  expectSafeRun(result, countByChannel(events));
  EXPECT_NE(result.output.find("roam-run: warning: ODOMETRY: utime went backwards"), std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find(", 1 out of order (skipped)"), std::string::npos) << result.output;
  EXPECT_EQ(result.status.at("deadreckoning").odometry_accepted, 299);
  EXPECT_EQ(result.status.at("deadreckoning").value("input skipped: out of order"), 1);
}

TEST(BadTiming, DuplicateEventsAreSkippedAndCounted) {
  // Five odometry steps and three ranges logged twice: the copies are skipped, so the path is
  // the clean one.
  Events events = cleanEvents();
  const RunResult clean = runEveryPlugin("duplicates_clean", events);
  Events doubled;
  int odometry = 0, ranges = 0;
  for (const Event& e : events) {
    doubled.push_back(e);
    if (e.channel == "ODOMETRY" && odometry++ % 60 == 7) doubled.push_back(e);
    if (e.channel == "RANGE" && ranges++ % 40 == 3) doubled.push_back(e);
  }
  ASSERT_EQ(doubled.size(), events.size() + 5 + 3);
  const RunResult result = runEveryPlugin("duplicates", doubled);
  expectSafeRun(result, countByChannel(doubled));
  EXPECT_NE(result.output.find(", 8 duplicates (skipped)"), std::string::npos) << result.output;
  for (const auto& plugin : pluginsInBuild()) {
    SCOPED_TRACE("plugin " + plugin);
    EXPECT_EQ(result.status.at(plugin).value("input skipped: duplicates"), 8);
    EXPECT_EQ(result.status.at(plugin).odometry_accepted, clean.status.at(plugin).odometry_accepted);
    EXPECT_EQ(result.status.at(plugin).ranges_accepted, clean.status.at(plugin).ranges_accepted);
  }
  ASSERT_EQ(result.poses.at("deadreckoning").size(), 301u);
  EXPECT_EQ(result.poses.at("deadreckoning").back().x_m, clean.poses.at("deadreckoning").back().x_m);
}

}  // namespace
}  // namespace hardening
}  // namespace roam
