// Teams as data: the whole-team pyfg reader (utilities/dataset/pyfg_team.hpp) on a hand-written
// file and on MR.CLAM 6, the team log (writeTeamLog) read back channel by channel, roam-import on
// a team file, and roam-sim's team runs (exact ranges between robots, the same bytes per seed).
#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include <array>
#include <cmath>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include "dataset_log.hpp"
#include "pyfg_team.hpp"
#include "roam/odometry_t.hpp"
#include "roam/pose_t.hpp"
#include "roam/range_t.hpp"
#include "roam/robot_range_t.hpp"
#include "team_sim.hpp"
#include "tool_test_util.hpp"

namespace {

const std::string kMrclam = std::string(ROAM_SOURCE_DIR) + "/data/mrclam6/mrclam6.pyfg";

// Three robots, listed B before A (names are read in letter order). Times in seconds.
//   A: poses at 0.5, 1.5, 2.5 s; 2 odometry steps; a range to L0 at A1 (1.5 s, sigma 0.3).
//   B: poses at 1.0, 1.5 s; 1 step; a sighting of L0 at B0 (1.0 s): range |(5, 5)| = sqrt(50),
//      bearing atan2(5, 5) = pi/4, sigma sqrt(0.25) = 0.5; a range to L1 at B1 (1.5 s, sigma 0.2).
//   C: one pose at 3.0 s, nothing else.
//   Between robots, sorted by time: B0-A0 at B0's 1.0 s (robot 1 -> 0, 10 m, sigma 0.02);
//   A2-B1 at A2's 2.5 s (0 -> 1, 8.2 m, sigma 0.1); C0-B0 at C0's 3.0 s (2 -> 1, 10 m, sigma 0.3).
//   Set aside: a pose prior (line 9) and an EDGE_SE2 between two robots (line 19).
const std::string kTeam =
    "VERTEX_XY L0 5 5\n"
    "VERTEX_XY L1 -5 0\n"
    "VERTEX_SE2 1.0 B0 0 0 0\n"
    "VERTEX_SE2 1.5 B1 1 0 0\n"
    "VERTEX_SE2 0.5 A0 10 0 1.5\n"
    "VERTEX_SE2 1.5 A1 10 1 1.5\n"
    "VERTEX_SE2 2.5 A2 10 2 1.5\n"
    "VERTEX_SE2 3.0 C0 0 10 0\n"
    "VERTEX_SE2:PRIOR 0 A0 10 0 1.5 0.01 0 0 0.01 0 0.01\n"
    "EDGE_SE2 0 B0 B1 1 0 0 0.01 0 0 0.01 0 0.0001\n"
    "EDGE_SE2 0 A0 A1 1 0 0 0.04 0 0 0.04 0 0.0004\n"
    "EDGE_SE2 0 A1 A2 1 0.1 0.05 0.04 0 0 0.04 0 0.0004\n"
    "EDGE_RANGE 0 A1 L0 6.4 0.09\n"
    "EDGE_RANGE 0 L1 B1 6.0 0.04\n"
    "EDGE_SE2_XY 0 B0 L0 5 5 0.25 0 0.25\n"
    "EDGE_RANGE 0 A2 B1 8.2 0.01\n"
    "EDGE_RANGE 0 B0 A0 10.0 0.0004\n"
    "EDGE_RANGE 0 C0 B0 10.0 0.09\n"
    "EDGE_SE2 0 A2 B1 -9 -1 0 0.1 0 0 0.1 0 0.01\n";

struct Event {
  std::string channel;
  int64_t timestamp;
  std::vector<uint8_t> data;
};

std::vector<Event> readEvents(const std::string& path) {
  std::vector<Event> events;
  lcm::LogFile log(path, "r");
  EXPECT_TRUE(log.good()) << path;
  while (const lcm::LogEvent* e = log.readNextEvent()) {
    const auto* bytes = static_cast<const uint8_t*>(e->data);
    events.push_back({e->channel, e->timestamp, std::vector<uint8_t>(bytes, bytes + e->datalen)});
  }
  return events;
}

template <typename Message>
Message decode(const Event& event) {
  Message message;
  EXPECT_EQ(message.decode(event.data.data(), 0, static_cast<int>(event.data.size())), static_cast<int>(event.data.size()))
      << event.channel;
  return message;
}

std::string fileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(PyfgTeam, ReadsEveryRobotAndTheRangesBetweenThem) {
  roam_test::ScratchDir dir;
  dir.write("team.pyfg", kTeam);
  const std::string file = dir.file("team.pyfg");
  const roam::TeamImport imported = roam::loadPyfgTeam(file);
  const roam::TeamDataset& team = imported.team;
  ASSERT_EQ(team.robots, (std::vector<std::string>{"A", "B", "C"}));
  ASSERT_EQ(team.members.size(), 3u);
  const roam::Dataset& a = team.members[0];
  const roam::Dataset& b = team.members[1];
  const roam::Dataset& c = team.members[2];
  EXPECT_EQ(a.ground_truth.size(), 3u);
  EXPECT_EQ(b.ground_truth.size(), 2u);
  EXPECT_EQ(c.ground_truth.size(), 1u);
  EXPECT_EQ(a.start.utime, 500000);
  EXPECT_EQ(a.start.x_m, 10.0);
  EXPECT_EQ(a.start.heading_rad, 1.5);
  EXPECT_EQ(c.start.utime, 3000000);
  EXPECT_EQ(c.start.robot, 2);
  ASSERT_EQ(a.odometry.size(), 2u);
  EXPECT_EQ(a.odometry[1].utime, 2500000);
  EXPECT_EQ(a.odometry[1].lateral_m, 0.1);
  EXPECT_EQ(a.odometry[1].delta_heading_rad, 0.05);
  EXPECT_EQ(a.odometry[1].robot, 0);
  ASSERT_EQ(b.odometry.size(), 1u);
  EXPECT_EQ(b.odometry[0].robot, 1);
  EXPECT_TRUE(c.odometry.empty());
  ASSERT_EQ(a.ranges.size(), 1u);
  EXPECT_EQ(a.ranges[0].utime, 1500000);
  EXPECT_EQ(a.ranges[0].range_m, 6.4);
  EXPECT_NEAR(a.ranges[0].sigma_m, 0.3, 1e-12);
  EXPECT_EQ(a.ranges[0].other_robot, -1);
  ASSERT_EQ(b.ranges.size(), 2u);  // the sighting (1.0 s) first
  EXPECT_EQ(b.ranges[0].utime, 1000000);
  EXPECT_NEAR(b.ranges[0].range_m, std::sqrt(50.0), 1e-12);
  EXPECT_TRUE(b.ranges[0].has_bearing);
  EXPECT_NEAR(b.ranges[0].bearing_rad, M_PI / 4, 1e-12);
  EXPECT_NEAR(b.ranges[0].sigma_m, 0.5, 1e-12);
  EXPECT_EQ(b.ranges[0].robot, 1);
  EXPECT_EQ(b.ranges[1].beacon_id, 1);
  EXPECT_NEAR(b.ranges[1].sigma_m, 0.2, 1e-12);
  EXPECT_TRUE(c.ranges.empty());
  for (const roam::Dataset& member : team.members) EXPECT_TRUE(member.beacons.empty());
  ASSERT_EQ(team.beacons.size(), 2u);
  EXPECT_EQ(team.beacons[1].x_m, -5.0);
  ASSERT_EQ(team.robot_ranges.size(), 3u);
  const std::vector<std::array<int64_t, 3>> expected = {{1000000, 1, 0}, {2500000, 0, 1}, {3000000, 2, 1}};
  const double expected_sigma[] = {0.02, 0.1, 0.3};
  const double expected_range[] = {10.0, 8.2, 10.0};
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(team.robot_ranges[i].utime, expected[i][0]) << i;
    EXPECT_EQ(team.robot_ranges[i].robot, expected[i][1]) << i;
    EXPECT_EQ(team.robot_ranges[i].other_robot, expected[i][2]) << i;
    EXPECT_EQ(team.robot_ranges[i].range_m, expected_range[i]) << i;
    EXPECT_NEAR(team.robot_ranges[i].sigma_m, expected_sigma[i], 1e-12) << i;
  }
  EXPECT_EQ(imported.time_unit_s, 1.0);
  EXPECT_EQ(imported.forward_axis, roam::ForwardAxis::kX);
  ASSERT_EQ(imported.notes.size(), 2u);
  EXPECT_EQ(imported.notes[0].rfind(file + ":9: set aside 1 pose prior(s)", 0), 0u) << imported.notes[0];
  EXPECT_EQ(imported.notes[1].rfind(file + ":19: set aside 1 relative pose(s) between two robots", 0), 0u)
      << imported.notes[1];
}

