// Multilateration: exact recovery on noise-free ranges, the line case refused, and the robust
// solution holding where 30 % of the ranges are long by 5-40 m (non-line-of-sight) while the
// linear one is pulled metres off.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "roam/estimation/multilateration.hpp"

namespace roam {
namespace estimation {
namespace {

TEST(Multilateration, PositionSpreadIsTheDistanceFromALine) {
  EXPECT_EQ(positionSpread({}), 0.0);
  EXPECT_EQ(positionSpread({{1.0, 2.0}}), 0.0);
  // On a line (any direction): 0; a 4 x 2 m rectangle's corners: the short side's half, 1 m.
  EXPECT_NEAR(positionSpread({{0.0, 0.0}, {1.0, 1.0}, {3.0, 3.0}}), 0.0, 1e-9);
  EXPECT_NEAR(positionSpread({{0.0, 0.0}, {4.0, 0.0}, {4.0, 2.0}, {0.0, 2.0}}), 1.0, 1e-12);
}

TEST(Multilateration, ExactOnNoiseFreeRanges) {
  const std::array<double, 2> beacon{12.5, -7.25};
  std::vector<std::array<double, 2>> positions{{0, 0}, {10, 0}, {0, 10}, {-5, 3}, {7, 8}};
  std::vector<double> ranges;
  for (const auto& p : positions) ranges.push_back(std::hypot(beacon[0] - p[0], beacon[1] - p[1]));
  std::array<double, 2> linear{};
  ASSERT_TRUE(multilaterateLinear(positions, ranges, &linear));
  EXPECT_NEAR(linear[0], beacon[0], 1e-9);
  EXPECT_NEAR(linear[1], beacon[1], 1e-9);
  RobustMultilateration robust;
  ASSERT_TRUE(multilaterateRobust(positions, ranges, 0.3, &robust));
  EXPECT_NEAR(robust.beacon_m[0], beacon[0], 1e-6);
  EXPECT_NEAR(robust.beacon_m[1], beacon[1], 1e-6);
  EXPECT_EQ(robust.inliers, 5);
  EXPECT_LT(robust.cost, 1e-10);
}

TEST(Multilateration, RefusesPositionsOnALine) {
  std::vector<std::array<double, 2>> positions{{0, 0}, {1, 1}, {2, 2}, {3, 3}};
  std::vector<double> ranges{5, 4, 3, 2};
  std::array<double, 2> beacon{};
  EXPECT_FALSE(multilaterateLinear(positions, ranges, &beacon));
  RobustMultilateration robust;
  EXPECT_FALSE(multilaterateRobust(positions, ranges, 0.3, &robust));
  EXPECT_FALSE(multilaterateLinear({{0, 0}, {1, 0}}, {1, 1}, &beacon));
}

TEST(Multilateration, RobustHoldsThirtyPercentLongOutliers) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> where(-20.0, 20.0), extra(5.0, 40.0), unit(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, 0.3);
  const std::array<double, 2> beacon{3.0, 25.0};
  std::vector<std::array<double, 2>> positions;
  std::vector<double> ranges;
  int outliers = 0;
  for (int i = 0; i < 200; ++i) {
    positions.push_back({where(rng), where(rng)});
    double r = std::hypot(beacon[0] - positions.back()[0], beacon[1] - positions.back()[1]) + noise(rng);
    if (unit(rng) < 0.3) {
      r += extra(rng);
      ++outliers;
    }
    ranges.push_back(r);
  }
  std::array<double, 2> linear{};
  ASSERT_TRUE(multilaterateLinear(positions, ranges, &linear));
  RobustMultilateration robust;
  ASSERT_TRUE(multilaterateRobust(positions, ranges, 0.3, &robust));
  const double linear_error = std::hypot(linear[0] - beacon[0], linear[1] - beacon[1]);
  const double robust_error = std::hypot(robust.beacon_m[0] - beacon[0], robust.beacon_m[1] - beacon[1]);
  std::printf("linear %.3f m, robust %.3f m, %d outliers, %d inliers\n", linear_error, robust_error, outliers,
              robust.inliers);
  EXPECT_GT(linear_error, 2.0);
  EXPECT_LT(robust_error, 0.15);
  EXPECT_NEAR(robust.inliers, 200 - outliers, 5);
}

TEST(Multilateration, ConsensusIgnoresLongOutliers) {
  // Twelve exact ranges, five of them 5-30 m too long: the linear solution on all is pulled off
  // by metres; the consensus of triples keeps the seven exact ones and is exact.
  const std::array<double, 2> beacon{20.0, 15.0};
  std::vector<std::array<double, 2>> positions;
  std::vector<double> ranges;
  for (int k = 0; k < 12; ++k) {
    positions.push_back({3.0 * k, k % 2 == 0 ? 0.0 : 6.0});
    const double true_m = std::hypot(beacon[0] - positions.back()[0], beacon[1] - positions.back()[1]);
    ranges.push_back(true_m + (k % 5 == 1 || k == 4 || k == 10 ? 5.0 + 2.5 * k : 0.0));
  }
  std::array<double, 2> plain{}, robust{};
  ASSERT_TRUE(multilaterateLinear(positions, ranges, &plain));
  ASSERT_TRUE(multilaterateConsensus(positions, ranges, 1.0, &robust));
  EXPECT_GT(std::hypot(plain[0] - beacon[0], plain[1] - beacon[1]), 1.0);
  EXPECT_NEAR(std::hypot(robust[0] - beacon[0], robust[1] - beacon[1]), 0.0, 1e-6);
  // Fewer than 3 ranges within the band of any triple's solution, or no band: refused.
  EXPECT_FALSE(multilaterateConsensus({{0, 0}, {1, 0}}, {1.0, 1.0}, 1.0, &robust));
  EXPECT_FALSE(multilaterateConsensus(positions, ranges, 0.0, &robust));
}

}  // namespace
}  // namespace estimation
}  // namespace roam
