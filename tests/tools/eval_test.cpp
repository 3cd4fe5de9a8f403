// roam-eval and roam-export on a small fixture log written here, with known truth and estimates;
// every expected figure is worked out in this file, independently of the tools' code.
#include <cmath>
#include <lcm/lcm-cpp.hpp>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "../common/fixture_log.hpp"
#include "roam/estimator_status_t.hpp"
#include "roam/map_t.hpp"
#include "roam/odometry_t.hpp"
#include "roam/pose_t.hpp"
#include "roam/trajectory_t.hpp"
#include "tool_test_util.hpp"

namespace {

constexpr double kTolerance = 1e-9;

using roam::test::FixtureLog;
using roam::test::fixturePose;

// Ground truth: 20 poses, t = 0..19 s, at (t, 0).
// Estimator "fix" publishes POSE_FIX at even t = 0..18 only, at (t, 0.01 (t - 9)^2): at an even
// t the error is 0.01 (t-9)^2; at an odd t (interpolated halfway between t-1 and t+1) it is
// 0.01 ((t-10)^2 + (t-8)^2) / 2 = 0.01 ((t-9)^2 + 1); t = 19 is outside its span (19 matched).
// It also publishes MAP_FIX (beacon 1 off by (3, 4) -> 5 m; beacon 2 exact; beacon 9 unknown)
// and STATUS_FIX with cpu_total_s 0.25 then 0.75 (the last counts).
// Estimator "smooth" publishes poses far off and a TRAJECTORY_SMOOTH (the one that is scored):
// the truth rotated by 90 degrees about the origin and moved by (1, 2): (t, 0) -> (1, 2 + t).
std::string writeFixture(const roam_test::ScratchDir& dir) {
  const std::string path = dir.file("fixture.lcmlog");
  FixtureLog log(path);
  const roam::map_t beacons = roam::test::fixtureMap({{1, 10, 10}, {2, -10, 5}});
  log.write("INITIAL_POSE", 0, fixturePose(0, 0, 0));
  log.write("BEACONS", 0, beacons);
  roam::trajectory_t smooth{};
  smooth.estimator = "smooth";
  for (int t = 0; t < 20; ++t) {
    const int64_t utime = t * 1000000LL;
    log.write("GROUND_TRUTH", utime, fixturePose(utime, t, 0));
    if (t > 0) {
      roam::odometry_t odometry{};
      odometry.utime = utime;
      odometry.delta_distance = 1.0;
      log.write("ODOMETRY", utime, odometry);
    }
    if (t % 2 == 0 && t <= 18) log.write("POSE_FIX", utime, fixturePose(utime, t, 0.01 * (t - 9) * (t - 9), "fix"));
    log.write("POSE_SMOOTH", utime, fixturePose(utime, 100, 100, "smooth"));
    smooth.utimes.push_back(utime);
    smooth.x.push_back(1.0);
    smooth.y.push_back(2.0 + t);
    smooth.heading.push_back(M_PI / 2);
  }
  smooth.num_poses = 20;
  smooth.utime = 19000000;
  log.write("TRAJECTORY_SMOOTH", smooth.utime, smooth);
  roam::map_t map = beacons;
  map.estimator = "fix";
  map.num_beacons = 3;
  map.beacons[0].x = 13;
  map.beacons[0].y = 14;
  map.beacons.push_back(map.beacons[1]);
  map.beacons[2].id = 9;
  log.write("MAP_FIX", 19000000, map);
  roam::estimator_status_t status{};
  status.estimator = "fix";
  status.state = roam::estimator_status_t::FINISHED;
  status.cpu_total_s = 0.25;
  log.write("STATUS_FIX", 10000000, status);
  status.cpu_total_s = 0.75;
  log.write("STATUS_FIX", 19000000, status);
  return path;
}

struct Stats {
  double mean, rmse;
};
Stats stats(const std::vector<double>& e, size_t begin, size_t end) {
  double sum = 0, sq = 0;
  for (size_t i = begin; i < end; ++i) {
    sum += e[i];
    sq += e[i] * e[i];
  }
  return {sum / (end - begin), std::sqrt(sq / (end - begin))};
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream in(line);
  std::string field;
  while (std::getline(in, field, ',')) fields.push_back(field);
  if (!line.empty() && line.back() == ',') fields.push_back("");
  return fields;
}

// The CSV row of `estimator` as header -> value.
std::map<std::string, std::string> csvRow(const std::string& csv, const std::string& estimator) {
  std::stringstream in(csv);
  std::string line;
  std::getline(in, line);
  const std::vector<std::string> header = split(line);
  while (std::getline(in, line)) {
    const std::vector<std::string> fields = split(line);
    if (fields.size() > 1 && fields[1] == estimator) {
      std::map<std::string, std::string> row;
      for (size_t i = 0; i < header.size() && i < fields.size(); ++i) row[header[i]] = fields[i];
      return row;
    }
  }
  return {};
}

TEST(Eval, FixtureFiguresMatchAnIndependentComputation) {
  roam_test::ScratchDir dir;
  const std::string log = writeFixture(dir);
  const roam_test::ToolResult r = roam_test::runTool(roam_test::tool("roam-eval") + " " + log + " --format csv");
  ASSERT_EQ(r.status, 0) << r.out;

  // "fix": errors at t = 0..18 as worked out above.
  std::vector<double> e;
  for (int t = 0; t <= 18; ++t) e.push_back(t % 2 == 0 ? 0.01 * (t - 9) * (t - 9) : 0.01 * ((t - 9) * (t - 9) + 1));
  // 19 rows in 10 chunks: boundaries floor(c * 19 / 10) = 0 1 3 5 7 9 11 13 15 17 19.
  const size_t bounds[] = {0, 1, 3, 5, 7, 9, 11, 13, 15, 17, 19};
  std::vector<Stats> chunks;
  for (int c = 0; c < 10; ++c) chunks.push_back(stats(e, bounds[c], bounds[c + 1]));
  // Chunk means: chunk 0 = {t = 0}: 0.81 (the highest: chunk 9, t = 17, 18, has (0.65 + 0.81) / 2
  // = 0.73); the lowest is chunk 5 (t = 9, 10: 0.01 and 0.01).
  EXPECT_NEAR(chunks[0].mean, 0.81, kTolerance);
  EXPECT_NEAR(chunks[5].mean, 0.01, kTolerance);
  EXPECT_NEAR(chunks[9].mean, 0.73, kTolerance);
  for (int c = 0; c < 10; ++c) {
    EXPECT_GE(chunks[c].mean, chunks[5].mean - kTolerance);
    EXPECT_LE(chunks[c].mean, chunks[0].mean + kTolerance);
  }
  const Stats full = stats(e, 0, e.size());

  const auto fix = csvRow(r.out, "fix");
  ASSERT_FALSE(fix.empty()) << r.out;
  EXPECT_EQ(fix.at("scored"), "poses");
  EXPECT_EQ(fix.at("matched"), "19");
  EXPECT_NEAR(std::stod(fix.at("full_mean_m")), full.mean, kTolerance);
  EXPECT_NEAR(std::stod(fix.at("full_rmse_m")), full.rmse, kTolerance);
  EXPECT_NEAR(std::stod(fix.at("last10_mean_m")), chunks[9].mean, kTolerance);
  EXPECT_NEAR(std::stod(fix.at("last10_rmse_m")), chunks[9].rmse, kTolerance);
  EXPECT_NEAR(std::stod(fix.at("best10_mean_m")), chunks[5].mean, kTolerance);
  EXPECT_NEAR(std::stod(fix.at("best10_rmse_m")), chunks[5].rmse, kTolerance);
  EXPECT_NEAR(std::stod(fix.at("worst10_mean_m")), chunks[0].mean, kTolerance);
  EXPECT_NEAR(std::stod(fix.at("worst10_rmse_m")), chunks[0].rmse, kTolerance);
  EXPECT_NEAR(std::stod(fix.at("max_m")), 0.81, kTolerance);          // t = 0 and t = 18
  EXPECT_NEAR(std::stod(fix.at("beacon_error_m")), (5.0 + 0.0) / 2, kTolerance);
  EXPECT_NEAR(std::stod(fix.at("cpu_s")), 0.75, kTolerance);
  EXPECT_EQ(fix.at("state"), "finished");

  // "smooth": the trajectory is scored, not the poses; error at t: |(1, 2 + t) - (t, 0)|.
  std::vector<double> s;
  for (int t = 0; t < 20; ++t) s.push_back(std::hypot(1.0 - t, 2.0 + t));
  const auto smooth = csvRow(r.out, "smooth");
  ASSERT_FALSE(smooth.empty()) << r.out;
  EXPECT_EQ(smooth.at("scored"), "trajectory");
  EXPECT_EQ(smooth.at("matched"), "20");
  EXPECT_NEAR(std::stod(smooth.at("full_mean_m")), stats(s, 0, 20).mean, kTolerance);
  EXPECT_NEAR(std::stod(smooth.at("last10_mean_m")), stats(s, 18, 20).mean, kTolerance);
  EXPECT_EQ(smooth.at("beacon_error_m"), "");
  EXPECT_EQ(smooth.at("cpu_s"), "");

  // "odometry": roam-eval's own dead reckoning from INITIAL_POSE (heading 0), 1 m per step:
  // exactly the truth.
  const auto odometry = csvRow(r.out, "odometry");
  ASSERT_FALSE(odometry.empty()) << r.out;
  EXPECT_EQ(odometry.at("matched"), "20");
  EXPECT_NEAR(std::stod(odometry.at("full_mean_m")), 0.0, kTolerance);
}

TEST(Eval, AlignedRemovesARigidMotion) {
  roam_test::ScratchDir dir;
  const std::string log = writeFixture(dir);
  const roam_test::ToolResult r =
      roam_test::runTool(roam_test::tool("roam-eval") + " " + log + " --format csv --aligned");
  ASSERT_EQ(r.status, 0) << r.out;
  // "smooth" is the truth moved rigidly: after the best rigid fit every error is 0.
  const auto smooth = csvRow(r.out, "smooth");
  EXPECT_NEAR(std::stod(smooth.at("full_mean_m")), 0.0, 1e-6);
  EXPECT_NEAR(std::stod(smooth.at("max_m")), 0.0, 1e-6);
}

TEST(Eval, TextTableHasTheFigure3Rows) {
  roam_test::ScratchDir dir;
  const std::string log = writeFixture(dir);
  const roam_test::ToolResult r = roam_test::runTool(roam_test::tool("roam-eval") + " " + log + " --metric mean");
  ASSERT_EQ(r.status, 0) << r.out;
  for (const char* text : {"fixture mean (m)", "full path", "last 10 %", "best 10 %", "worst 10 %", "max",
                           "beacons", "CPU (s)", "fix", "smooth", "odometry"}) {
    EXPECT_NE(r.out.find(text), std::string::npos) << text << "\n" << r.out;
  }
  EXPECT_EQ(r.out.find("RMSE"), std::string::npos) << r.out;
  // fix's max error 0.81 m and CPU 0.750 s appear as printed figures.
  EXPECT_NE(r.out.find("0.81"), std::string::npos);
  EXPECT_NE(r.out.find("0.750"), std::string::npos);
}

TEST(Eval, SeveralLogsBecomeColumns) {
  roam_test::ScratchDir dir;
  const std::string log = writeFixture(dir);
  const std::string copy = dir.file("again.lcmlog");
  ASSERT_EQ(std::system(("cp " + log + " " + copy).c_str()), 0);
  const roam_test::ToolResult r =
      roam_test::runTool(roam_test::tool("roam-eval") + " " + log + " " + copy + " --format markdown");
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_EQ(r.out.rfind("| estimator | segment | fixture mean (m) | fixture RMSE (m) | again mean (m) | again RMSE (m) |", 0),
            0u)
      << r.out;
}

TEST(Eval, UnreadableLogExitsTwoWithOneLine) {
  const roam_test::ToolResult r = roam_test::runTool(roam_test::tool("roam-eval") + " /nonexistent/x.lcmlog");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.out, "roam-eval: error: /nonexistent/x.lcmlog: cannot open (No such file or directory)\n");
}

