// The published trajectory RTS-smoothed over the particle cloud (smooth_trajectory): on a seeded
// gyro-drift figure-8 (the issue-15 kind), surveyed beacons and the start pose, the smoothed
// path is closer to the truth than the filtered one; the key off publishes the filtered path
// itself; a repeat is bit-identical.
#include <cstdio>

#include <gtest/gtest.h>

#include "feed.hpp"
#include "online_em_slam.hpp"
#include "roam/options.hpp"
#include "sim.hpp"

namespace roam {
namespace {

using online_em::addOnlineEmOptions;
using online_em::OnlineEmConfig;
using online_em::OnlineEmSlam;
using online_em_test::feed;
using online_em_test::meanError;

Path publishedTrajectory(const Dataset& data, const std::string& anchor, bool smooth) {
  OnlineEmConfig config;
  setOptions(&config, addOnlineEmOptions, {{"anchor", anchor}, {"smooth_trajectory", smooth ? "true" : "false"}});
  OnlineEmSlam slam(config);
  feed(data, slam);
  Path path;
  EXPECT_TRUE(slam.trajectory(false, &path));
  EXPECT_EQ(path.size(), slam.filteredPath().size());
  return path;
}

TEST(OnlineEmSmoothing, SmoothedPathBeatsTheFilteredOne) {
  const Dataset data = sim::simulate(sim::gyroDriftFigure8World(7, 2000));
  for (const std::string anchor : {"beacons", "start_pose"}) {
    const Path filtered = publishedTrajectory(data, anchor, false);
    const Path smoothed = publishedTrajectory(data, anchor, true);
    const double filtered_m = meanError(filtered, data.ground_truth);
    const double smoothed_m = meanError(smoothed, data.ground_truth);
    std::printf("%s: filtered %.3f m, smoothed %.3f m\n", anchor.c_str(), filtered_m, smoothed_m);
    // Measured (simulation seed 7, 2,000 steps): beacons 0.350 -> 0.256 m; start pose 0.820 ->
    // 0.821 m (its error is the frame its map was placed in, a rigid motion of the whole path
    // that no smoothing moves): there the smoothing must not cost.
    if (anchor == "beacons")
      EXPECT_LT(smoothed_m, 0.8 * filtered_m);
    else
      EXPECT_LT(smoothed_m, filtered_m + 0.03);
  }
}

TEST(OnlineEmSmoothing, OffPublishesTheFilteredPathAndRepeatsAreBitIdentical) {
  const Dataset data = sim::simulate(sim::gyroDriftFigure8World(8, 1200));
  OnlineEmConfig config;
  setOptions(&config, addOnlineEmOptions, {{"anchor", "beacons"}, {"smooth_trajectory", "false"}});
  OnlineEmSlam off(config);
  feed(data, off);
  Path path;
  ASSERT_TRUE(off.trajectory(false, &path));
  ASSERT_EQ(path.size(), off.filteredPath().size());
  for (size_t k = 0; k < path.size(); ++k) {
    EXPECT_EQ(path[k].x_m, off.filteredPath()[k].x_m);
    EXPECT_EQ(path[k].heading_rad, off.filteredPath()[k].heading_rad);
  }
  const Path a = publishedTrajectory(data, "beacons", true), b = publishedTrajectory(data, "beacons", true);
  ASSERT_EQ(a.size(), b.size());
  for (size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].x_m, b[k].x_m);
    EXPECT_EQ(a[k].y_m, b[k].y_m);
    EXPECT_EQ(a[k].heading_rad, b[k].heading_rad);
    EXPECT_EQ(a[k].covariance, b[k].covariance);
  }
}

}  // namespace
}  // namespace roam
