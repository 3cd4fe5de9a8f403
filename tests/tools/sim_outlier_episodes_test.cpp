// roam-sim's NLOS in stretches (--outlier-episode-s): each beacon's ranges are long by one excess
// per stretch, the stretches cover --outlier-fraction of the time, and everything else is the
// same seed's clean run, bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "sim.hpp"
#include "tool_test_util.hpp"

namespace {

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

TEST(SimOutlierEpisodes, RangesAreTheCleanRunsPlusOneExcessPerStretch) {
  roam::sim::SimConfig config = roam::sim::nlos30LawnMowerWorld(11, 30000);  // 6000 s
  config.outlier_episode_s = 20.0;
  const roam::sim::SimRun episodic = roam::sim::simulate(config);
  roam::sim::SimConfig clean_config = config;
  clean_config.outlier_fraction = 0.0;
  const roam::sim::SimRun clean = roam::sim::simulate(clean_config);

  const double duration_s = (episodic.ground_truth.back().utime - episodic.start.utime) * 1e-6;
  const auto episodes = roam::sim::outlierEpisodes(config, episodic.beacons, duration_s);
  ASSERT_EQ(episodes.size(), episodic.beacons.size());
  // Each beacon NLOS 30 % of the time in stretches of 20 s on average.
  double nlos_s = 0.0;
  size_t stretches = 0;
  for (const auto& [id, mine] : episodes) {
    for (const roam::sim::OutlierEpisode& e : mine) {
      EXPECT_GE(e.excess_m, 2.0);
      EXPECT_LE(e.excess_m, 40.0);
      nlos_s += std::min(e.end_s, duration_s) - e.start_s;
    }
    stretches += mine.size();
  }
  const double fraction = nlos_s / (duration_s * static_cast<double>(episodes.size()));
  const double mean_stretch_s = nlos_s / static_cast<double>(stretches);
  EXPECT_NEAR(fraction, 0.3, 0.05);
  EXPECT_NEAR(mean_stretch_s, 20.0, 4.0);

  ASSERT_EQ(episodic.ranges.size(), clean.ranges.size());
  size_t long_ranges = 0;
  for (size_t k = 0; k < clean.ranges.size(); ++k) {
    const roam::Range& r = episodic.ranges[k];
    const roam::Range& c = clean.ranges[k];
    ASSERT_EQ(r.utime, c.utime);
    ASSERT_EQ(r.beacon_id, c.beacon_id);
    const double t_s = (r.utime - episodic.start.utime) * 1e-6;
    double excess_m = 0.0;
    for (const roam::sim::OutlierEpisode& e : episodes.at(r.beacon_id))
      if (t_s >= e.start_s && t_s < e.end_s) excess_m = e.excess_m;
    if (excess_m == 0.0) {
      EXPECT_TRUE(sameBits(r.range_m, c.range_m)) << "range " << k;
    } else {
      EXPECT_NEAR(r.range_m - c.range_m, excess_m, 1e-9) << "range " << k;
      ++long_ranges;
    }
  }
  EXPECT_NEAR(static_cast<double>(long_ranges) / static_cast<double>(clean.ranges.size()), 0.3, 0.05);
  ASSERT_EQ(episodic.odometry.size(), clean.odometry.size());
  for (size_t k = 0; k < clean.odometry.size(); ++k) {
    EXPECT_TRUE(sameBits(episodic.odometry[k].forward_m, clean.odometry[k].forward_m));
    EXPECT_TRUE(sameBits(episodic.odometry[k].delta_heading_rad, clean.odometry[k].delta_heading_rad));
  }
  // Range by range (the default) draws each range's fate from the run's own stream instead.
  config.outlier_episode_s = 0.0;
  EXPECT_TRUE(roam::sim::outlierEpisodes(config, episodic.beacons, duration_s).empty());
}

TEST(SimOutlierEpisodes, CommandLine) {
  roam_test::ScratchDir dir;
  const std::string sim = roam_test::tool("roam-sim");
  const roam_test::ToolResult help = roam_test::runTool(sim + " --help");
  EXPECT_EQ(help.status, 0);
  EXPECT_NE(help.out.find("--outlier-episode-s"), std::string::npos);
  const roam_test::ToolResult bad = roam_test::runTool(sim + " -o " + dir.file("x.lcmlog") + " --outlier-episode-s -5");
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.out.find("--outlier-episode-s: expected a finite number >= 0"), std::string::npos) << bad.out;
  const roam_test::ToolResult ok = roam_test::runTool(sim + " -o " + dir.file("x.lcmlog") +
                                                      " --steps 500 --schedule round_robin --outlier-fraction 0.3 --outlier-episode-s 20");
  EXPECT_EQ(ok.status, 0) << ok.out;
}

}  // namespace