TEST(PyfgTeam, OneRobotIsATeamOfOneAndRefusalsNameTheLine) {
  roam_test::ScratchDir dir;
  dir.write("one.pyfg", "VERTEX_SE2 0 A0 0 0 0\nVERTEX_SE2 1 A1 1 0 0\nEDGE_SE2 0 A0 A1 1 0 0 0.01 0 0 0.01 0 0.0001\n");
  const roam::TeamImport one = roam::loadPyfgTeam(dir.file("one.pyfg"));
  EXPECT_EQ(one.team.robots, std::vector<std::string>{"A"});
  EXPECT_EQ(one.team.members.at(0).odometry.size(), 1u);
  EXPECT_TRUE(one.team.robot_ranges.empty());
  const std::string head = "VERTEX_SE2 0 A0 0 0 0\nVERTEX_SE2 1 A1 1 0 0\nVERTEX_SE2 0 B0 5 0 0\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {head + "EDGE_RANGE 0 A0 A1 1.0 0.01\n", ":4: EDGE_RANGE A0 A1: a range between two poses of one robot is not supported"},
      {head + "EDGE_RANGE 0 A0 B7 1.0 0.01\n", ":4: EDGE_RANGE: b 'B7' has no VERTEX_SE2"},
      {head + "EDGE_RANGE 0 A0 B0 -1 0.01\n", ":4: EDGE_RANGE: range must be > 0, got '-1'"},
      {head + "EDGE_SE2 0 A0 A1 1 0 0 0.01 0 0 0.01 0 0.0001\nVERTEX_SE2 2 B2 5 0 0\n", ":5: pose B2 follows B0"},
  };
  for (const auto& [text, error] : cases) {
    dir.write("bad.pyfg", text);
    try {
      roam::loadPyfgTeam(dir.file("bad.pyfg"));
      ADD_FAILURE() << "accepted: " << text;
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(std::string(e.what()).rfind(dir.file("bad.pyfg") + error, 0), 0u) << e.what();
    }
  }
}

