// Damaged and degenerate logs (README "Bad input"): no ranges, empty, cut inside an event, a
// corrupt sync word, messages that do not decode on known channels.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "hardening_util.hpp"
#include "roam/self_check.hpp"

namespace roam {
namespace hardening {
namespace {

std::string logBytes(const Events& events) {
  const fs::path path = fs::path(ROAM_BINARY_DIR) / "tests" / "scratch" /
                        ("hardening_bytes_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) +
                         ".lcmlog");
  fs::create_directories(path.parent_path());
  writeLog(path, events);
  std::ifstream in(path, std::ios::binary);
  std::ostringstream out;
  out << in.rdbuf();
  return out.str();
}

// The on-disk size of an event: sync word, event number, timestamp, two lengths, channel, data.
size_t eventBytes(const Event& e) { return 4 + 8 + 8 + 4 + 4 + e.channel.size() + e.bytes.size(); }

void putInt32(std::string* bytes, size_t at, int32_t value) {
  for (int i = 0; i < 4; ++i) (*bytes)[at + i] = static_cast<char>((static_cast<uint32_t>(value) >> (24 - 8 * i)) & 0xff);
}

TEST(BadLog, ALogWithNoRangesRunsOnOdometryAlone) {
  Events events = cleanEvents();
  Events no_ranges;
  for (const Event& e : events) {
    if (e.channel != "RANGE") no_ranges.push_back(e);
  }
  const RunResult result = runEveryPlugin("no_ranges", no_ranges);
  expectSafeRun(result, countByChannel(no_ranges));
  for (const auto& plugin : pluginsInBuild()) {
    SCOPED_TRACE("plugin " + plugin);
    EXPECT_EQ(result.status.at(plugin).ranges_accepted + result.status.at(plugin).ranges_rejected, 0);
  }
  EXPECT_NE(result.output.find("input: " + std::to_string(no_ranges.size()) + " events, 300 odometry, 0 ranges"),
            std::string::npos) << result.output;
  EXPECT_EQ(result.poses.at("deadreckoning").size(), 301u);
}

// The SDK's self-check (roam/self_check.hpp): an estimator that accepted no range, because the
// log has none or because every one was rejected (max_range_m below every range), publishes dead
// reckoning exactly as its path, and its STATUS says so. Without the rule the EKF's and online EM's
// motion models (process noise, particles) publish paths of their own.
TEST(BadLog, WithNoUsableRangeEveryEstimatorsPathIsDeadReckoning) {
  Events events = cleanEvents();
  Events no_ranges;
  for (const Event& e : events)
    if (e.channel != "RANGE") no_ranges.push_back(e);
  for (int variant = 0; variant < 2; ++variant) {
    SCOPED_TRACE(variant == 0 ? "no ranges in the log" : "every range rejected");
    const RunResult result = variant == 0 ? runEveryPlugin("self_check_none", no_ranges)
                                          : runEveryPlugin("self_check_rejected", events, "max_range_m = 0.001\n");
    ASSERT_EQ(result.exit_status, 0) << result.output;
    const Path& dead_reckoning = result.poses.at("deadreckoning");
    ASSERT_EQ(dead_reckoning.size(), 301u);
    for (const auto& plugin : pluginsInBuild()) {
      SCOPED_TRACE("plugin " + plugin);
      EXPECT_EQ(result.status.at(plugin).ranges_accepted, 0);
      const auto it = result.trajectory.find(plugin);
      if (it == result.trajectory.end()) continue;  // refused (spectral needs ranges): still refused
      ASSERT_EQ(it->second.size(), dead_reckoning.size());
      for (size_t k = 0; k < dead_reckoning.size(); ++k) {
        ASSERT_NEAR(it->second[k].x_m, dead_reckoning[k].x_m, 1e-9) << k;
        ASSERT_NEAR(it->second[k].y_m, dead_reckoning[k].y_m, 1e-9) << k;
      }
      // Said where the estimator's own path differed (online EM's particles); the EKF's and the
      // batch's already were dead reckoning here.
      if (plugin == "online_em") {
        EXPECT_EQ(result.status.at(plugin).value(SelfCheck::kNote), 1.0);
      }
    }
  }
}

// A file that is not an LCM log is refused as roam-eval refuses it (exit 2, one line naming the
// file), before the output log is opened.
TEST(BadLog, AFileThatIsNotAnLcmLogIsRefused) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"", "input.lcmlog: empty file: not an LCM log (no event to replay)"},
      {"time_s,x_m,y_m\n0,1,2\n", "input.lcmlog: not an LCM log (no event could be read"},
      {"VERTEX_SE2 0 A0 0 0 0\nEDGE_RANGE 0 A0 L0 5.0 0.5\n", "input.lcmlog: not an LCM log (no event could be read"}};
  int index = 0;
  for (const auto& [bytes, expected] : cases) {
    SCOPED_TRACE("case " + std::to_string(index));
    const std::string name = "foreign_" + std::to_string(index++);
    const RunResult result = runEveryPlugin(name, {}, "", "", &bytes);
    EXPECT_FALSE(result.result_log_whole) << "no result log may be written";
    EXPECT_EQ(result.exit_status, 2) << result.output;
    EXPECT_NE(result.output.find("roam-run: error: "), std::string::npos) << result.output;
    EXPECT_NE(result.output.find(expected), std::string::npos) << result.output;
    EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1) << result.output;
  }
}

