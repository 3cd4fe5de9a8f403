// EkfFilter: motion model, measurement Jacobians against central differences, Joseph update.
#include <gtest/gtest.h>

#include <cmath>

#include "ekf_config.hpp"
#include "ekf_filter.hpp"

namespace roam {
namespace ekf {
namespace {

constexpr double kExact = 1e-12;
constexpr double kJacobianTolerance = 1e-7;  // central differences with h = 1e-6

EkfFilter filterWithBeacon(bool with_bias) {
  EkfFilter filter;
  filter.reset(Eigen::Vector3d(1.0, 2.0, 0.3), 0.01 * Eigen::Matrix3d::Identity(), with_bias, 0.1, 0.5);
  filter.addBeacon(7, Eigen::Vector2d(5.0, 9.0), 0.04 * Eigen::Matrix2d::Identity());
  return filter;
}

TEST(EkfFilter, PredictMovesThenTurns) {
  EkfFilter filter;
  filter.reset(Eigen::Vector3d(1.0, 2.0, M_PI / 2), Eigen::Matrix3d::Zero(), false, 0.1, 0.5);
  filter.predict(2.0, 0.5, 0.0, 0.0);
  // Heading pi/2: the step goes along +y, (1, 2) -> (1, 4); then heading pi/2 + 0.5.
  EXPECT_NEAR(filter.mean()(0), 1.0, kExact);
  EXPECT_NEAR(filter.mean()(1), 4.0, kExact);
  EXPECT_NEAR(filter.mean()(2), M_PI / 2 + 0.5, kExact);
  // Only the distance noise, along +y: P_yy = var_d = 0.04, the rest 0.
  EkfFilter noisy;
  noisy.reset(Eigen::Vector3d(0.0, 0.0, M_PI / 2), Eigen::Matrix3d::Zero(), false, 0.1, 0.5);
  noisy.predict(2.0, 0.0, 0.04, 0.0);
  EXPECT_NEAR(noisy.covariance()(1, 1), 0.04, kExact);
  EXPECT_NEAR(noisy.covariance()(0, 0), 0.0, kExact);
}

TEST(EkfFilter, PredictWrapsHeading) {
  EkfFilter filter;
  filter.reset(Eigen::Vector3d(0.0, 0.0, 3.0), Eigen::Matrix3d::Zero(), false, 0.1, 0.5);
  filter.predict(0.0, 0.5, 0.0, 0.0);
  EXPECT_NEAR(filter.mean()(2), 3.5 - 2.0 * M_PI, kExact);
}

TEST(EkfFilter, RangePredictionWorkedByHand) {
  EkfFilter filter = filterWithBeacon(false);
  // |(5, 9) - (1, 2)| = |(4, 7)| = sqrt(65).
  EXPECT_NEAR(filter.predictRange(7, nullptr), std::sqrt(65.0), kExact);
  // Bearing atan2(7, 4) - 0.3.
  EXPECT_NEAR(filter.predictBearing(7, nullptr), std::atan2(7.0, 4.0) - 0.3, kExact);
}

TEST(EkfFilter, JacobiansMatchCentralDifferences) {
  for (bool with_bias : {false, true}) {
    const EkfFilter filter = filterWithBeacon(with_bias);  // scale 1, offset 0
    Eigen::RowVectorXd H_range, H_bearing;
    filter.predictRange(7, &H_range);
    filter.predictBearing(7, &H_bearing);
    const int m = filter.beaconIndex(7);
    // A filter with the same scale and offset and the pose and beacon moved to x.
    auto rebuild = [&](const Eigen::VectorXd& x) {
      EkfFilter f;
      f.reset(x.head<3>(), Eigen::Matrix3d::Identity(), with_bias, 0.1, 0.5);
      f.addBeacon(7, x.segment<2>(m), Eigen::Matrix2d::Identity());
      return f;
    };
    const double h = 1e-6;
    for (int i = 0; i < filter.size(); ++i) {
      if (with_bias && (i == EkfFilter::kScale || i == EkfFilter::kOffset)) {
        // range = scale |m - p| + offset: d/dscale = |m - p| = sqrt(65), d/doffset = 1.
        EXPECT_NEAR(H_range(i), i == EkfFilter::kScale ? std::sqrt(65.0) : 1.0, kExact);
        EXPECT_NEAR(H_bearing(i), 0.0, kExact);
        continue;
      }
      Eigen::VectorXd dx = Eigen::VectorXd::Zero(filter.size());
      dx(i) = h;
      const EkfFilter plus = rebuild(filter.mean() + dx), minus = rebuild(filter.mean() - dx);
      const double numeric_range = (plus.predictRange(7, nullptr) - minus.predictRange(7, nullptr)) / (2 * h);
      const double numeric_bearing = (plus.predictBearing(7, nullptr) - minus.predictBearing(7, nullptr)) / (2 * h);
      EXPECT_NEAR(H_range(i), numeric_range, kJacobianTolerance) << "state " << i;
      EXPECT_NEAR(H_bearing(i), numeric_bearing, kJacobianTolerance) << "state " << i;
    }
  }
}

TEST(EkfFilter, PerBeaconOffsetEntersTheRangeAndLearnsLikeAScalarKalman) {
  // Robot and beacon known exactly (variance 0), beacon 7 with its own offset o ~ N(0, 1.5^2),
  // beacon 8 without: range = |m - p| + o. Worked by hand: the prediction is sqrt(65) + 0 and
  // d range / d o = 1; a range of sqrt(65) + 2 with sigma 1 gives S = 2.25 + 1, K = 2.25 / 3.25,
  // o = 2 K and var(o) = (1 - K)^2 2.25 + K^2 = 2.25 / 3.25; beacon 8's range is untouched.
  EkfFilter filter;
  filter.reset(Eigen::Vector3d(1.0, 2.0, 0.3), Eigen::Matrix3d::Zero(), false, 0.1, 0.5);
  filter.addBeacon(7, Eigen::Vector2d(5.0, 9.0), Eigen::Matrix2d::Zero(), 1.5);
  filter.addBeacon(8, Eigen::Vector2d(1.0, 12.0), Eigen::Matrix2d::Zero());
  ASSERT_EQ(filter.size(), 3 + 3 + 2);
  const int o = filter.beaconOffsetIndex(7);
  EXPECT_EQ(o, filter.beaconIndex(7) + 2);
  EXPECT_EQ(filter.beaconOffsetIndex(8), -1);
  EXPECT_NEAR(filter.covariance()(o, o), 2.25, kExact);
  Eigen::RowVectorXd H;
  EXPECT_NEAR(filter.predictRange(7, &H), std::sqrt(65.0), kExact);
  EXPECT_NEAR(H(o), 1.0, kExact);
  double nis = 0.0;
  ASSERT_EQ(filter.updateRange(7, std::sqrt(65.0) + 2.0, 1.0, 100.0, &nis), EkfFilter::Update::kApplied);
  const double K = 2.25 / 3.25;
  EXPECT_NEAR(nis, 4.0 / 3.25, kExact);
  EXPECT_NEAR(filter.beaconOffset(7), 2.0 * K, kExact);
  EXPECT_NEAR(filter.covariance()(o, o), 2.25 / 3.25, kExact);
  EXPECT_NEAR(filter.predictRange(7, nullptr), std::sqrt(65.0) + 2.0 * K, kExact);
  EXPECT_NEAR(filter.predictRange(8, nullptr), 10.0, kExact);
  EXPECT_NEAR(filter.mean()(0), 1.0, kExact);  // the pose is known: only o moved
}

TEST(EkfFilter, RangeUpdateMatchesScalarKalmanAndStaysSymmetric) {
  // Robot known exactly at the origin, beacon at (10, 0) with variance 4 per axis, range 9 with
  // sigma 1: H = [.., 1, 0] on the beacon, S = 4 + 1 = 5, K_mx = 4/5, innovation 9 - 10 = -1,
  // so mx = 10 - 0.8 = 9.2 and var(mx) = (1 - 0.8)^2 4 + 0.8^2 1 = 0.8; my is unchanged.
  EkfFilter filter;
  filter.reset(Eigen::Vector3d::Zero(), Eigen::Matrix3d::Zero(), false, 0.1, 0.5);
  filter.addBeacon(1, Eigen::Vector2d(10.0, 0.0), 4.0 * Eigen::Matrix2d::Identity());
  double nis = 0.0;
  EXPECT_EQ(filter.updateRange(1, 9.0, 1.0, 100.0, &nis), EkfFilter::Update::kApplied);
  EXPECT_NEAR(nis, 1.0 / 5.0, kExact);
  EXPECT_NEAR(filter.mean()(3), 9.2, kExact);
  EXPECT_NEAR(filter.mean()(4), 0.0, kExact);
  EXPECT_NEAR(filter.covariance()(3, 3), 0.8, kExact);
  EXPECT_NEAR(filter.covariance()(4, 4), 4.0, kExact);
  EXPECT_TRUE(filter.covariance().isApprox(filter.covariance().transpose(), 0.0));
}

TEST(EkfFilter, GateRejectsWithoutChangingTheState) {
  EkfFilter filter = filterWithBeacon(true);
  const Eigen::VectorXd x = filter.mean();
  const Eigen::MatrixXd P = filter.covariance();
  double nis = 0.0;
  EXPECT_EQ(filter.updateRange(7, std::sqrt(65.0) + 20.0, 0.3, chiSquareQuantile(1, 0.999), &nis),
            EkfFilter::Update::kGated);
  EXPECT_GT(nis, chiSquareQuantile(1, 0.999));
  EXPECT_EQ(filter.mean(), x);
  EXPECT_EQ(filter.covariance(), P);
}

TEST(EkfConfig, ChiSquareQuantiles) {
  // Tabulated: chi2(1) 95 % = 3.841, 99.9 % = 10.828; chi2(2) 95 % = -2 ln 0.05 = 5.991.
  EXPECT_NEAR(chiSquareQuantile(1, 0.95), 3.8415, 1e-4);
  EXPECT_NEAR(chiSquareQuantile(1, 0.999), 10.8276, 1e-4);
  EXPECT_NEAR(chiSquareQuantile(2, 0.95), 5.9915, 1e-4);
  EXPECT_TRUE(std::isinf(chiSquareQuantile(1, 1.0)));
}

TEST(EkfConfig, WilsonHilfertyQuantilesAreWithinAPercentOfTheTables) {
  // Tabulated: chi2(10) 99 % = 23.209, chi2(30) 99.9 % = 59.703, chi2(100) 95 % = 124.342.
  EXPECT_NEAR(chiSquareQuantileWilsonHilferty(10, 0.99), 23.209, 0.01 * 23.209);
  EXPECT_NEAR(chiSquareQuantileWilsonHilferty(30, 0.999), 59.703, 0.01 * 59.703);
  EXPECT_NEAR(chiSquareQuantileWilsonHilferty(100, 0.95), 124.342, 0.01 * 124.342);
}

}  // namespace
}  // namespace ekf
}  // namespace roam
