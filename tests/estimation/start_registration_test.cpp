// Start registration: a robot's start found exactly from exact ranges to another robot's path, the
// heading said unknown where one fixed point is all it ranged, a bound with noise and outliers.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "roam/estimation/start_registration.hpp"

namespace roam {
namespace estimation {
namespace {

// The robot drives a curve in its own frame; the other robot (world frame) a wider loop.
Eigen::Vector2d localPath(double t) { return {2.0 * t, 3.0 * std::sin(0.3 * t)}; }
Eigen::Vector2d otherPath(double t) { return {10.0 * std::cos(0.2 * t), 8.0 * std::sin(0.2 * t)}; }

Eigen::Vector2d toWorld(const Eigen::Vector3d& start, const Eigen::Vector2d& local) {
  const double c = std::cos(start.z()), s = std::sin(start.z());
  return start.head<2>() + Eigen::Vector2d(c * local.x() - s * local.y(), s * local.x() + c * local.y());
}

std::vector<StartRangeObservation> rangesToOther(const Eigen::Vector3d& start, int n, double sigma_m) {
  std::vector<StartRangeObservation> out;
  for (int i = 0; i < n; ++i) {
    const double t = 0.25 * i;
    StartRangeObservation o;
    o.local_m = localPath(t);
    o.world_m = otherPath(t);
    o.range_m = (o.world_m - toWorld(start, o.local_m)).norm();
    o.sigma_m = sigma_m;
    out.push_back(o);
  }
  return out;
}

TEST(StartRegistration, ExactRangesToAMovingRobotGiveTheStart) {
  const Eigen::Vector3d start(4.0, -3.0, 2.2);
  const StartRegistration found = registerStart(rangesToOther(start, 80, 0.1));
  ASSERT_EQ(found.status, StartRegistration::Status::kFound);
  EXPECT_NEAR(found.start.x(), start.x(), 1e-6);
  EXPECT_NEAR(found.start.y(), start.y(), 1e-6);
  EXPECT_NEAR(found.start.z(), start.z(), 1e-6);
  EXPECT_EQ(found.inliers, 80);
}

TEST(StartRegistration, OneFixedPointLeavesTheHeadingUnknown) {
  const Eigen::Vector3d start(4.0, -3.0, 2.2);
  std::vector<StartRangeObservation> observations = rangesToOther(start, 80, 0.1);
  for (auto& o : observations) {
    o.world_m = Eigen::Vector2d(1.0, 2.0);  // one beacon: every heading about it fits alike
    o.range_m = (o.world_m - toWorld(start, o.local_m)).norm();
  }
  EXPECT_EQ(registerStart(observations).status, StartRegistration::Status::kAmbiguous);
}

TEST(StartRegistration, TooFewRangesAreSaid) {
  EXPECT_EQ(registerStart(rangesToOther({0.0, 0.0, 0.0}, 5, 0.1)).status, StartRegistration::Status::kTooFew);
}

TEST(StartRegistration, NoiseAndLongOutliersStayWithinABound) {
  const Eigen::Vector3d start(-6.0, 5.0, -1.0);
  for (unsigned seed : {1u, 2u, 3u}) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> noise(0.0, 0.2);
    std::uniform_real_distribution<double> unit(0.0, 1.0), extra(2.0, 20.0);
    std::vector<StartRangeObservation> observations = rangesToOther(start, 200, 0.2);
    for (auto& o : observations) o.range_m += noise(rng) + (unit(rng) < 0.2 ? extra(rng) : 0.0);
    const StartRegistration found = registerStart(observations);
    ASSERT_EQ(found.status, StartRegistration::Status::kFound) << "seed " << seed;
    // 160 inlier ranges of 0.2 m over a ~20 m baseline: centimetres, and a degree.
    EXPECT_LT((found.start.head<2>() - start.head<2>()).norm(), 0.15) << "seed " << seed;
    EXPECT_LT(std::abs(found.start.z() - start.z()), 0.02) << "seed " << seed;
    // f: 1.4826 x the median |residual|, which a fifth of the ranges long puts at the inliers'
    // 0.625 quantile: 1.3 where the stated sigma is right.
    EXPECT_NEAR(found.noise_factor, 1.3, 0.2) << "seed " << seed;
    // Its covariance says as much (3 sigma).
    EXPECT_LT(std::abs(found.start.z() - start.z()), 3.0 * std::sqrt(found.covariance(2, 2)) + 1e-3);
  }
}

TEST(StartRegistration, RunsAreBitIdentical) {
  std::vector<StartRangeObservation> observations = rangesToOther({1.0, 2.0, 0.5}, 60, 0.1);
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, 0.1);
  for (auto& o : observations) o.range_m += noise(rng);
  const StartRegistration a = registerStart(observations), b = registerStart(observations);
  EXPECT_EQ(a.start, b.start);
  EXPECT_EQ(a.cost, b.cost);
}

}  // namespace
}  // namespace estimation
}  // namespace roam
