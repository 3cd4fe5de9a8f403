// Bad start pose and surveyed beacons (README "Bad input"): non-finite values are rejected by
// the SDK shim before any estimator sees them, counted as "rejected initial pose: not finite"
// and "rejected beacon: not finite"; the good values still arrive.
#include <gtest/gtest.h>

#include <limits>

#include "hardening_util.hpp"
#include "roam/map_t.hpp"
#include "roam/pose_t.hpp"

namespace roam {
namespace hardening {
namespace {

TEST(BadPose, NonFiniteInitialPoseAndBeaconsAreRejected) {
  Events events = cleanEvents();
  ASSERT_EQ(events[0].channel, "INITIAL_POSE");
  ASSERT_EQ(events[1].channel, "BEACONS");
  // A NaN start pose before the good one; a fifth surveyed beacon at (inf, 0) beside the four.
  Event nan_pose = events[0];
  modify<roam::pose_t>(&nan_pose, [](roam::pose_t& m) { m.x = std::numeric_limits<double>::quiet_NaN(); });
  modify<roam::map_t>(&events[1], [](roam::map_t& m) {
    roam::beacon_t bad = m.beacons[0];
    bad.id = 9;
    bad.x = std::numeric_limits<double>::infinity();
    m.beacons.push_back(bad);
    m.num_beacons = static_cast<int32_t>(m.beacons.size());
  });
  const int64_t good_start_utime = events[0].utime;
  nan_pose.utime = good_start_utime - 1;  // earlier, so the good one is not "out of order"
  modify<roam::pose_t>(&nan_pose, [&](roam::pose_t& m) { m.utime = good_start_utime - 1; });
  events.insert(events.begin(), nan_pose);
  const RunResult result = runEveryPlugin("bad_pose", events);
  expectSafeRun(result, countByChannel(events));
  for (const auto& plugin : pluginsInBuild()) {
    SCOPED_TRACE("plugin " + plugin);
    EXPECT_EQ(result.status.at(plugin).value("rejected initial pose: not finite"), 1);
    EXPECT_EQ(result.status.at(plugin).value("rejected beacon: not finite"), 1);
  }
  const Path& dr = result.poses.at("deadreckoning");
  ASSERT_EQ(dr.size(), 301u);
  EXPECT_EQ(dr.front().utime, good_start_utime);  // started from the good pose
}

}  // namespace
}  // namespace hardening
}  // namespace roam
