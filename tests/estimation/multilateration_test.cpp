// Multilateration: exact recovery on noise-free ranges, the line case refused, and the robust
// solution holding where 30 % of the ranges are long by 5-40 m (non-line-of-sight) while the
// linear one is pulled metres off.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <utility>

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
  // The reported cost is sum_i rho(e_i^2) / 2 (Cauchy, c = 2.385) at the solution, and the
  // solution is its minimum: a millimetre any way costs more.
  auto cost = [&](double x_m, double y_m) {
    const double c = 2.385;
    double sum = 0.0;
    for (size_t i = 0; i < positions.size(); ++i) {
      const double e = (std::hypot(x_m - positions[i][0], y_m - positions[i][1]) - ranges[i]) / 0.3;
      sum += 0.5 * c * c * std::log1p(e * e / (c * c));
    }
    return sum;
  };
  const double at = cost(robust.beacon_m[0], robust.beacon_m[1]);
  EXPECT_NEAR(robust.cost, at, 1e-9 * at);
  for (const auto& [dx, dy] : {std::pair{1e-3, 0.0}, {-1e-3, 0.0}, {0.0, 1e-3}, {0.0, -1e-3}})
    EXPECT_GT(cost(robust.beacon_m[0] + dx, robust.beacon_m[1] + dy), at);
}

TEST(MultilaterationConsensus, ExactOnNoiseFreeRangesAndRefusesBadInput) {
  // Noise-free: every range agrees with the beacon; off a line the refined point is exact.
  const std::array<double, 2> beacon{12.5, -7.25};
  std::vector<std::array<double, 2>> positions{{0, 0}, {10, 0}, {0, 10}, {-5, 3}, {7, 8}};
  std::vector<double> ranges, tolerance(positions.size(), 0.5);
  for (const auto& p : positions) ranges.push_back(std::hypot(beacon[0] - p[0], beacon[1] - p[1]));
  ConsensusMultilateration result;
  ASSERT_TRUE(multilaterateConsensus(positions, ranges, tolerance, &result));
  EXPECT_NEAR(result.point_m[0], beacon[0], 1e-6);
  EXPECT_NEAR(result.point_m[1], beacon[1], 1e-6);
  EXPECT_EQ(result.inliers, 5);
  EXPECT_FALSE(multilaterateConsensus({{0, 0}}, {1.0}, {0.5}, &result));
  EXPECT_FALSE(multilaterateConsensus(positions, ranges, {0.5}, &result));
}

TEST(MultilaterationConsensus, HoldsWithFortyPercentOfRangesArbitrarilyWrong) {
  // 40 % of the ranges are off by -150..+100 m (an AUV's acoustic echoes), 60 % have 2 m noise:
  // the consensus point is within 1.5 m and names the wrong ones; the linear one is > 2 m off.
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 2.0);
  std::uniform_real_distribution<double> wild(-150.0, 100.0), angle(0.0, 2.0 * M_PI);
  const std::array<double, 2> beacon{40.0, -120.0};
  std::vector<std::array<double, 2>> positions;
  std::vector<double> ranges, tolerance;
  std::vector<bool> outlier;
  for (int i = 0; i < 40; ++i) {
    const double a = angle(rng);
    positions.push_back({150.0 * std::cos(a), 100.0 * std::sin(a)});
    const double truth = std::hypot(beacon[0] - positions.back()[0], beacon[1] - positions.back()[1]);
    outlier.push_back(i % 5 < 2);
    ranges.push_back(outlier.back() ? std::max(1.0, truth + wild(rng)) : truth + noise(rng));
    tolerance.push_back(3.0 * 2.0);
  }
  ConsensusMultilateration result;
  ASSERT_TRUE(multilaterateConsensus(positions, ranges, tolerance, &result));
  EXPECT_LT(std::hypot(result.point_m[0] - beacon[0], result.point_m[1] - beacon[1]), 1.5);
  int wrongly_kept = 0, good_dropped = 0;
  for (size_t i = 0; i < outlier.size(); ++i) {
    wrongly_kept += outlier[i] && result.inlier[i];
    good_dropped += !outlier[i] && !result.inlier[i];
  }
  EXPECT_LE(wrongly_kept, 2);
  EXPECT_EQ(good_dropped, 0);
  std::array<double, 2> linear{};
  ASSERT_TRUE(multilaterateLinear(positions, ranges, &linear));
  EXPECT_GT(std::hypot(linear[0] - beacon[0], linear[1] - beacon[1]), 2.0);
  ConsensusMultilateration again;  // bit-identical with sampled pairs too
  ASSERT_TRUE(multilaterateConsensus(positions, ranges, tolerance, &again, 50));
  ConsensusMultilateration again2;
  ASSERT_TRUE(multilaterateConsensus(positions, ranges, tolerance, &again2, 50));
  EXPECT_EQ(again.point_m, again2.point_m);
  EXPECT_LT(std::hypot(again.point_m[0] - beacon[0], again.point_m[1] - beacon[1]), 1.5);
}

