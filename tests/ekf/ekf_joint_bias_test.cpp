// solveJointHeadingBias (ekf_joint_bias.hpp): K pending beacons, one range bias and one
// heading-rate bias error solved together from the buffered sightings.
#include <cmath>
#include <map>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "ekf_joint_bias.hpp"

namespace roam {
namespace ekf {
namespace {

using estimation::MultilaterationResult;
using estimation::RangeBiasPrior;
using estimation::Sighting;

struct JointWorld {
  std::map<int, std::vector<Sighting>> sightings;
  std::map<int, MultilaterationResult> start;
  RangeBiasPrior bias;
};

// K beacons on a 30 m circle, each seen 20 times from a 10 m circular path whose buffered
// positions are off by (dx_db, dy_db) db_rad_s; exact ranges r = s |m - p| + o, except every
// tenth, 8 m long (non-line-of-sight). Each beacon's own solve starts 1 m off.
JointWorld jointWorld(int beacons, double db_rad_s, double scale, double offset_m, unsigned seed) {
  JointWorld w;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> angle(0.0, 2.0 * M_PI), slope(-60.0, 60.0);
  for (int k = 0; k < beacons; ++k) {
    const double a = 2.0 * M_PI * k / beacons;
    const Eigen::Vector2d m(30.0 * std::cos(a), 30.0 * std::sin(a));
    for (int i = 0; i < 20; ++i) {
      const double b = angle(rng);
      const Eigen::Vector2d p(10.0 * std::cos(b), 10.0 * std::sin(b));
      Sighting s;
      s.sigma_m = 0.3;
      s.dx_db = slope(rng);
      s.dy_db = slope(rng);
      s.x_m = p.x() - s.dx_db * db_rad_s;
      s.y_m = p.y() - s.dy_db * db_rad_s;
      s.range_m = scale * (m - p).norm() + offset_m + (i % 10 == 9 ? 8.0 : 0.0);
      w.sightings[k].push_back(s);
    }
    MultilaterationResult own;
    own.status = MultilaterationResult::Status::kReady;
    own.world_m = m + Eigen::Vector2d(0.6, -0.8);
    own.scale = scale;
    own.offset_m = offset_m;
    own.heading_rate_bias_rad_s = db_rad_s;
    w.start[k] = own;
  }
  w.bias.scale = 1.0;
  w.bias.scale_sigma = 0.1;
  w.bias.offset_m = 0.0;
  w.bias.offset_sigma_m = 1.0;
  w.bias.heading_rate_bias_sigma_rad_s = 1.0;  // a prior that leaves db to the data
  return w;
}

TEST(EkfJointBias, RecoversTheBiasesExactlyFromNoiseFreeSightingsAndDropsTheLongRanges) {
  for (const int beacons : {2, 4, 64}) {
    SCOPED_TRACE(beacons);
    const JointWorld w = jointWorld(beacons, 0.004, 1.0, 0.0, 7);
    const JointBiasResult r = solveJointHeadingBias(w.sightings, w.start, w.bias, 3.0, 6);
    ASSERT_TRUE(r.ok);
    EXPECT_EQ(r.beacons, beacons);
    EXPECT_EQ(r.sightings_used, 18 * beacons);  // the two long ranges of each beacon left out
    // Exact up to the db prior's pull (its cost 0.004^2 / 1^2 = 1.6e-5 against the data's
    // information of ~1e4 per sighting in db): ~1e-8 rad/s. With the long ranges kept (gate
    // 1000) db is -0.008 to 0.012 and the offset 0.5-3.9 m.
    EXPECT_NEAR(r.db_rad_s, 0.004, 1e-7);
    EXPECT_NEAR(r.scale, 1.0, 1e-7);
    EXPECT_NEAR(r.offset_m, 0.0, 1e-6);
    EXPECT_NEAR(r.chi2, 1.6e-5, 1e-8);
    EXPECT_GT(r.db_sigma_rad_s, 0.0);
  }
}

TEST(EkfJointBias, RefusesWithOneBeaconOrTooFewRanges) {
  const JointWorld one = jointWorld(1, 0.004, 1.0, 0.0, 7);
  EXPECT_FALSE(solveJointHeadingBias(one.sightings, one.start, one.bias, 3.0, 6).ok);
  const JointWorld two = jointWorld(2, 0.004, 1.0, 0.0, 7);
  EXPECT_FALSE(solveJointHeadingBias(two.sightings, two.start, two.bias, 3.0, 21).ok);  // 20 each
}

TEST(EkfJointBias, RepeatsBitForBit) {
  const JointWorld w = jointWorld(16, -0.003, 1.0, 0.0, 11);
  const JointBiasResult a = solveJointHeadingBias(w.sightings, w.start, w.bias, 3.0, 6);
  const JointBiasResult b = solveJointHeadingBias(w.sightings, w.start, w.bias, 3.0, 6);
  ASSERT_TRUE(a.ok);
  EXPECT_EQ(a.db_rad_s, b.db_rad_s);
  EXPECT_EQ(a.db_sigma_rad_s, b.db_sigma_rad_s);
  EXPECT_EQ(a.chi2, b.chi2);
}

}  // namespace
}  // namespace ekf
}  // namespace roam
