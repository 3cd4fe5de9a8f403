// roam-sim's range gaps (--range-gap START_S:DURATION_S): no range from any beacon inside a gap,
// and everything else identical, bit for bit, to the same seed without gaps.
#include <gtest/gtest.h>

#include <cstring>
#include <stdexcept>

#include "sim.hpp"
#include "tool_test_util.hpp"

namespace {

roam::sim::SimConfig outlierWorld() {
  roam::sim::SimConfig c = roam::sim::nlos30LawnMowerWorld(7, 1500);  // 300 s
  c.outlier_fraction = 0.02;
  c.range_dropout = 0.1;  // dropouts draw from the generator too
  return c;
}

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

TEST(SimRangeGap, NoRangeInsideAGapAndTheRestUnchanged) {
  roam::sim::SimConfig config = outlierWorld();
  const roam::sim::SimRun plain = roam::sim::simulate(config);
  config.range_gaps = {{60.0, 30.0}, {200.0, 30.0}};
  const roam::sim::SimRun gapped = roam::sim::simulate(config);

  const int64_t start = plain.start.utime;
  auto in_gap = [&](int64_t utime) {
    const double t_s = (utime - start) * 1e-6;
    return (t_s >= 60.0 && t_s < 90.0) || (t_s >= 200.0 && t_s < 230.0);
  };
  // 2 Hz round robin with 10 % dropout: ~0.9 * 2 * 300 = 540 ranges, ~108 of them in the 60 s.
  size_t expected = 0;
  for (const roam::Range& r : plain.ranges) expected += in_gap(r.utime) ? 0 : 1;
  ASSERT_GT(plain.ranges.size() - expected, 90u);
  ASSERT_EQ(gapped.ranges.size(), expected);
  size_t j = 0;
  for (const roam::Range& r : plain.ranges) {
    if (in_gap(r.utime)) continue;
    const roam::Range& g = gapped.ranges[j++];
    EXPECT_EQ(g.utime, r.utime);
    EXPECT_EQ(g.beacon_id, r.beacon_id);
    EXPECT_TRUE(sameBits(g.range_m, r.range_m)) << "range " << j;
  }
  for (const roam::Range& g : gapped.ranges) EXPECT_FALSE(in_gap(g.utime)) << g.utime;

  ASSERT_EQ(gapped.odometry.size(), plain.odometry.size());
  for (size_t k = 0; k < plain.odometry.size(); ++k) {
    EXPECT_TRUE(sameBits(gapped.odometry[k].forward_m, plain.odometry[k].forward_m));
    EXPECT_TRUE(sameBits(gapped.odometry[k].delta_heading_rad, plain.odometry[k].delta_heading_rad));
  }
  ASSERT_EQ(gapped.ground_truth.size(), plain.ground_truth.size());
  for (size_t k = 0; k < plain.ground_truth.size(); ++k) {
    EXPECT_TRUE(sameBits(gapped.ground_truth[k].x_m, plain.ground_truth[k].x_m));
    EXPECT_TRUE(sameBits(gapped.ground_truth[k].y_m, plain.ground_truth[k].y_m));
  }
  ASSERT_EQ(gapped.beacons.size(), plain.beacons.size());
  for (size_t n = 0; n < plain.beacons.size(); ++n) {
    EXPECT_TRUE(sameBits(gapped.beacons[n].x_m, plain.beacons[n].x_m));
    EXPECT_TRUE(sameBits(gapped.beacons[n].y_m, plain.beacons[n].y_m));
  }
}

TEST(SimRangeGap, ParsesAndRejects) {
  const roam::sim::RangeGap gap = roam::sim::parseRangeGap("120.5:30");
  EXPECT_EQ(gap.start_s, 120.5);
  EXPECT_EQ(gap.duration_s, 30.0);
  for (const char* bad : {"", "120", ":30", "120:", "a:30", "120:3x", "-1:30", "120:0", "120:-5", "nan:30", "1:inf"})
    EXPECT_THROW(roam::sim::parseRangeGap(bad), std::invalid_argument) << bad;
  roam::sim::SimConfig config = outlierWorld();
  config.range_gaps = {{10.0, 0.0}};
  EXPECT_THROW(roam::sim::simulate(config), std::invalid_argument);
}

TEST(SimRangeGap, CommandLine) {
  roam_test::ScratchDir dir;
  const std::string sim = roam_test::tool("roam-sim");
  const roam_test::ToolResult help = roam_test::runTool(sim + " --help");
  EXPECT_EQ(help.status, 0);
  EXPECT_NE(help.out.find("--range-gap"), std::string::npos);
  const roam_test::ToolResult bad = roam_test::runTool(sim + " -o " + dir.file("x.lcmlog") + " --range-gap 10:-3");
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.out.find("--range-gap: range gap '10:-3'"), std::string::npos) << bad.out;
  EXPECT_NE(bad.out.find("duration must be"), std::string::npos) << bad.out;
  const roam_test::ToolResult ok = roam_test::runTool(sim + " -o " + dir.file("x.lcmlog") +
                                                      " --steps 500 --schedule round_robin --range-gap 10:30 --range-gap 60:5");
  EXPECT_EQ(ok.status, 0) << ok.out;
  // 100 s at 2 Hz = 200 ranges, 35 s of them silent: 130.
  EXPECT_NE(ok.out.find(" 130 ranges"), std::string::npos) << ok.out;
}

}  // namespace