TEST(Eval, CutLogIsScoredAsFarAsItGoesAndTheDamageReported) {
  roam_test::ScratchDir dir;
  const std::string log = writeFixture(dir);
  ASSERT_EQ(::truncate(log.c_str(), 1500), 0);  // cuts an event in the middle
  const roam_test::ToolResult r = roam_test::runTool(roam_test::tool("roam-eval") + " " + log + " --format csv");
  EXPECT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("skipped 1 corrupt or undecodable event"), std::string::npos) << r.out;
}

TEST(Export, WritesThePathRoamEvalScores) {
  roam_test::ScratchDir dir;
  const std::string log = writeFixture(dir);
  const std::string out = dir.file("smooth.csv");
  const roam_test::ToolResult r =
      roam_test::runTool(roam_test::tool("roam-export") + " " + log + " --estimator smooth -o " + out);
  ASSERT_EQ(r.status, 0) << r.out;
  std::ifstream in(out);
  std::string header, first, second;
  std::getline(in, header);
  std::getline(in, first);
  std::getline(in, second);
  EXPECT_EQ(header, "time_s,x_m,y_m,heading_rad");
  EXPECT_EQ(first, "0.000000,1,2,1.5707963267948966");  // the trajectory, not POSE_SMOOTH (100, 100)
  EXPECT_EQ(second, "1.000000,1,3,1.5707963267948966");

  const roam_test::ToolResult map = roam_test::runTool(roam_test::tool("roam-export") + " " + log + " --map --estimator fix");
  EXPECT_EQ(map.status, 0);
  EXPECT_EQ(map.out, "beacon_id,x_m,y_m\n1,13,14\n2,-10,5\n9,-10,5\n");

  const roam_test::ToolResult truth = roam_test::runTool(roam_test::tool("roam-export") + " " + log + " --ground-truth");
  EXPECT_EQ(truth.status, 0);
  EXPECT_EQ(truth.out.substr(0, 60), "time_s,x_m,y_m,heading_rad\n0.000000,0,0,0\n1.000000,1,0,0\n2.0");

  const roam_test::ToolResult missing = roam_test::runTool(roam_test::tool("roam-export") + " " + log + " --estimator nope");
  EXPECT_EQ(missing.status, 2);
  EXPECT_EQ(missing.out, "roam-export: error: " + log + ": no estimator 'nope' (found: fix, smooth)\n");
}