TEST(Multilateration, TriplesIgnoreLongOutliers) {
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
  ASSERT_TRUE(multilaterateTriples(positions, ranges, 1.0, &robust));
  EXPECT_GT(std::hypot(plain[0] - beacon[0], plain[1] - beacon[1]), 1.0);
  EXPECT_NEAR(std::hypot(robust[0] - beacon[0], robust[1] - beacon[1]), 0.0, 1e-6);
  // Fewer than 3 ranges within the band of any triple's solution, or no band: refused.
  EXPECT_FALSE(multilaterateTriples({{0, 0}, {1, 0}}, {1.0, 1.0}, 1.0, &robust));
  EXPECT_FALSE(multilaterateTriples(positions, ranges, 0.0, &robust));
}

TEST(Multilateration, TriplesAreDrawnWhenThereAreTooManyToTry) {
  // A landmark of 170 ranges (a 60 m lane and its turn at 10 Hz ranging), 40 % of them 2-40 m
  // long: C(170, 3) = 804,440 triples, more than max_triples (20,000 by default), so 20,000 are
  // drawn by the fixed sequence. The inliers are exact, so the consensus is exact either way.
  const std::array<double, 2> beacon{30.0, 12.0};
  std::vector<std::array<double, 2>> positions;
  std::vector<double> ranges;
  for (int k = 0; k < 170; ++k) {
    positions.push_back(k < 150 ? std::array<double, 2>{0.4 * k, 0.0} : std::array<double, 2>{60.0, 0.25 * (k - 149)});
    const double true_m = std::hypot(beacon[0] - positions.back()[0], beacon[1] - positions.back()[1]);
    ranges.push_back(true_m + (k % 5 < 2 ? 2.0 + 0.23 * k : 0.0));
  }
  std::array<double, 2> drawn{}, again{}, every{};
  ASSERT_TRUE(multilaterateTriples(positions, ranges, 1.0, &drawn));
  ASSERT_TRUE(multilaterateTriples(positions, ranges, 1.0, &again));
  ASSERT_TRUE(multilaterateTriples(positions, ranges, 1.0, &every, 1 << 30));
  EXPECT_NEAR(std::hypot(drawn[0] - beacon[0], drawn[1] - beacon[1]), 0.0, 1e-6);
  EXPECT_NEAR(std::hypot(every[0] - beacon[0], every[1] - beacon[1]), 0.0, 1e-6);
  EXPECT_EQ(drawn, again);  // bit-identical
  // At most max_triples triples: every one is tried, in order, and the answer is the one of
  // trying every triple bit for bit (C(30, 3) = 4060; the last 30: the lane's end and the turn).
  const std::vector<std::array<double, 2>> last30(positions.end() - 30, positions.end());
  const std::vector<double> ranges30(ranges.end() - 30, ranges.end());
  std::array<double, 2> capped{}, uncapped{};
  ASSERT_TRUE(multilaterateTriples(last30, ranges30, 1.0, &capped, 4060));
  ASSERT_TRUE(multilaterateTriples(last30, ranges30, 1.0, &uncapped, 1 << 30));
  EXPECT_EQ(capped, uncapped);
  // Drawn with a cap of 100 on 30 ranges: still three distinct ranges per triple (an exact
  // answer needs a triple of distinct exact ranges).
  std::array<double, 2> few{};
  ASSERT_TRUE(multilaterateTriples(last30, ranges30, 1.0, &few, 100));
  EXPECT_NEAR(std::hypot(few[0] - beacon[0], few[1] - beacon[1]), 0.0, 1e-6);
}

}  // namespace
}  // namespace estimation
}  // namespace roam
