// roam-eval and roam-export on a small team result log written here (robots A, B, C), with
// hand-made ground truth and estimates; every expected figure is worked out in this file.
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "../common/fixture_log.hpp"
#include "roam/estimator_status_t.hpp"
#include "roam/odometry_t.hpp"
#include "roam/pose_t.hpp"
#include "roam/trajectory_t.hpp"
#include "tool_test_util.hpp"

namespace {

constexpr double kTolerance = 1e-9;
constexpr int kPoses = 10;  // t = 0..9 s per robot

using roam::test::FixtureLog;
using roam::test::fixturePose;

// Ground truth at t: A (t, 0), B (0, t), C (t, 5).
struct Point {
  double x, y;
};
Point truth(char robot, int t) {
  if (robot == 'A') return {double(t), 0.0};
  if (robot == 'B') return {0.0, double(t)};
  return {double(t), 5.0};
}

// "rot": every robot's path is its truth rotated by 90 degrees about (2, 1):
// (x, y) -> (2 - (y - 1), 1 + (x - 2)). Its error at a pose is |R p' - p'| for p' = p - (2, 1),
// i.e. sqrt(2) |p - (2, 1)|: unaligned > 0; one rigid motion undoes it for the whole team: 0.
Point rotated(Point p) { return {2.0 - (p.y - 1.0), 1.0 + (p.x - 2.0)}; }

// The team log:
// - GROUND_TRUTH_A/B/C, INITIAL_POSE_A and ODOMETRY_A (dead reckoning the log does not hold as an
//   estimator: roam-eval must not invent an "odometry" row), BEACONS {1 at (10, 10)}.
// - "ekf_x" (a name with '_': channels TRAJECTORY_EKF_X_A, ...): A = truth + (0.3, 0.4), error
//   0.5 m each; B = truth exactly, 0 m; no path for C. MAP_EKF_X beacon 1 at (13, 14): 5 m.
//   STATUS_EKF_X cpu 1.5 s.
//   Team unaligned: 10 x 0.5 and 10 x 0 -> mean 0.25, RMSE sqrt(10 x 0.25 / 20) = sqrt(0.125);
//   coverage 20 / 30 poses.
// - "rot": POSE_ROT_A/B/C, every path rotated() as above.
std::string writeTeamLog(const roam_test::ScratchDir& dir) {
  const std::string path = dir.file("team.lcmlog");
  FixtureLog log(path);
  log.write("BEACONS", 0, roam::test::fixtureMap({{1, 10, 10}}));
  log.write("INITIAL_POSE_A", 0, fixturePose(0, 0, 0));
  std::map<char, roam::trajectory_t> ekf;
  for (int t = 0; t < kPoses; ++t) {
    const int64_t utime = t * 1000000LL;
    for (char robot : {'A', 'B', 'C'}) {
      const Point p = truth(robot, t);
      log.write(std::string("GROUND_TRUTH_") + robot, utime, fixturePose(utime, p.x, p.y));
      const Point r = rotated(p);
      log.write(std::string("POSE_ROT_") + robot, utime, fixturePose(utime, r.x, r.y, "rot"));
      roam::trajectory_t& trajectory = ekf[robot];
      trajectory.estimator = "ekf_x";
      trajectory.utimes.push_back(utime);
      trajectory.x.push_back(p.x + (robot == 'A' ? 0.3 : 0.0));
      trajectory.y.push_back(p.y + (robot == 'A' ? 0.4 : 0.0));
      trajectory.heading.push_back(0.0);
      trajectory.num_poses = t + 1;
      trajectory.utime = utime;
    }
    if (t > 0) {
      roam::odometry_t odometry{};
      odometry.utime = utime;
      odometry.delta_distance = 1.0;
      log.write("ODOMETRY_A", utime, odometry);
    }
  }
  log.write("TRAJECTORY_EKF_X_A", 9000000, ekf['A']);
  log.write("TRAJECTORY_EKF_X_B", 9000000, ekf['B']);
  roam::map_t map = roam::test::fixtureMap({{1, 13, 14}});
  map.estimator = "ekf_x";
  log.write("MAP_EKF_X", 9000000, map);
  roam::estimator_status_t status{};
  status.estimator = "ekf_x";
  status.state = roam::estimator_status_t::FINISHED;
  status.cpu_total_s = 1.5;
  log.write("STATUS_EKF_X", 9000000, status);
  return path;
}

double rotUnalignedMean() {
  double sum = 0;
  for (char robot : {'A', 'B', 'C'})
    for (int t = 0; t < kPoses; ++t) sum += std::sqrt(2.0) * std::hypot(truth(robot, t).x - 2.0, truth(robot, t).y - 1.0);
  return sum / (3 * kPoses);
}

std::vector<std::string> split(const std::string& line, char separator) {
  std::vector<std::string> fields;
  std::stringstream in(line);
  std::string field;
  while (std::getline(in, field, separator)) fields.push_back(field);
  if (!line.empty() && line.back() == separator) fields.push_back("");
  return fields;
}

// The CSV row of (estimator, robot) as header -> value.
std::map<std::string, std::string> csvRow(const std::string& csv, const std::string& estimator,
                                          const std::string& robot) {
  std::stringstream in(csv);
  std::string line;
  std::getline(in, line);
  const std::vector<std::string> header = split(line, ',');
  while (std::getline(in, line)) {
    const std::vector<std::string> fields = split(line, ',');
    std::map<std::string, std::string> row;
    for (size_t i = 0; i < header.size() && i < fields.size(); ++i) row[header[i]] = fields[i];
    if (row["estimator"] == estimator && row["robot"] == robot) return row;
  }
  return {};
}

// The text table's cells of the row starting with `estimator` (cells are 2+ spaces apart).
std::vector<std::string> textRow(const std::string& text, const std::string& estimator) {
  std::stringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind(estimator + " ", 0) != 0) continue;
    std::vector<std::string> cells;
    size_t i = 0;
    while (i < line.size()) {
      const size_t end = line.find("  ", i);
      cells.push_back(line.substr(i, end == std::string::npos ? std::string::npos : end - i));
      if (end == std::string::npos) break;
      i = line.find_first_not_of(' ', end);
    }
    return cells;
  }
  return {};
}