TEST(BadLog, ALogCutInsideAnEventIsReplayedUpToTheCut) {
  const Events events = cleanEvents();
  const std::string bytes = logBytes(events);
  const std::string cut = bytes.substr(0, bytes.size() - eventBytes(events.back()) / 2);
  const RunResult result = runEveryPlugin("cut", {}, "", "", &cut);
  Events delivered(events.begin(), events.end() - 1);  // all but the cut last event
  expectSafeRun(result, countByChannel(delivered));
  EXPECT_NE(result.output.find("input.lcmlog: the log ends inside an event (cut or corrupt): replayed up to there"),
            std::string::npos) << result.output;
}

TEST(BadLog, ACorruptSyncWordLosesOneEventOnly) {
  const Events events = cleanEvents();
  std::string bytes = logBytes(events);
  // The sync word of ODOMETRY step 150.
  const size_t target = indicesOf(events, "ODOMETRY")[150];
  size_t offset = 0;
  for (size_t i = 0; i < target; ++i) offset += eventBytes(events[i]);
  ASSERT_EQ(static_cast<unsigned char>(bytes[offset]), 0xED);
  bytes[offset] = 'X';
  const RunResult result = runEveryPlugin("sync", {}, "", "", &bytes);
  Events delivered = events;
  delivered.erase(delivered.begin() + static_cast<long>(target));
  expectSafeRun(result, countByChannel(delivered));
  EXPECT_NE(result.output.find("input.lcmlog: " + std::to_string(eventBytes(events[target])) + " corrupt bytes skipped"),
            std::string::npos) << result.output;
  EXPECT_EQ(result.status.at("deadreckoning").odometry_accepted, 299);
}

TEST(BadLog, MessagesThatDoNotDecodeOnKnownChannelsAreSkippedAndCounted) {
  Events events = cleanEvents();
  // ODOMETRY step 40: a wrong type fingerprint. RANGE 20: cut short.
  events[indicesOf(events, "ODOMETRY")[40]].bytes.replace(0, 8, 8, '\x7f');
  events[indicesOf(events, "RANGE")[20]].bytes.resize(20);
  // Before the good INITIAL_POSE and BEACONS: copies whose lengths lie. A pose_t whose
  // estimator string claims length 0 and a map_t claiming 2^31 - 1 beacons (LCM's decoder
  // would throw, or ask for 120 GB) and one claiming -1.
  Event bad_pose = events[0], huge_map = events[1], negative_map = events[1];
  ASSERT_EQ(bad_pose.channel, "INITIAL_POSE");
  ASSERT_EQ(huge_map.channel, "BEACONS");
  putInt32(&bad_pose.bytes, 16, 0);               // hash, utime, then the string length
  putInt32(&huge_map.bytes, 16 + 4 + 1, 0x7fffffff);  // hash, utime, "" (length 1), num_beacons
  putInt32(&negative_map.bytes, 16 + 4 + 1, -1);
  events.insert(events.begin(), {bad_pose, huge_map, negative_map});
  const RunResult result = runEveryPlugin("undecodable", events);
  expectSafeRun(result, countByChannel(events));
  EXPECT_NE(result.output.find(", 5 undecodable (skipped: BEACONS=2 INITIAL_POSE=1 ODOMETRY=1 RANGE=1)"),
            std::string::npos) << result.output;
  for (const auto& plugin : pluginsInBuild()) {
    SCOPED_TRACE("plugin " + plugin);
    EXPECT_EQ(result.status.at(plugin).value("input skipped: undecodable"), 5);
  }
  EXPECT_EQ(result.status.at("deadreckoning").odometry_accepted, 299);
  EXPECT_EQ(result.poses.at("deadreckoning").front().utime, events[3].utime);  // the good start pose
}

}  // namespace
}  // namespace hardening
}  // namespace roam
