#include "roam/estimation/range_model.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace roam {
namespace estimation {
namespace {

TEST(RangeModel, PredictsScaleTimesDistancePlusOffset) {
  EXPECT_DOUBLE_EQ(beaconDistance_m(1.0, 2.0, 4.0, 6.0), 5.0);
  EXPECT_DOUBLE_EQ(predictedRange_m(5.0, RangeCalibration{}), 5.0);
  EXPECT_DOUBLE_EQ(predictedRange_m(5.0, RangeCalibration{1.07, -0.25}), 1.07 * 5.0 - 0.25);
  EXPECT_DOUBLE_EQ(predictedRange_m(5.0, 2.0, 1.0), 11.0);
}

TEST(RangeModel, PositionGradientIsMinusScaleTimesTheUnitVectorToTheBeacon) {
  const RangeCalibration c{1.05, 0.3};
  const double x = 1.0, y = -2.0, bx = 7.0, by = 3.0, h = 1e-6;
  const double d = beaconDistance_m(x, y, bx, by);
  const double gx = (predictedRange_m(beaconDistance_m(x + h, y, bx, by), c) -
                     predictedRange_m(beaconDistance_m(x - h, y, bx, by), c)) / (2 * h);
  const double gy = (predictedRange_m(beaconDistance_m(x, y + h, bx, by), c) -
                     predictedRange_m(beaconDistance_m(x, y - h, bx, by), c)) / (2 * h);
  EXPECT_NEAR(gx, -c.scale * (bx - x) / d, 1e-8);
  EXPECT_NEAR(gy, -c.scale * (by - y) / d, 1e-8);
}

TEST(RobustKernels, WeightsAreOneAtZeroAndFallAsTheKernelSays) {
  EXPECT_DOUBLE_EQ(huberWeight(0.0), 1.0);
  EXPECT_DOUBLE_EQ(huberWeight(kHuber95), 1.0);
  EXPECT_DOUBLE_EQ(huberWeight(-4.0 * kHuber95), 0.25);
  EXPECT_DOUBLE_EQ(cauchyWeight(0.0), 1.0);
  EXPECT_DOUBLE_EQ(cauchyWeight(kCauchy95), 0.5);
  EXPECT_DOUBLE_EQ(cauchyWeight(-3.0 * kCauchy95), 0.1);
  EXPECT_DOUBLE_EQ(tukeyWeight(0.0), 1.0);
  EXPECT_DOUBLE_EQ(tukeyWeight(kTukey95), 0.0);
  EXPECT_DOUBLE_EQ(tukeyWeight(kTukey95 / std::sqrt(2.0)), 0.25);
}

}  // namespace
}  // namespace estimation
}  // namespace roam