TEST(TeamEval, TableShowsTheTeamAndEachRobot) {
  roam_test::ScratchDir dir;
  const std::string log = writeTeamLog(dir);
  const roam_test::ToolResult r = roam_test::runTool(roam_test::tool("roam-eval") + " " + log + " --metric mean");
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("team: team of 3 robots (A, B, C)"), std::string::npos) << r.out;
  for (const char* text : {"team mean (m)", "team aligned mean (m)", "A mean (m)", "B mean (m)", "C mean (m)"})
    EXPECT_NE(r.out.find(text), std::string::npos) << text << "\n" << r.out;
  EXPECT_EQ(r.out.find("odometry"), std::string::npos) << r.out;  // not an estimator of this log
  // estimator, team mean, team aligned mean, A, B, C, beacons, CPU, coverage.
  const std::vector<std::string> ekf = textRow(r.out, "ekf_x");
  ASSERT_EQ(ekf.size(), 9u) << r.out;
  EXPECT_EQ(ekf[1], "(0.25)");  // 67 % of the team's poses: in parentheses
  EXPECT_EQ(ekf[3], "0.50");
  EXPECT_EQ(ekf[4], "0.00");
  EXPECT_EQ(ekf[5], "no path");
  EXPECT_EQ(ekf[6], "5.00");
  EXPECT_EQ(ekf[7], "1.500");
  EXPECT_EQ(ekf[8], "67 % (partial)");
  const std::vector<std::string> rot = textRow(r.out, "rot");
  ASSERT_EQ(rot.size(), 9u) << r.out;
  char expected[32];
  std::snprintf(expected, sizeof expected, "%.2f", rotUnalignedMean());
  EXPECT_EQ(rot[1], expected);
  EXPECT_EQ(rot[2], "0.00");
  EXPECT_EQ(rot[8], "100 %");
}

