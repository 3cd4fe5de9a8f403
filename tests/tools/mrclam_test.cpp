// MR.CLAM 6 (data/mrclam6), a real team of five robots, read one robot at a time: the robot's
// landmark sightings are ranges with bearings to the surveyed landmarks, and the estimators use
// them end to end (roam-import, roam-run, roam-eval).
#include <gtest/gtest.h>

#include <cstdio>
#include <map>
#include <sstream>
#include <string>

#include "tool_test_util.hpp"

namespace {

const std::string kMrclam = std::string(ROAM_SOURCE_DIR) + "/data/mrclam6/mrclam6.pyfg";

// "name  full path  mean  rmse" rows of roam-eval's table: name -> mean (m).
std::map<std::string, double> fullPathMeans(const std::string& table) {
  std::map<std::string, double> means;
  std::istringstream lines(table);
  for (std::string line; std::getline(lines, line);) {
    std::istringstream words(line);
    std::string name, full, path;
    double mean = 0.0;
    if (words >> name >> full >> path >> mean && full == "full" && path == "path") means[name] = mean;
  }
  return means;
}

// Robot D alone (1,643 odometry steps, 1,418 sightings): the EKF with the surveyed landmarks is
// within a quarter of the robot's dead reckoning (0.27 m against 1.22 measured); every range it
// was given is a sighting with a bearing.
TEST(Mrclam6, ARobotAloneUsesItsLandmarkSightings) {
  ROAM_REQUIRE_DATA(kMrclam);
  roam_test::ScratchDir dir;
  const auto imported = roam_test::runTool(roam_test::tool("roam-import") + " " + kMrclam + " --robot D -o " +
                                           dir.file("d.lcmlog"));
  ASSERT_EQ(imported.status, 0) << imported.out;
  EXPECT_NE(imported.out.find("(1643 odometry, 1418 ranges, 1644 ground truth, 15 beacons)"), std::string::npos)
      << imported.out;
  dir.write("d.ini", "[runtime]\ninput = d.lcmlog\noutput = out.lcmlog\n"
                     "[estimator.deadreckoning]\nplugin = deadreckoning\n"
                     "[estimator.ekf_beacons]\nplugin = ekf\nanchor = beacons\n");
  const auto run = roam_test::runTool(roam_test::tool("roam-run") + " " + dir.file("d.ini") + " --no-progress");
  ASSERT_EQ(run.status, 0) << run.out;
  const auto eval = roam_test::runTool(roam_test::tool("roam-eval") + " " + dir.file("out.lcmlog"));
  ASSERT_EQ(eval.status, 0) << eval.out;
  const auto means = fullPathMeans(eval.out);
  ASSERT_TRUE(means.count("deadreckoning") && means.count("ekf_beacons")) << eval.out;
  std::printf("MR.CLAM 6 robot D: dead reckoning %.2f m, EKF with beacons %.2f m\n", means.at("deadreckoning"),
              means.at("ekf_beacons"));
  EXPECT_GT(means.at("deadreckoning"), 1.0);
  EXPECT_LT(means.at("ekf_beacons"), 0.25 * means.at("deadreckoning"));
}

}  // namespace
