// roam-sim's beacon survey error (--beacon-survey-sigma): the published beacons (BEACONS) are the
// true ones displaced by N(0, sigma^2) per axis, the ranges stay those to the true positions, and
// nothing else in the run changes; the command line names a bad value.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>

#include "sim.hpp"
#include "tool_test_util.hpp"

namespace {

TEST(SimBeaconSurvey, PublishedBeaconsMoveByTheirSurveyErrorAndNothingElseChanges) {
  double sum_m2 = 0.0;
  int axes = 0;
  for (uint64_t seed = 1; seed <= 25; ++seed) {
    roam::sim::SimConfig config = roam::sim::goatsLikeWorld(seed, 60);
    const roam::sim::SimRun exact = roam::sim::simulate(config);
    config.beacon_survey_sigma_m = 5.0;
    const roam::sim::SimRun surveyed = roam::sim::simulate(config);
    const auto errors_m = roam::sim::beaconSurveyErrors(config, exact.beacons);
    ASSERT_EQ(surveyed.beacons.size(), exact.beacons.size());
    ASSERT_EQ(errors_m.size(), exact.beacons.size());
    for (size_t n = 0; n < exact.beacons.size(); ++n) {
      const auto& e = errors_m.at(exact.beacons[n].id);
      EXPECT_EQ(surveyed.beacons[n].x_m, exact.beacons[n].x_m + e[0]);
      EXPECT_EQ(surveyed.beacons[n].y_m, exact.beacons[n].y_m + e[1]);
      sum_m2 += e[0] * e[0] + e[1] * e[1];
      axes += 2;
    }
    ASSERT_EQ(surveyed.ranges.size(), exact.ranges.size());
    for (size_t k = 0; k < exact.ranges.size(); ++k) EXPECT_EQ(surveyed.ranges[k].range_m, exact.ranges[k].range_m) << k;
    ASSERT_EQ(surveyed.odometry.size(), exact.odometry.size());
    for (size_t k = 0; k < exact.odometry.size(); ++k) EXPECT_EQ(surveyed.odometry[k].forward_m, exact.odometry[k].forward_m);
    EXPECT_EQ(surveyed.ground_truth.back().x_m, exact.ground_truth.back().x_m);
  }
  // 200 axis draws of sigma 5 m: their RMS is within 15 % of 5 (the chi-square's 3.5-sigma band).
  EXPECT_NEAR(std::sqrt(sum_m2 / axes), 5.0, 0.75);
}

TEST(SimBeaconSurvey, ANegativeSigmaIsRefusedByName) {
  roam_test::ScratchDir dir;
  const roam_test::ToolResult made =
      roam_test::runTool(roam_test::tool("roam-sim") + " -o " + dir.file("x.lcmlog") + " --beacon-survey-sigma -1");
  EXPECT_EQ(made.status, 2) << made.out;
  EXPECT_NE(made.out.find("--beacon-survey-sigma"), std::string::npos) << made.out;
}

}  // namespace