TEST(TeamEval, CsvFiguresMatchAnIndependentComputation) {
  roam_test::ScratchDir dir;
  const std::string log = writeTeamLog(dir);
  const roam_test::ToolResult r = roam_test::runTool(roam_test::tool("roam-eval") + " " + log + " --format csv");
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find(",coverage,ranked,robot,team_aligned_mean_m,team_aligned_rmse_m\n"), std::string::npos);

  const auto ekf = csvRow(r.out, "ekf_x", "team");
  ASSERT_FALSE(ekf.empty()) << r.out;
  EXPECT_EQ(ekf.at("matched"), "20");
  EXPECT_NEAR(std::stod(ekf.at("full_mean_m")), 0.25, kTolerance);
  EXPECT_NEAR(std::stod(ekf.at("full_rmse_m")), std::sqrt(0.125), kTolerance);
  EXPECT_NEAR(std::stod(ekf.at("max_m")), 0.5, kTolerance);
  EXPECT_NEAR(std::stod(ekf.at("beacon_error_m")), 5.0, kTolerance);
  EXPECT_NEAR(std::stod(ekf.at("coverage")), 20.0 / 30.0, kTolerance);
  // One motion for A and B together cannot undo A's offset against B: a translation by half of
  // it leaves 0.25 m everywhere; no rigid fit does better than some, none reaches 0.
  EXPECT_GT(std::stod(ekf.at("team_aligned_mean_m")), 0.1);
  EXPECT_LE(std::stod(ekf.at("team_aligned_mean_m")), 0.25 + kTolerance);

  const auto a = csvRow(r.out, "ekf_x", "A");
  ASSERT_FALSE(a.empty()) << r.out;
  EXPECT_EQ(a.at("scored"), "trajectory");
  EXPECT_EQ(a.at("matched"), "10");
  EXPECT_NEAR(std::stod(a.at("full_mean_m")), 0.5, kTolerance);  // offset (0.3, 0.4)
  EXPECT_NEAR(std::stod(a.at("last10_mean_m")), 0.5, kTolerance);
  EXPECT_EQ(a.at("ranked"), "true");
  const auto b = csvRow(r.out, "ekf_x", "B");
  EXPECT_NEAR(std::stod(b.at("full_mean_m")), 0.0, kTolerance);
  const auto c = csvRow(r.out, "ekf_x", "C");
  ASSERT_FALSE(c.empty()) << r.out;
  EXPECT_EQ(c.at("scored"), "none");
  EXPECT_EQ(c.at("matched"), "0");
  EXPECT_EQ(c.at("full_mean_m"), "");
  EXPECT_EQ(c.at("ranked"), "false");

  const auto rot = csvRow(r.out, "rot", "team");
  ASSERT_FALSE(rot.empty()) << r.out;
  EXPECT_EQ(rot.at("matched"), "30");
  EXPECT_GT(std::stod(rot.at("full_mean_m")), 1.0);
  EXPECT_NEAR(std::stod(rot.at("full_mean_m")), rotUnalignedMean(), kTolerance);
  EXPECT_LT(std::stod(rot.at("team_aligned_mean_m")), 1e-9);
  EXPECT_EQ(csvRow(r.out, "rot", "C").at("scored"), "poses");
}

TEST(TeamEval, AlignedAlignsEachRobotAloneButTheTeamAsOne) {
  roam_test::ScratchDir dir;
  const std::string log = writeTeamLog(dir);
  const roam_test::ToolResult r =
      roam_test::runTool(roam_test::tool("roam-eval") + " " + log + " --format csv --aligned");
  ASSERT_EQ(r.status, 0) << r.out;
  // Robot A alone is the truth translated: 0 once aligned; the team's one fit still leaves error.
  EXPECT_NEAR(std::stod(csvRow(r.out, "ekf_x", "A").at("full_mean_m")), 0.0, 1e-9);
  EXPECT_GT(std::stod(csvRow(r.out, "ekf_x", "team").at("team_aligned_mean_m")), 0.1);
  const roam_test::ToolResult text = roam_test::runTool(roam_test::tool("roam-eval") + " " + log + " --aligned");
  EXPECT_NE(text.out.find("A aligned mean (m)"), std::string::npos) << text.out;
}