TEST(PyfgTeam, ReadsMrclam6AsATeamOfFive) {
  ROAM_REQUIRE_DATA(kMrclam);
  const roam::TeamImport imported = roam::loadPyfgTeam(kMrclam);
  const roam::TeamDataset& team = imported.team;
  ASSERT_EQ(team.robots, (std::vector<std::string>{"A", "B", "C", "D", "E"}));
  // Per robot, counted from the file (awk on the pose names): VERTEX_SE2 1954 + 2500 + 2417 +
  // 1644 + 2759 = 11,274; odometry one fewer each (11,269 EDGE_SE2); sightings (EDGE_SE2_XY)
  // 1527 + 2607 + 3729 + 1418 + 3840 = 13,121, the data README's per-robot figures.
  const size_t poses[] = {1954, 2500, 2417, 1644, 2759};
  const size_t sightings[] = {1527, 2607, 3729, 1418, 3840};
  size_t all_poses = 0, all_sightings = 0;
  for (size_t r = 0; r < 5; ++r) {
    const roam::Dataset& d = team.members[r];
    EXPECT_EQ(d.ground_truth.size(), poses[r]) << team.robots[r];
    EXPECT_EQ(d.odometry.size(), poses[r] - 1) << team.robots[r];
    EXPECT_EQ(d.ranges.size(), sightings[r]) << team.robots[r];
    for (const roam::Range& range : d.ranges) ASSERT_TRUE(range.has_bearing);
    all_poses += d.ground_truth.size();
    all_sightings += d.ranges.size();
  }
  EXPECT_EQ(all_poses, 11274u);
  EXPECT_EQ(all_sightings, 13121u);
  EXPECT_EQ(team.beacons.size(), 15u);
  EXPECT_EQ(team.beacons.front().id, 6);
  ASSERT_EQ(team.robot_ranges.size(), 3537u);
  // The first: "EDGE_RANGE 1248444191.100000143 A0 B0 3.755529984 0.009879055", at A0's time.
  const roam::Range& first = team.robot_ranges.front();
  EXPECT_EQ(first.utime, 1248444191100000);
  EXPECT_EQ(first.robot, 0);
  EXPECT_EQ(first.other_robot, 1);
  EXPECT_EQ(first.range_m, 3.755529984);
  EXPECT_NEAR(first.sigma_m, std::sqrt(0.009879055), 1e-15);
  for (size_t i = 1; i < team.robot_ranges.size(); ++i) ASSERT_LE(team.robot_ranges[i - 1].utime, team.robot_ranges[i].utime);
  EXPECT_EQ(imported.time_unit_s, 1.0);
}

