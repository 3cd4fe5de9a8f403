// roam-run on a team's log ([team] robots): each robot's inputs on <CHANNEL>_<robot>, ranges
// between robots on ROBOT_RANGE_<robot>. A one-robot plugin runs once per robot, as on that
// robot's own log; a team plugin (tests/runtime/team_plugin) runs once, told every robot's inputs.
#include <gtest/gtest.h>

#include <lcm/lcm-cpp.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include "dataset_log.hpp"
#include "roam/messages.hpp"
#include "roam/plugin_shim.hpp"
#include "roam/estimator_status_t.hpp"
#include "roam/robot_range_t.hpp"
#include "roam/trajectory_t.hpp"
#include "small_world.hpp"
#include "test_util.hpp"

namespace roam {
namespace {

using testing_util::run;
using testing_util::roamRun;
using testing_util::scratchDir;
using testing_util::writeFile;
namespace fs = std::filesystem;

constexpr int kRangeEverySteps = 5;  // a range from A to B every fifth pose

// Two robots of the small world (different seeds, B started 6 m to the side) and the true
// distance between them every kRangeEverySteps poses, measured by A.
struct TwoRobots {
  Dataset a, b;
  std::vector<std::tuple<int64_t, double>> a_to_b;  // utime, range_m
};

TwoRobots twoRobots() {
  sim::SimConfig config = testing_util::smallWorld();
  TwoRobots team;
  team.a = sim::simulate(config);
  config.seed = 8;
  config.start.y_m = 6.0;
  config.beacons = team.a.beacons;  // one set of beacons for the team
  team.b = sim::simulate(config);
  for (size_t k = 0; k < team.a.ground_truth.size(); k += kRangeEverySteps) {
    const Pose& pa = team.a.ground_truth[k];
    const Pose& pb = team.b.ground_truth[k];
    EXPECT_EQ(pa.utime, pb.utime);  // one clock: same start and step
    team.a_to_b.emplace_back(pa.utime, std::hypot(pa.x_m - pb.x_m, pa.y_m - pb.y_m));
  }
  return team;
}

// The team log, written event by event: BEACONS, each robot's INITIAL_POSE_<R>, then by utime
// each robot's ODOMETRY_<R> and RANGE_<R>, and A's ROBOT_RANGE_A.
void writeTeamLog(const fs::path& path, const TwoRobots& team) {
  lcm::LogFile log(path.string(), "w");
  struct Event {
    int64_t utime;
    int order;
    std::string channel;
    std::vector<uint8_t> bytes;
  };
  std::vector<Event> events;
  auto add = [&](int64_t utime, int order, const std::string& channel, const auto& message) {
    Event event{utime, order, channel, std::vector<uint8_t>(static_cast<size_t>(message.getEncodedSize()))};
    message.encode(event.bytes.data(), 0, static_cast<int>(event.bytes.size()));
    events.push_back(std::move(event));
  };
  std::vector<roam_beacon> beacons;
  for (const Beacon& beacon : team.a.beacons) beacons.push_back(shim::toC(beacon));
  add(0, 0, "BEACONS", toMessage(beacons, 0));
  const std::pair<const char*, const Dataset*> members[] = {{"A", &team.a}, {"B", &team.b}};
  for (const auto& [name, member] : members) {
    const std::string robot = name;
    add(0, 1, "INITIAL_POSE_" + robot, toMessage(shim::toC(member->start)));
    for (const Odometry& odometry : member->odometry) add(odometry.utime, 2, "ODOMETRY_" + robot, toMessage(shim::toC(odometry)));
    for (const Range& range : member->ranges) add(range.utime, 3, "RANGE_" + robot, toMessage(shim::toC(range)));
  }
  for (const auto& [utime, range_m] : team.a_to_b) {
    roam::robot_range_t message;
    message.utime = utime;
    message.other_robot = "B";
    message.range = range_m;
    message.sigma = 0.1;
    add(utime, 4, "ROBOT_RANGE_A", message);
  }
  std::stable_sort(events.begin(), events.end(), [](const Event& x, const Event& y) {
    return std::tie(x.utime, x.order) < std::tie(y.utime, y.order);
  });
  for (Event& event : events) {
    lcm::LogEvent out;
    out.timestamp = event.utime;
    out.channel = event.channel;
    out.datalen = static_cast<int32_t>(event.bytes.size());
    out.data = event.bytes.data();
    ASSERT_EQ(log.writeEvent(&out), 0);
  }
}

// channel -> the last trajectory_t on it; STATUS_ channels -> their last keys and values.
struct Outputs {
  std::map<std::string, roam::trajectory_t> paths;
  std::map<std::string, std::map<std::string, double>> statuses;
};

Outputs readOutputs(const fs::path& path) {
  Outputs out;
  lcm::LogFile log(path.string(), "r");
  for (const lcm::LogEvent* event = log.readNextEvent(); event != nullptr; event = log.readNextEvent()) {
    if (event->channel.rfind("TRAJECTORY_", 0) == 0) {
      roam::trajectory_t message;
      if (message.decode(event->data, 0, event->datalen) >= 0) out.paths[event->channel] = message;
    } else if (event->channel.rfind("STATUS_", 0) == 0) {
      roam::estimator_status_t message;
      if (message.decode(event->data, 0, event->datalen) < 0) continue;
      auto& values = out.statuses[event->channel];
      for (int i = 0; i < message.num_values; ++i) values[message.keys[static_cast<size_t>(i)]] = message.values[static_cast<size_t>(i)];
    }
  }
  return out;
}

std::string teamConfig(const fs::path& input) {
  return "[runtime]\ninput = " + input.string() + "\noutput = result.lcmlog\nplugin_path = " ROAM_TEST_PLUGIN_DIR
         "\n\n[team]\nrobots = A B\n\n[estimator.dr]\nplugin = deadreckoning\n\n[estimator.team]\nplugin = team_dr\n";
}

TEST(TeamRun, EachRobotsPathEqualsItsOwnRunAndTheTeamPluginSeesEveryRange) {
  const fs::path dir = scratchDir("team_run");
  const TwoRobots team = twoRobots();
  writeTeamLog(dir / "team.lcmlog", team);
  const auto result = run(roamRun() + " " + writeFile(dir / "team.ini", teamConfig(dir / "team.lcmlog")).string() +
                          " --no-progress");
  ASSERT_EQ(result.status, 0) << result.output;
  // "input: ... 601 odometry, ... ranges, 61 ranges between robots" (300 steps of each robot; 301
  // poses of A, every fifth: 0, 5, ..., 300).
  EXPECT_NE(result.output.find("600 odometry"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("61 ranges between robots"), std::string::npos) << result.output;

  // Robot B alone, on its own log.
  writeDatasetLog((dir / "b.lcmlog").string(), team.b);
  const auto alone = run(roamRun() + " " +
                         writeFile(dir / "b.ini", "[runtime]\ninput = b.lcmlog\noutput = b-result.lcmlog\n\n"
                                                  "[estimator.dr]\nplugin = deadreckoning\n").string() +
                         " --no-progress");
  ASSERT_EQ(alone.status, 0) << alone.output;

  const Outputs outputs = readOutputs(dir / "result.lcmlog");
  const Outputs b_alone = readOutputs(dir / "b-result.lcmlog");
  for (const char* channel : {"TRAJECTORY_DR_A", "TRAJECTORY_DR_B", "TRAJECTORY_TEAM_A", "TRAJECTORY_TEAM_B"}) {
    ASSERT_TRUE(outputs.paths.count(channel)) << channel;
    EXPECT_EQ(outputs.paths.at(channel).num_poses, 301) << channel;
  }
  EXPECT_FALSE(outputs.paths.count("TRAJECTORY_TEAM"));
  // The one-robot plugin on robot B of the team: its run on B's own log, bit for bit.
  const roam::trajectory_t& dr_b = outputs.paths.at("TRAJECTORY_DR_B");
  const roam::trajectory_t& own_b = b_alone.paths.at("TRAJECTORY_DR");
  EXPECT_EQ(dr_b.x, own_b.x);
  EXPECT_EQ(dr_b.y, own_b.y);
  EXPECT_EQ(dr_b.utimes, own_b.utimes);
  // The team plugin's dead reckoning of each robot: the shipped plugin's, to rounding.
  for (const std::string robot : {"A", "B"}) {
    const roam::trajectory_t& mine = outputs.paths.at("TRAJECTORY_TEAM_" + robot);
    const roam::trajectory_t& shipped = outputs.paths.at("TRAJECTORY_DR_" + robot);
    for (size_t k = 0; k < mine.x.size(); ++k) {
      ASSERT_NEAR(mine.x[k], shipped.x[k], 1e-9) << robot << " pose " << k;
      ASSERT_NEAR(mine.y[k], shipped.y[k], 1e-9) << robot << " pose " << k;
    }
  }
  // B's start is 6 m from A's: the team plugin's paths are not one robot's twice.
  EXPECT_NEAR(outputs.paths.at("TRAJECTORY_TEAM_B").y[0] - outputs.paths.at("TRAJECTORY_TEAM_A").y[0], 6.0, 1e-9);
  // Every range between robots reached the team plugin, named A to B; no one-robot run got one.
  const auto& status = outputs.statuses.at("STATUS_TEAM");
  EXPECT_EQ(status.at("ranges between robots"), 61.0);
  EXPECT_EQ(status.at("ranges from A to B"), 61.0);
}

TEST(TeamRun, ARobotRangeNamingNoMemberIsSkippedAndCounted) {
  const fs::path dir = scratchDir("team_run_unknown");
  TwoRobots team = twoRobots();
  writeTeamLog(dir / "team.lcmlog", team);
  // The same log read as a team of A and C: B's channels are nobody's, A's ranges name no member.
  std::string config = teamConfig(dir / "team.lcmlog");
  config.replace(config.find("robots = A B"), 12, "robots = A C");
  const auto result = run(roamRun() + " " + writeFile(dir / "team.ini", config).string() + " --no-progress");
  ASSERT_EQ(result.status, 0) << result.output;
  EXPECT_NE(result.output.find("0 ranges between robots"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("61 ranges to a robot not in [team] robots (skipped)"), std::string::npos) << result.output;
}

TEST(TeamRun, ATeamNeedsDistinctRobotNames) {
  const fs::path dir = scratchDir("team_run_names");
  const fs::path log = testing_util::writeSmallWorldLog(dir);
  for (const auto& [robots, message] : std::vector<std::pair<std::string, std::string>>{
           {"A A", "[team] robots: 'A' is named twice"},
           {"A B/C", "[team] robots: 'B/C': a robot's name must be letters, digits, '_' or '-'"},
           {"", "[team] robots: missing: name the team's robots"}}) {
    const std::string text = "[runtime]\ninput = " + log.string() + "\n\n[team]\nrobots = " + robots +
                             "\n\n[estimator.dr]\nplugin = deadreckoning\n";
    const auto result = run(roamRun() + " " + writeFile(dir / "team.ini", text).string() + " --print-config");
    EXPECT_EQ(result.status, 2) << robots;
    EXPECT_NE(result.output.find(message), std::string::npos) << result.output;
  }
}

}  // namespace
}  // namespace roam
