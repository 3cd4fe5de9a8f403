// roam-sim's stated odometry noise (--odo-sigma-reported, --odo-heading-sigma-reported): every
// odometry message carries the diagonal covariance it names, as a log's generator writes one
// (GOATS 16: 0.02 m and 0.002 rad per edge), and nothing else in the run changes; one without the
// other is refused by name.
#include <gtest/gtest.h>

#include <string>

#include "sim.hpp"
#include "tool_test_util.hpp"

namespace {

TEST(SimOdometryCovariance, EveryStepStatesTheDiagonalAndNothingElseChanges) {
  roam::sim::SimConfig config = roam::sim::goatsLikeWorld(7, 40);
  config.odo_sigma_reported_m = 0.0;
  config.odo_heading_sigma_reported_rad = 0.0;
  const roam::sim::SimRun plain = roam::sim::simulate(config);
  config.odo_sigma_reported_m = 0.02;
  config.odo_heading_sigma_reported_rad = 0.002;
  const roam::sim::SimRun stated = roam::sim::simulate(config);
  ASSERT_EQ(stated.odometry.size(), plain.odometry.size());
  for (size_t k = 0; k < plain.odometry.size(); ++k) {
    EXPECT_FALSE(plain.odometry[k].hasCovariance()) << k;
    ASSERT_TRUE(stated.odometry[k].hasCovariance()) << k;
    const auto& c = stated.odometry[k].covariance;
    EXPECT_EQ(c[0], 0.02 * 0.02);
    EXPECT_EQ(c[4], 0.02 * 0.02);
    EXPECT_EQ(c[8], 0.002 * 0.002);
    for (int i : {1, 2, 3, 5, 6, 7}) EXPECT_EQ(c[i], 0.0) << i;
    EXPECT_EQ(stated.odometry[k].forward_m, plain.odometry[k].forward_m);
    EXPECT_EQ(stated.odometry[k].lateral_m, plain.odometry[k].lateral_m);
    EXPECT_EQ(stated.odometry[k].delta_heading_rad, plain.odometry[k].delta_heading_rad);
  }
  ASSERT_EQ(stated.ranges.size(), plain.ranges.size());
  for (size_t k = 0; k < plain.ranges.size(); ++k) EXPECT_EQ(stated.ranges[k].range_m, plain.ranges[k].range_m) << k;
  EXPECT_EQ(stated.ground_truth.back().x_m, plain.ground_truth.back().x_m);
}

TEST(SimOdometryCovariance, OneWithoutTheOtherIsRefusedByName) {
  roam::sim::SimConfig config = roam::sim::goatsLikeWorld(7, 10);
  config.odo_heading_sigma_reported_rad = 0.0;
  EXPECT_THROW(roam::sim::simulate(config), std::invalid_argument);
  roam_test::ScratchDir dir;
  const roam_test::ToolResult made =
      roam_test::runTool(roam_test::tool("roam-sim") + " -o " + dir.file("x.lcmlog") + " --odo-heading-sigma-reported 0.002");
  EXPECT_EQ(made.status, 2) << made.out;
  EXPECT_NE(made.out.find("--odo-sigma-reported"), std::string::npos) << made.out;
}

}  // namespace