TEST(TeamLog, EveryChannelReadsBackInUtimeOrder) {
  roam_test::ScratchDir dir;
  dir.write("team.pyfg", kTeam);
  const roam::TeamDataset team = roam::loadPyfgTeam(dir.file("team.pyfg")).team;
  const roam::TeamLogWriteSummary summary = roam::writeTeamLog(dir.file("team.lcmlog"), team);
  const std::vector<Event> events = readEvents(dir.file("team.lcmlog"));
  // The header at the earliest start (A0, 0.5 s), then by utime: ground truth, odometry, range,
  // robot range, robot by robot within each (see kTeam's comment for the items' times).
  const std::vector<std::string> channels = {
      "INITIAL_POSE_A", "INITIAL_POSE_B", "INITIAL_POSE_C", "BEACONS",
      "GROUND_TRUTH_A",                                                       // 0.5 s
      "GROUND_TRUTH_B", "RANGE_B", "ROBOT_RANGE_B",                           // 1.0 s
      "GROUND_TRUTH_A", "GROUND_TRUTH_B", "ODOMETRY_A", "ODOMETRY_B", "RANGE_A", "RANGE_B",  // 1.5 s
      "GROUND_TRUTH_A", "ODOMETRY_A", "ROBOT_RANGE_A",                        // 2.5 s
      "GROUND_TRUTH_C", "ROBOT_RANGE_C"};                                     // 3.0 s
  ASSERT_EQ(events.size(), channels.size());
  EXPECT_EQ(summary.events, static_cast<long>(channels.size()));
  for (size_t i = 0; i < channels.size(); ++i) EXPECT_EQ(events[i].channel, channels[i]) << i;
  for (size_t i = 0; i < 4; ++i) EXPECT_EQ(events[i].timestamp, 500000) << i;
  for (size_t i = 1; i < events.size(); ++i) EXPECT_LE(events[i - 1].timestamp, events[i].timestamp) << i;
  const auto start_b = decode<roam::pose_t>(events[1]);
  EXPECT_EQ(start_b.utime, 1000000);  // the pose keeps its own time
  const auto robot_range = decode<roam::robot_range_t>(events[7]);
  EXPECT_EQ(robot_range.utime, 1000000);
  EXPECT_EQ(robot_range.other_robot, "A");
  EXPECT_EQ(robot_range.range, 10.0);
  EXPECT_NEAR(robot_range.sigma, 0.02, 1e-12);
  const auto sighting = decode<roam::range_t>(events[6]);
  EXPECT_TRUE(sighting.has_bearing);
  EXPECT_NEAR(sighting.range, std::sqrt(50.0), 1e-12);
  const auto step = decode<roam::odometry_t>(events[15]);
  EXPECT_EQ(step.utime, 2500000);
  EXPECT_EQ(summary.members.at(1).ranges, 2);
  EXPECT_EQ(summary.robot_ranges, (std::vector<long>{1, 1, 1}));
  roam::TeamDataset broken = team;
  broken.robot_ranges[0].other_robot = 7;
  EXPECT_THROW(roam::writeTeamLog(dir.file("broken.lcmlog"), broken), std::invalid_argument);
}

