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
  // deadreckoning ran each robot alone; the team plugin (team_dr) is not named.
  EXPECT_NE(result.output.find("roam-run: note: ran each robot alone, without the 61 ranges between robots (their "
                               "plugins estimate one robot; spectral_batch and ekf solve the team): dr\n"),
            std::string::npos)
      << result.output;

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

// [team] starts withholds the other robots' INITIAL_POSE_<robot> from every estimator: the
// one-robot run of B starts at the origin, A's at its start, and the team plugin (which needs a
// start to dead-reckon from) has no path for B; the effective config says which were given.
TEST(TeamRun, StartsNamesTheRobotsWhoseStartIsGiven) {
  const fs::path dir = scratchDir("team_run_starts");
  writeTeamLog(dir / "team.lcmlog", twoRobots());
  std::string config = teamConfig(dir / "team.lcmlog");
  config.replace(config.find("robots = A B"), 12, "robots = A B\nstarts = A");
  const std::string ini = writeFile(dir / "team.ini", config).string();
  const auto printed = run(roamRun() + " " + ini + " --print-config");
  ASSERT_EQ(printed.status, 0) << printed.output;
  EXPECT_NE(printed.output.find("[team]\nrobots = A B\nstarts = A\n"), std::string::npos) << printed.output;
  const auto result = run(roamRun() + " " + ini + " --no-progress");
  ASSERT_EQ(result.status, 0) << result.output;
  const Outputs outputs = readOutputs(dir / "result.lcmlog");
  EXPECT_EQ(outputs.paths.at("TRAJECTORY_DR_B").x[0], 0.0);
  EXPECT_EQ(outputs.paths.at("TRAJECTORY_DR_B").y[0], 0.0);
  EXPECT_TRUE(outputs.paths.count("TRAJECTORY_TEAM_A"));
  EXPECT_FALSE(outputs.paths.count("TRAJECTORY_TEAM_B"));
  EXPECT_NEAR(outputs.paths.at("TRAJECTORY_DR_A").x[0], twoRobots().a.ground_truth.front().x_m, 1e-9);

  for (const auto& [starts, message] : std::vector<std::pair<std::string, std::string>>{
           {"A C", "[team] starts: 'C' is not one of the team's robots"},
           {"A A", "[team] starts: 'A' is named twice"}}) {
    std::string bad = teamConfig(dir / "team.lcmlog");
    bad.replace(bad.find("robots = A B"), 12, "robots = A B\nstarts = " + starts);
    const auto refused = run(roamRun() + " " + writeFile(dir / "bad.ini", bad).string() + " --print-config");
    EXPECT_EQ(refused.status, 2) << starts;
    EXPECT_NE(refused.output.find(message), std::string::npos) << refused.output;
  }
}

// The SDK's self-check on a team's answer (roam/self_check.hpp, TeamSelfCheck), through roam-run.

// A STATUS key starting with `prefix` whose value is 1 (a note), or "" if none.
std::string noteStartingWith(const std::map<std::string, double>& status, const std::string& prefix) {
  for (const auto& [key, value] : status)
    if (key.rfind(prefix, 0) == 0 && value == 1.0) return key;
  return "";
}

// `config` with the team plugin's section given `keys` (e.g. "heading_bias_rad = 0.01\n").
std::string withTeamKeys(std::string config, const std::string& keys) {
  const std::string section = "plugin = team_dr\n";
  return config.replace(config.find(section), section.size(), section + keys);
}

// Every robot's TRAJECTORY_TEAM_<R> is TRAJECTORY_DR_<R> (the shipped plugin's dead reckoning).
void expectTeamIsDeadReckoning(const Outputs& outputs) {
  for (const std::string robot : {"A", "B"}) {
    const roam::trajectory_t& team = outputs.paths.at("TRAJECTORY_TEAM_" + robot);
    const roam::trajectory_t& dr = outputs.paths.at("TRAJECTORY_DR_" + robot);
    ASSERT_EQ(team.x.size(), dr.x.size()) << robot;
    for (size_t k = 0; k < team.x.size(); ++k) {
      ASSERT_NEAR(team.x[k], dr.x[k], 1e-9) << robot << " pose " << k;
      ASSERT_NEAR(team.y[k], dr.y[k], 1e-9) << robot << " pose " << k;
    }
  }
}

// team_dr turning 0.01 rad a step more than the odometry (B the other way): over 300 steps 3 rad,
// each path curls metres away from the truth (the small world's dead reckoning drifts ~2 % of the
// distance), so it explains the ranges to beacons (1.3 m against 0.08 m) and the 61 exact ranges
// from A to B worse than dead reckoning.
constexpr const char* kDistorted = "heading_bias_rad = 0.01\n";

TEST(TeamRun, SelfCheckLeavesAGoodTeamAnswerAndScoresEveryRange) {
  const fs::path dir = scratchDir("team_check_good");
  writeTeamLog(dir / "team.lcmlog", twoRobots());
  const auto result = run(roamRun() + " " + writeFile(dir / "team.ini", teamConfig(dir / "team.lcmlog")).string() +
                          " --no-progress");
  ASSERT_EQ(result.status, 0) << result.output;
  const Outputs outputs = readOutputs(dir / "result.lcmlog");
  expectTeamIsDeadReckoning(outputs);  // team_dr's exact dead reckoning, left as it is
  const auto& status = outputs.statuses.at("STATUS_TEAM");
  EXPECT_EQ(noteStartingWith(status, TeamSelfCheck::kTeamWorseNote), "");
  EXPECT_EQ(noteStartingWith(status, TeamSelfCheck::kNoRangeNote), "");
  // Scored: A's ranges to beacons, B's, and the 61 from A to B; its paths fit as dead reckoning does.
  for (const std::string robot : {"A", "B"}) {
    ASSERT_TRUE(status.count(TeamSelfCheck::memberKey(SelfCheck::kRangesScored, robot))) << robot;
    EXPECT_GT(status.at(TeamSelfCheck::memberKey(SelfCheck::kRangesScored, robot)), 100.0) << robot;
    EXPECT_NEAR(status.at(TeamSelfCheck::memberKey(SelfCheck::kPathFit, robot)),
                status.at(TeamSelfCheck::memberKey(SelfCheck::kDeadReckoningFit, robot)), 1e-9);
  }
  ASSERT_TRUE(status.count(TeamSelfCheck::kRobotRangesScored));
  EXPECT_EQ(status.at(TeamSelfCheck::kRobotRangesScored), 61.0);
  EXPECT_NEAR(status.at(TeamSelfCheck::kRobotPathFit), status.at(TeamSelfCheck::kRobotDeadReckoningFit), 1e-9);
}