TEST(Eval, APathCoveringLittleOfTheRunShowsItsCoverageAndIsNotRanked) {
  // Ground truth 20 poses; "quit" published one pose (t = 0, exact) and gave up: 1 of 20 matched,
  // 5 % coverage, error 0.00 over what it covers, shown in parentheses and not ranked.
  roam_test::ScratchDir dir;
  const std::string path = dir.file("quit.lcmlog");
  {
    FixtureLog log(path);
    log.write("INITIAL_POSE", 0, fixturePose(0, 0, 0));
    for (int t = 0; t < 20; ++t) log.write("GROUND_TRUTH", t * 1000000LL, fixturePose(t * 1000000LL, t, 0));
    log.write("POSE_QUIT", 0, fixturePose(0, 0, 0, "quit"));
  }
  const roam_test::ToolResult text = roam_test::runTool(roam_test::tool("roam-eval") + " " + path + " --metric mean");
  ASSERT_EQ(text.status, 0) << text.out;
  EXPECT_NE(text.out.find("(0.00)"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("5 % (partial)"), std::string::npos) << text.out;
  const roam_test::ToolResult csv = roam_test::runTool(roam_test::tool("roam-eval") + " " + path + " --format csv");
  ASSERT_EQ(csv.status, 0) << csv.out;
  EXPECT_NE(csv.out.find(",coverage,ranked\n"), std::string::npos) << csv.out;
  EXPECT_NE(csv.out.find(",0.050000000000000003,false\n"), std::string::npos) << csv.out;
}

TEST(Export, TumForEvo) {
  // smooth's trajectory at t = 0 is (1, 2) heading pi/2: quaternion (0, 0, sin(pi/4), cos(pi/4)).
  roam_test::ScratchDir dir;
  const std::string log = writeFixture(dir);
  const roam_test::ToolResult r =
      roam_test::runTool(roam_test::tool("roam-export") + " " + log + " --estimator smooth --format tum");
  ASSERT_EQ(r.status, 0) << r.out;
  std::istringstream lines(r.out);
  std::string first;
  std::getline(lines, first);
  std::istringstream fields(first);
  double t, x, y, z, qx, qy, qz, qw;
  ASSERT_TRUE(fields >> t >> x >> y >> z >> qx >> qy >> qz >> qw) << first;
  EXPECT_EQ(t, 0.0);
  EXPECT_EQ(x, 1.0);
  EXPECT_EQ(y, 2.0);
  EXPECT_EQ(z, 0.0);
  EXPECT_EQ(qx, 0.0);
  EXPECT_EQ(qy, 0.0);
  EXPECT_NEAR(qz, std::sqrt(0.5), kTolerance);
  EXPECT_NEAR(qw, std::sqrt(0.5), kTolerance);
  const roam_test::ToolResult truth =
      roam_test::runTool(roam_test::tool("roam-export") + " " + log + " --ground-truth --format tum");
  EXPECT_EQ(truth.out.substr(0, 38), "0.000000 0 0 0 0 0 0 1\n1.000000 1 0 0 ");
}

TEST(Export, PyfgHoldsThePathAtTheOdometryTimesTheMapAndTheEdges) {
  // fix: poses at even t only; at odd t interpolated. 19 odometry steps -> 20 poses, 19 edges;
  // its map (beacons 1, 2, 9) as VERTEX_XY.
  roam_test::ScratchDir dir;
  const std::string log = writeFixture(dir);
  const roam_test::ToolResult r = roam_test::runTool(roam_test::tool("roam-export") + " " + log +
                                                     " --estimator fix --format pyfg -o " + dir.file("fix.pyfg"));
  ASSERT_EQ(r.status, 0) << r.out;
  std::ifstream in(dir.file("fix.pyfg"));
  std::string line;
  int poses = 0, beacons = 0, edges = 0;
  std::string pose1;
  while (std::getline(in, line)) {
    if (line.rfind("VERTEX_SE2 ", 0) == 0 && ++poses == 2) pose1 = line;
    if (line.rfind("VERTEX_XY ", 0) == 0) ++beacons;
    if (line.rfind("EDGE_SE2 ", 0) == 0) ++edges;
  }
  EXPECT_EQ(poses, 20);
  EXPECT_EQ(edges, 19);
  EXPECT_EQ(beacons, 3);
  // t = 1: halfway between (0, 0.81) and (2, 0.49): (1, 0.65).
  std::istringstream fields(pose1);
  std::string type, time, name;
  double x, y;
  fields >> type >> time >> name >> x >> y;
  EXPECT_EQ(time, "1.000000");
  EXPECT_EQ(name, "A1");
  EXPECT_NEAR(x, 1.0, kTolerance);
  EXPECT_NEAR(y, 0.65, kTolerance);
  const roam_test::ToolResult no_file =
      roam_test::runTool(roam_test::tool("roam-export") + " " + log + " --estimator fix --format pyfg");
  EXPECT_EQ(no_file.status, 2);
  EXPECT_EQ(no_file.out, "roam-export: error: --format pyfg needs -o FILE\n");
}

TEST(Eval, StatusPrintsEachEstimatorsLastStatusLine) {
  roam_test::ScratchDir dir;
  const std::string path = dir.file("status.lcmlog");
  {
    FixtureLog log(path);
    roam::estimator_status_t status{};
    status.estimator = "ekf";
    status.state = roam::estimator_status_t::TRACKING;
    log.write("STATUS_EKF", 1, status);  // superseded by the next one
    status.state = roam::estimator_status_t::FINISHED;
    status.odometry_accepted = 99;
    status.odometry_rejected = 1;
    status.ranges_accepted = 30;
    status.ranges_rejected = 10;
    status.num_values = 2;
    status.keys = {"heading_rate_bias_rad_s", "distance_scale"};
    status.values = {0.0099, 0.97};
    log.write("STATUS_EKF", 2, status);
  }
  const roam_test::ToolResult r = roam_test::runTool(roam_test::tool("roam-eval") + " " + path + " --status");
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_EQ(r.out, "status ekf: finished, odometry 1/100 rejected, ranges 10/40 rejected; "
                   "heading_rate_bias_rad_s 0.0099; distance_scale 0.97\n");
}

}  // namespace