TEST(TeamLog, RoamImportWritesATeamFileAsATeamLog) {
  ROAM_REQUIRE_DATA(kMrclam);
  roam_test::ScratchDir dir;
  const std::string log = dir.file("team.lcmlog");
  const auto result = roam_test::runTool(roam_test::tool("roam-import") + " " + kMrclam + " -o " + log);
  ASSERT_EQ(result.status, 0) << result.out;
  EXPECT_NE(result.out.find("a team of 5 robots, 39207 events (3537 ranges between robots, 15 beacons)"), std::string::npos)
      << result.out;
  EXPECT_NE(result.out.find("roam-import: robot A: 1953 odometry, 1527 ranges to beacons, 387 ranges to robots, 1954 "
                            "ground truth"),
            std::string::npos)
      << result.out;
  EXPECT_NE(result.out.find("roam-import: the team's beacons: 15 (ids 6 7 8"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("roam-import: config: [team] robots = A B C D E\n"), std::string::npos) << result.out;
  std::map<std::string, long> counts;
  for (const Event& e : readEvents(log)) ++counts[e.channel];
  EXPECT_EQ(counts["BEACONS"], 1);
  EXPECT_EQ(counts["INITIAL_POSE_D"], 1);
  EXPECT_EQ(counts["GROUND_TRUTH_E"], 2759);
  EXPECT_EQ(counts["ODOMETRY_C"], 2416);
  EXPECT_EQ(counts["RANGE_B"], 2607);
  EXPECT_EQ(counts["ROBOT_RANGE_A"] + counts["ROBOT_RANGE_B"] + counts["ROBOT_RANGE_C"] + counts["ROBOT_RANGE_D"] +
                counts["ROBOT_RANGE_E"],
            3537);
  EXPECT_EQ(counts.count("ODOMETRY"), 0u);
  // --robot still reads one robot.
  const auto one = roam_test::runTool(roam_test::tool("roam-import") + " " + kMrclam + " -o " + log + " --robot D");
  EXPECT_EQ(one.status, 0) << one.out;
  EXPECT_NE(one.out.find("(1643 odometry, 1418 ranges, 1644 ground truth, 15 beacons)"), std::string::npos) << one.out;
}

TEST(TeamSim, ExactRangesAreTheDistanceBetweenTheRobots) {
  roam::sim::TeamSimConfig config;
  config.num_robots = 3;
  config.robot.num_steps = 400;
  config.robot.path = roam::sim::PathKind::kRandomWalk;
  config.robot.schedule = roam::sim::RangeSchedule::kRoundRobin;
  config.robot_range_rate_hz = 2.0;
  const roam::TeamDataset team = roam::sim::simulateTeam(config);
  ASSERT_EQ(team.robots, (std::vector<std::string>{"A", "B", "C"}));
  // 400 steps of 0.2 s = 80 s; 3 pairs at 2 Hz each = one range every 1/6 s: 480.
  ASSERT_EQ(team.robot_ranges.size(), 480u);
  std::map<int64_t, size_t> step_of;
  for (size_t k = 0; k < team.members[0].ground_truth.size(); ++k) step_of[team.members[0].ground_truth[k].utime] = k;
  std::vector<int> measured(3, 0);
  for (const roam::Range& r : team.robot_ranges) {
    ASSERT_TRUE(step_of.count(r.utime)) << r.utime;
    const roam::Pose& a = team.members.at(static_cast<size_t>(r.robot)).ground_truth.at(step_of[r.utime]);
    const roam::Pose& b = team.members.at(static_cast<size_t>(r.other_robot)).ground_truth.at(step_of[r.utime]);
    ASSERT_EQ(a.utime, r.utime);
    ASSERT_EQ(b.utime, r.utime);
    EXPECT_NEAR(r.range_m, std::hypot(a.x_m - b.x_m, a.y_m - b.y_m), 1e-9);
    ++measured[static_cast<size_t>(r.robot)];
  }
  for (int count : measured) EXPECT_GT(count, 0);
  // Distinct starts, own noise streams, the team's beacons.
  const roam::Pose& start_a = team.members[0].start;
  const roam::Pose& start_b = team.members[1].start;
  EXPECT_NEAR(std::hypot(start_a.x_m - start_b.x_m, start_a.y_m - start_b.y_m), config.robot_spacing_m, 1e-12);
  EXPECT_NE(team.members[1].ground_truth.back().x_m, team.members[2].ground_truth.back().x_m);
  EXPECT_EQ(team.beacons.size(), 4u);
  for (size_t r = 0; r < 3; ++r) {
    EXPECT_TRUE(team.members[r].beacons.empty());
    EXPECT_FALSE(team.members[r].ranges.empty());
    EXPECT_EQ(team.members[r].odometry.back().robot, static_cast<int>(r));
  }
}

TEST(TeamSim, RoamSimTeamRunsAreTheSameBytesForTheSameSeed) {
  roam_test::ScratchDir dir;
  const std::string sim = roam_test::tool("roam-sim") +
                          " --robots 3 --steps 200 --path figure8 --schedule round_robin --range-sigma 0.2 "
                          "--outlier-fraction 0.1 --odo-distance-sigma-rel 0.02 --odo-heading-sigma 0.003 -o ";
  const auto first = roam_test::runTool(sim + dir.file("a.lcmlog") + " --seed 7");
  ASSERT_EQ(first.status, 0) << first.out;
  EXPECT_NE(first.out.find("a team of 3 robots"), std::string::npos) << first.out;
  ASSERT_EQ(roam_test::runTool(sim + dir.file("b.lcmlog") + " --seed 7").status, 0);
  ASSERT_EQ(roam_test::runTool(sim + dir.file("c.lcmlog") + " --seed 8").status, 0);
  const std::string a = fileBytes(dir.file("a.lcmlog"));
  EXPECT_FALSE(a.empty());
  EXPECT_EQ(a, fileBytes(dir.file("b.lcmlog")));
  EXPECT_NE(a, fileBytes(dir.file("c.lcmlog")));
  std::map<std::string, long> counts;
  for (const Event& e : readEvents(dir.file("a.lcmlog"))) ++counts[e.channel];
  EXPECT_EQ(counts["ODOMETRY_C"], 200);
  EXPECT_EQ(counts["ROBOT_RANGE_A"] + counts["ROBOT_RANGE_B"] + counts["ROBOT_RANGE_C"], 120);  // 40 s, 3 pairs, 1 Hz
  // No beacons at all is a team run too; not for one robot.
  const auto bare = roam_test::runTool(roam_test::tool("roam-sim") + " --robots 2 --beacons 0 --steps 50 --schedule "
                                       "round_robin -o " + dir.file("d.lcmlog"));
  EXPECT_EQ(bare.status, 0) << bare.out;
  EXPECT_NE(bare.out.find("0 beacons"), std::string::npos) << bare.out;
  const auto alone = roam_test::runTool(roam_test::tool("roam-sim") + " --beacons 0 -o " + dir.file("e.lcmlog"));
  EXPECT_EQ(alone.status, 2) << alone.out;
}

}  // namespace