// Distorted, with every range, and with the ranges between robots alone (a robot with ranges to
// other robots only has used ranges: judged, not "no usable range"): replaced by dead reckoning.
TEST(TeamRun, SelfCheckReplacesADistortedTeamAnswerByDeadReckoning) {
  for (const bool beacon_ranges : {true, false}) {
    SCOPED_TRACE(beacon_ranges ? "every range" : "ranges between robots only");
    const fs::path dir = scratchDir(beacon_ranges ? "team_check_bad" : "team_check_bad_robots");
    TwoRobots team = twoRobots();
    if (!beacon_ranges) team.a.ranges.clear(), team.b.ranges.clear();
    writeTeamLog(dir / "team.lcmlog", team);
    const std::string config = withTeamKeys(teamConfig(dir / "team.lcmlog"), kDistorted);
    const auto result = run(roamRun() + " " + writeFile(dir / "team.ini", config).string() + " --no-progress");
    ASSERT_EQ(result.status, 0) << result.output;
    const Outputs outputs = readOutputs(dir / "result.lcmlog");
    expectTeamIsDeadReckoning(outputs);
    const auto& status = outputs.statuses.at("STATUS_TEAM");
    const std::string note = noteStartingWith(status, TeamSelfCheck::kTeamWorseNote);
    ASSERT_NE(note, "");
    EXPECT_NE(note.find("ranges between robots"), std::string::npos) << note;
    EXPECT_EQ(note.find("A, ranges to beacons") != std::string::npos, beacon_ranges) << note;
    EXPECT_EQ(noteStartingWith(status, TeamSelfCheck::kNoRangeNote), "");
    EXPECT_GT(status.at(TeamSelfCheck::kRobotPathFit), status.at(TeamSelfCheck::kRobotDeadReckoningFit));
    // Said at the end of the run too: "note: team self-check: the team's paths ...".
    EXPECT_NE(result.output.find("note: team " + std::string(TeamSelfCheck::kTeamWorseNote).substr(6)), std::string::npos)
        << result.output;
  }
}

// No range between robots: team_dr accepts none (it takes only those), so no robot used a range
// and each publishes its dead reckoning exactly, however its answer was distorted.
TEST(TeamRun, SelfCheckPublishesDeadReckoningForRobotsThatUsedNoRange) {
  const fs::path dir = scratchDir("team_check_no_range");
  TwoRobots team = twoRobots();
  team.a_to_b.clear();
  writeTeamLog(dir / "team.lcmlog", team);
  const std::string config = withTeamKeys(teamConfig(dir / "team.lcmlog"), kDistorted);
  const auto result = run(roamRun() + " " + writeFile(dir / "team.ini", config).string() + " --no-progress");
  ASSERT_EQ(result.status, 0) << result.output;
  const Outputs outputs = readOutputs(dir / "result.lcmlog");
  expectTeamIsDeadReckoning(outputs);
  const auto& status = outputs.statuses.at("STATUS_TEAM");
  for (const std::string robot : {"A", "B"}) {
    bool named = false;
    for (const auto& [key, value] : status)
      named = named || (key.rfind(TeamSelfCheck::kNoRangeNote, 0) == 0 && key.find("(robot " + robot + ")") != std::string::npos);
    EXPECT_TRUE(named) << robot;
  }
}

// The same run twice: the same decision, the same paths and figures, bit for bit.
TEST(TeamRun, SelfCheckRepeatsBitForBit) {
  std::vector<Outputs> runs;
  for (const char* name : {"team_check_repeat_1", "team_check_repeat_2"}) {
    const fs::path dir = scratchDir(name);
    writeTeamLog(dir / "team.lcmlog", twoRobots());
    const std::string config = withTeamKeys(teamConfig(dir / "team.lcmlog"), kDistorted);
    const auto result = run(roamRun() + " " + writeFile(dir / "team.ini", config).string() + " --no-progress");
    ASSERT_EQ(result.status, 0) << result.output;
    runs.push_back(readOutputs(dir / "result.lcmlog"));
  }
  ASSERT_NE(noteStartingWith(runs[0].statuses.at("STATUS_TEAM"), TeamSelfCheck::kTeamWorseNote), "");
  EXPECT_EQ(runs[0].statuses.at("STATUS_TEAM"), runs[1].statuses.at("STATUS_TEAM"));
  for (const char* channel : {"TRAJECTORY_TEAM_A", "TRAJECTORY_TEAM_B"}) {
    EXPECT_EQ(runs[0].paths.at(channel).x, runs[1].paths.at(channel).x) << channel;
    EXPECT_EQ(runs[0].paths.at(channel).y, runs[1].paths.at(channel).y) << channel;
  }
}

}  // namespace
}  // namespace roam