TEST(TeamEval, JsonHasTheTeamAndEachRobot) {
  roam_test::ScratchDir dir;
  const std::string log = writeTeamLog(dir);
  const roam_test::ToolResult r = roam_test::runTool(roam_test::tool("roam-eval") + " " + log + " --format json");
  ASSERT_EQ(r.status, 0) << r.out;
  for (const char* text : {"\"ground_truth\": 30, \"robots\": [\"A\", \"B\", \"C\"]", "{\"estimator\": \"ekf_x\", \"team\": {\"matched\": 20, \"unaligned\": {\"mean_m\": 0.25,",
                           "\"C\": {\"scored\": null, \"matched\": 0,", "\"A\": {\"scored\": \"trajectory\", \"matched\": 10,"})
    EXPECT_NE(r.out.find(text), std::string::npos) << text << "\n" << r.out;
}

TEST(TeamEval, ATeamLogBesideASingleRobotLogGetsItsOwnTable) {
  roam_test::ScratchDir dir;
  const std::string team = writeTeamLog(dir);
  const std::string single = dir.file("single.lcmlog");
  {
    FixtureLog log(single);
    for (int t = 0; t < 5; ++t) {
      log.write("GROUND_TRUTH", t * 1000000LL, fixturePose(t * 1000000LL, t, 0));
      log.write("POSE_EKF_X", t * 1000000LL, fixturePose(t * 1000000LL, t, 0.5, "ekf_x"));
    }
  }
  const roam_test::ToolResult r =
      roam_test::runTool(roam_test::tool("roam-eval") + " " + single + " " + team + " --metric mean");
  ASSERT_EQ(r.status, 0) << r.out;
  // The single robot's table first, as alone; then a blank line and the team's own table.
  EXPECT_EQ(r.out.rfind("estimator  segment", 0), 0u) << r.out;
  EXPECT_NE(r.out.find("single mean (m)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("coverage              100 %\n\nteam: team of 3 robots"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("no GROUND_TRUTH"), std::string::npos) << r.out;
}

TEST(TeamEval, AnEstimatorThatPublishedNoPathIsListedWithNone) {
  // Robots A and B; "quiet" only reported its status: exit 0, its row says "no path" for both.
  roam_test::ScratchDir dir;
  const std::string path = dir.file("quiet.lcmlog");
  {
    FixtureLog log(path);
    log.write("GROUND_TRUTH_A", 0, fixturePose(0, 0, 0));
    log.write("GROUND_TRUTH_B", 0, fixturePose(0, 1, 0));
    roam::estimator_status_t status{};
    status.estimator = "quiet";
    status.state = roam::estimator_status_t::FAILED;
    log.write("STATUS_QUIET", 0, status);
  }
  const roam_test::ToolResult r = roam_test::runTool(roam_test::tool("roam-eval") + " " + path + " --metric mean");
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("estimator 'quiet' failed"), std::string::npos) << r.out;
  const std::vector<std::string> quiet = textRow(r.out, "quiet");
  ASSERT_EQ(quiet.size(), 8u) << r.out;
  EXPECT_EQ(quiet[1], "-");
  EXPECT_EQ(quiet[3], "no path");
  EXPECT_EQ(quiet[4], "no path");
  EXPECT_EQ(quiet[7], "0 % (partial)");
}

std::vector<std::vector<double>> tumRows(const std::string& text) {
  std::vector<std::vector<double>> rows;
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    std::istringstream fields(line);
    std::vector<double> row;
    double value;
    while (fields >> value) row.push_back(value);
    rows.push_back(row);
  }
  return rows;
}

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(TeamExport, RobotWritesThatRobotsPathAsTum) {
  roam_test::ScratchDir dir;
  const std::string log = writeTeamLog(dir);
  const roam_test::ToolResult a = roam_test::runTool(roam_test::tool("roam-export") + " " + log +
                                                     " --estimator ekf_x --robot A --format tum");
  ASSERT_EQ(a.status, 0) << a.out;
  const auto rows = tumRows(a.out);
  ASSERT_EQ(rows.size(), 10u) << a.out;
  // t = 2: A's truth (2, 0) + (0.3, 0.4), heading 0: quaternion (0, 0, 0, 1).
  const std::vector<double> expected{2.0, 2.3, 0.4, 0, 0, 0, 0, 1};
  ASSERT_EQ(rows[2].size(), 8u);
  for (size_t i = 0; i < 8; ++i) EXPECT_NEAR(rows[2][i], expected[i], kTolerance) << i;

  const roam_test::ToolResult truth =
      roam_test::runTool(roam_test::tool("roam-export") + " " + log + " --ground-truth --robot B --format tum");
  ASSERT_EQ(truth.status, 0) << truth.out;
  EXPECT_EQ(truth.out.substr(0, 46), "0.000000 0 0 0 0 0 0 1\n1.000000 0 1 0 0 0 0 1\n");

  const roam_test::ToolResult none =
      roam_test::runTool(roam_test::tool("roam-export") + " " + log + " --estimator ekf_x --robot C");
  EXPECT_EQ(none.status, 2);
  EXPECT_EQ(none.out, "roam-export: error: " + log + ": estimator 'ekf_x' published no path for robot C\n");
  const roam_test::ToolResult stranger =
      roam_test::runTool(roam_test::tool("roam-export") + " " + log + " --estimator ekf_x --robot D");
  EXPECT_EQ(stranger.status, 2);
  EXPECT_EQ(stranger.out, "roam-export: error: " + log + ": no robot 'D' in the team (robots: A, B, C)\n");
}

