// The shared motion model: exact steps worked out by hand, Jacobians against central
// differences, and the noise floor under a reported covariance.
#include <gtest/gtest.h>

#include <cmath>

#include "roam/estimation/motion_model.hpp"

namespace roam {
namespace estimation {
namespace {

constexpr double kTolerance = 1e-12;

Odometry makeStep(double forward_m, double lateral_m, double turn_rad, int64_t utime = 0) {
  Odometry o;
  o.utime = utime;
  o.forward_m = forward_m;
  o.lateral_m = lateral_m;
  o.delta_heading_rad = turn_rad;
  return o;
}

TEST(MotionModel, MoveThenTurnIsTheCaseWithoutLateralMotion) {
  // From (1, 2) facing +y (pi/2): 3 m forward is (1, 5); then turn by 0.25 rad.
  Pose start;
  start.x_m = 1.0;
  start.y_m = 2.0;
  start.heading_rad = M_PI / 2;
  const Pose next = step(start, makeStep(3.0, 0.0, 0.25, 77));
  EXPECT_NEAR(next.x_m, 1.0, kTolerance);
  EXPECT_NEAR(next.y_m, 5.0, kTolerance);
  EXPECT_NEAR(next.heading_rad, M_PI / 2 + 0.25, kTolerance);
  EXPECT_EQ(next.utime, 77);
}

TEST(MotionModel, LateralMotionIsToTheLeftOfTheHeading) {
  // Facing +y, 2 m to the left is -x: (1, 2) -> (-1, 2). Forward 1 m as well: (-1, 3).
  const Eigen::Vector3d next = step(Eigen::Vector3d(1.0, 2.0, M_PI / 2), Eigen::Vector3d(1.0, 2.0, 0.0));
  EXPECT_NEAR(next[0], -1.0, kTolerance);
  EXPECT_NEAR(next[1], 3.0, kTolerance);
}

TEST(MotionModel, CalibrationScalesTheDistanceAndRemovesTheGyroBias) {
  // s = 1.1, b = 0.01 rad/s over 2 s: (2, 1, 0.5) -> (2.2, 1.1, 0.48).
  OdometryCalibration calibration;
  calibration.distance_scale = 1.1;
  calibration.heading_rate_bias_rad_s = 0.01;
  const Eigen::Vector3d inc = calibratedIncrement(makeStep(2.0, 1.0, 0.5), 2.0, calibration);
  EXPECT_NEAR(inc[0], 2.2, kTolerance);
  EXPECT_NEAR(inc[1], 1.1, kTolerance);
  EXPECT_NEAR(inc[2], 0.48, kTolerance);
}

TEST(MotionModel, StandingStillTurnsByNothingWhateverTheGyroReports) {
  // s = 1.1, b = 0.004 rad/s over 0.2 s: moving, (0.001, 0, 0.002) -> (0.0011, 0, 0.0012);
  // standing still the turn is 0 and the bias moves nothing (its Jacobian column is zero).
  OdometryCalibration calibration{1.1, 0.004};
  const Eigen::Vector3d moving = calibratedIncrement(makeStep(0.001, 0.0, 0.002), 0.2, calibration);
  const Eigen::Vector3d standing = calibratedIncrement(makeStep(0.001, 0.0, 0.002), 0.2, calibration, true);
  EXPECT_NEAR(moving[2], 0.0012, kTolerance);
  EXPECT_NEAR(standing[0], 0.0011, kTolerance);
  EXPECT_EQ(standing[2], 0.0);
  const Eigen::Vector3d pose(1, 2, 0.3);
  EXPECT_EQ(stepJacobians(pose, makeStep(0.001, 0.0, 0.002), 0.2, calibration, true).wrt_calibration(2, 1), 0.0);
  EXPECT_EQ(stepJacobians(pose, makeStep(0.001, 0.0, 0.002), 0.2, calibration).wrt_calibration(2, 1), -0.2);
}

TEST(MotionModel, JacobiansMatchCentralDifferences) {
  const Eigen::Vector3d pose(0.3, -1.2, 2.1);
  const Odometry odometry = makeStep(1.7, -0.4, 0.2);
  const double dt_s = 3.0;
  OdometryCalibration calibration{1.05, 0.002};
  const StepJacobians j = stepJacobians(pose, odometry, dt_s, calibration);
  auto next = [&](const Eigen::Vector3d& p, const OdometryCalibration& c) {
    return step(p, calibratedIncrement(odometry, dt_s, c));
  };
  constexpr double h = 1e-6, kDerivativeTolerance = 1e-8;
  for (int k = 0; k < 3; ++k) {
    Eigen::Vector3d plus = pose, minus = pose;
    plus[k] += h;
    minus[k] -= h;
    const Eigen::Vector3d numeric = (next(plus, calibration) - next(minus, calibration)) / (2 * h);
    EXPECT_TRUE(numeric.isApprox(j.wrt_pose.col(k), kDerivativeTolerance)) << k;
  }
  const Eigen::Vector3d inc = calibratedIncrement(odometry, dt_s, calibration);
  for (int k = 0; k < 3; ++k) {
    Eigen::Vector3d plus = inc, minus = inc;
    plus[k] += h;
    minus[k] -= h;
    const Eigen::Vector3d numeric = (step(pose, plus) - step(pose, minus)) / (2 * h);
    EXPECT_LT((numeric - j.wrt_increment.col(k)).norm(), kDerivativeTolerance) << k;
  }
  OdometryCalibration plus = calibration, minus = calibration;
  plus.distance_scale += h;
  minus.distance_scale -= h;
  EXPECT_LT(((next(pose, plus) - next(pose, minus)) / (2 * h) - j.wrt_calibration.col(0)).norm(),
            kDerivativeTolerance);
  plus = minus = calibration;
  plus.heading_rate_bias_rad_s += h;
  minus.heading_rate_bias_rad_s -= h;
  EXPECT_LT(((next(pose, plus) - next(pose, minus)) / (2 * h) - j.wrt_calibration.col(1)).norm(),
            kDerivativeTolerance);
}

TEST(MotionModel, NoiseFromRatesOrFromTheReportedCovarianceNeverBelowTheFloor) {
  MotionNoise noise;
  noise.distance_fraction = 0.1;
  noise.heading_rad_per_sqrt_s = 0.01;
  Odometry odometry = makeStep(3.0, 4.0, 0.0);  // 5 m: sigma 0.5 m; 4 s: sigma 0.02 rad
  Eigen::Matrix3d cov = incrementCovariance(odometry, 4.0, noise);
  EXPECT_NEAR(cov(0, 0), 0.25, kTolerance);
  EXPECT_NEAR(cov(1, 1), 0.25, kTolerance);
  EXPECT_NEAR(cov(2, 2), 4e-4, kTolerance);
  EXPECT_EQ(cov(0, 1), 0.0);
  // A reported covariance larger than the floor is taken as it is.
  odometry.covariance = {1.0, 0.5, 0.0, 0.5, 1.0, 0.0, 0.0, 0.0, 0.01};
  cov = incrementCovariance(odometry, 4.0, noise);
  EXPECT_NEAR(cov(0, 1), 0.5, kTolerance);
  EXPECT_NEAR(cov(2, 2), 0.01, kTolerance);
  // One that claims 2 cm for a 5 m step is raised to the floor, its correlation kept:
  // forward and lateral each scaled by 0.5 / 0.02 = 25, so the covariance 2e-4 becomes 0.125.
  odometry.covariance = {4e-4, 2e-4, 0.0, 2e-4, 4e-4, 0.0, 0.0, 0.0, 1.0};
  cov = incrementCovariance(odometry, 4.0, noise);
  EXPECT_NEAR(cov(0, 0), 0.25, 1e-12);
  EXPECT_NEAR(cov(0, 1), 0.125, 1e-12);
  EXPECT_NEAR(cov(2, 2), 1.0, kTolerance);
  noise.use_reported_covariance = false;
  EXPECT_NEAR(incrementCovariance(odometry, 4.0, noise)(2, 2), 4e-4, kTolerance);
}

}  // namespace
}  // namespace estimation
}  // namespace roam