TEST(TeamExport, OutputFileBecomesOneFilePerRobot) {
  roam_test::ScratchDir dir;
  const std::string log = writeTeamLog(dir);
  const roam_test::ToolResult r = roam_test::runTool(roam_test::tool("roam-export") + " " + log +
                                                     " --estimator ekf_x --format tum -o " + dir.file("ekf.tum"));
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_EQ(r.out, "roam-export: " + log + ": estimator 'ekf_x' published no path for robot C: no file for it\n");
  EXPECT_FALSE(std::filesystem::exists(dir.file("ekf.tum")));
  EXPECT_FALSE(std::filesystem::exists(dir.file("ekf_C.tum")));
  const auto a = tumRows(readFile(dir.file("ekf_A.tum")));
  const auto b = tumRows(readFile(dir.file("ekf_B.tum")));
  ASSERT_EQ(a.size(), 10u);
  ASSERT_EQ(b.size(), 10u);
  EXPECT_NEAR(a[9][1], 9.3, kTolerance);
  EXPECT_NEAR(b[9][2], 9.0, kTolerance);

  const roam_test::ToolResult truth = roam_test::runTool(roam_test::tool("roam-export") + " " + log +
                                                         " --ground-truth -o " + dir.file("truth.csv"));
  ASSERT_EQ(truth.status, 0) << truth.out;
  EXPECT_EQ(readFile(dir.file("truth_C.csv")).substr(0, 45), "time_s,x_m,y_m,heading_rad\n0.000000,0,5,0\n1.0");

  const roam_test::ToolResult stdout_only =
      roam_test::runTool(roam_test::tool("roam-export") + " " + log + " --estimator rot");
  EXPECT_EQ(stdout_only.status, 2);
  EXPECT_EQ(stdout_only.out, "roam-export: error: " + log +
                                 " is a team log (robots A, B, C): give --robot R, or -o FILE for one file per "
                                 "robot (FILE_<R>)\n");
}

TEST(TeamExport, RobotOnASingleRobotLogIsAnError) {
  roam_test::ScratchDir dir;
  const std::string single = dir.file("single.lcmlog");
  {
    FixtureLog log(single);
    log.write("GROUND_TRUTH", 0, fixturePose(0, 1, 2));
  }
  const roam_test::ToolResult r =
      roam_test::runTool(roam_test::tool("roam-export") + " " + single + " --ground-truth --robot A");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.out, "roam-export: error: --robot A: " + single + " is not a team log (no GROUND_TRUTH_<R>)\n");
  const roam_test::ToolResult plain = roam_test::runTool(roam_test::tool("roam-export") + " " + single + " --ground-truth");
  EXPECT_EQ(plain.status, 0);
  EXPECT_EQ(plain.out, "time_s,x_m,y_m,heading_rad\n0.000000,1,2,0\n");
}

}  // namespace
