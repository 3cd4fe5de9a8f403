// The residuals of the batch problem: values worked out by hand, and the automatic derivatives
// against central numeric differences (ceres::GradientChecker).
#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "batch_residuals.hpp"

namespace roam {
namespace spectral_batch {
namespace {

constexpr double kValueTolerance = 1e-12;
// Relative Jacobian error allowed between automatic and numeric (central) differences.
// Central differences with a relative step of 1e-6 are good to ~1e-5 relative on the range rows
// (truncation error of the curvature 1/r); a wrong derivative is off by O(1).
constexpr double kJacobianRelativeTolerance = 1e-4;

std::vector<double> evaluate(const ceres::CostFunction& cost, std::vector<const double*> blocks) {
  std::vector<double> residuals(cost.num_residuals());
  EXPECT_TRUE(cost.Evaluate(blocks.data(), residuals.data(), nullptr));
  return residuals;
}

TEST(BatchResiduals, OdometryValuesByHand) {
  // Pose a at the origin facing +y (heading pi/2); pose b at (-0.5, 2, pi/2 + 0.3).
  // In robot frame a the displacement (-0.5, 2) is (along, lateral) = (2, 0.5).
  // Measured d = 1.5, dtheta = 0.1; sigmas (0.5, 0.25, 0.1):
  //   r0 = (2 - 1.5) / 0.5 = 1,  r1 = 0.5 / 0.25 = 2,  r2 = (0.3 - 0.1) / 0.1 = 2.
  std::unique_ptr<ceres::CostFunction> cost(OdometryResidual::create(
      Eigen::Vector3d(1.5, 0.0, 0.1), 1.0, Eigen::Vector3d(1 / 0.5, 1 / 0.25, 1 / 0.1).asDiagonal()));
  const double a[3] = {0.0, 0.0, M_PI / 2};
  const double b[3] = {-0.5, 2.0, M_PI / 2 + 0.3};
  const double uncalibrated[2] = {1.0, 0.0};
  const std::vector<double> r = evaluate(*cost, {a, b, uncalibrated});
  EXPECT_NEAR(r[0], 1.0, kValueTolerance);
  EXPECT_NEAR(r[1], 2.0, kValueTolerance);
  EXPECT_NEAR(r[2], 2.0, kValueTolerance);
}

TEST(BatchResiduals, OdometryCalibrationAndLateral) {
  // Reported (u, v, w) = (1, 0.25, 0.2) over 0.2 s; distance scale 2 and heading-rate bias
  // 0.5 rad/s make it (2, 0.5, 0.1): b above is then the prediction exactly, but for its heading
  // (0.3 turned against 0.1): r = (0, 0, 0.2 / 0.1).
  std::unique_ptr<ceres::CostFunction> cost(OdometryResidual::create(
      Eigen::Vector3d(1.0, 0.25, 0.2), 0.2, Eigen::Vector3d(1 / 0.5, 1 / 0.25, 1 / 0.1).asDiagonal()));
  const double a[3] = {0.0, 0.0, M_PI / 2};
  const double b[3] = {-0.5, 2.0, M_PI / 2 + 0.3};
  const double calibration[2] = {2.0, 0.5};
  const std::vector<double> r = evaluate(*cost, {a, b, calibration});
  EXPECT_NEAR(r[0], 0.0, kValueTolerance);
  EXPECT_NEAR(r[1], 0.0, kValueTolerance);
  EXPECT_NEAR(r[2], 2.0, kValueTolerance);
}

TEST(BatchResiduals, HeadingErrorIsWrapped) {
  // b's heading is a full turn ahead of a + dtheta: the wrapped error is 0, not 2 pi.
  std::unique_ptr<ceres::CostFunction> cost(
      OdometryResidual::create(Eigen::Vector3d(0.0, 0.0, 0.2), 1.0, Eigen::Matrix3d::Identity()));
  const double a[3] = {0.0, 0.0, 3.0};
  const double b[3] = {0.0, 0.0, 3.0 + 0.2 + 2 * M_PI};
  const double uncalibrated[2] = {1.0, 0.0};
  EXPECT_NEAR(evaluate(*cost, {a, b, uncalibrated})[2], 0.0, kValueTolerance);
}

TEST(BatchResiduals, RangeValuesByHand) {
  // Robot at (1, 1), beacon at (4, 5): distance 5. Scale 1.1, offset 0.2 -> predicted 5.7;
  // measured 5.2, sigma 0.25 -> r = (5.7 - 5.2) / 0.25 = 2.
  std::unique_ptr<ceres::CostFunction> at_pose(RangeAtPoseResidual::create(5.2, 0.25));
  const double pose[3] = {1.0, 1.0, 0.7};
  const double beacon[2] = {4.0, 5.0};
  const double calibration[2] = {1.1, 0.2};
  const double no_offset[1] = {0.0};
  EXPECT_NEAR(evaluate(*at_pose, {pose, beacon, calibration, no_offset})[0], 2.0, kValueTolerance);

  // The same robot position as a quarter of the way from (0, 1) to (4, 1).
  std::unique_ptr<ceres::CostFunction> along(RangeAlongStepResidual::create(5.2, 0.25, 0.25));
  const double a[3] = {0.0, 1.0, 0.0};
  const double b[3] = {4.0, 1.0, 0.0};
  EXPECT_NEAR(evaluate(*along, {a, b, beacon, calibration, no_offset})[0], 2.0, kValueTolerance);
  // A per-beacon offset of -0.5 m cancels the error.
  const double beacon_offset[1] = {-0.5};
  EXPECT_NEAR(evaluate(*along, {a, b, beacon, calibration, beacon_offset})[0], 0.0, kValueTolerance);
}

// Checks a cost function's Jacobians at a point against central differences of its residuals.
// Written out rather than with ceres::GradientChecker: its ProbeResults holds Eigen matrices that
// the packaged libceres allocates and this file would free, and the two disagree on Eigen's
// aligned-allocation convention (AddressSanitizer reports the mismatched free).
void checkJacobians(const ceres::CostFunction& cost, std::vector<std::vector<double>> blocks) {
  constexpr double kRelativeStep = 1e-6;
  const int num_residuals = cost.num_residuals();
  const std::vector<int32_t>& sizes = cost.parameter_block_sizes();
  ASSERT_EQ(sizes.size(), blocks.size());
  std::vector<const double*> parameters;
  for (auto& block : blocks) parameters.push_back(block.data());
  std::vector<double> residuals(num_residuals);
  std::vector<std::vector<double>> jacobians(sizes.size());
  std::vector<double*> jacobian_pointers;
  for (size_t i = 0; i < sizes.size(); ++i) {
    jacobians[i].resize(static_cast<size_t>(num_residuals * sizes[i]));
    jacobian_pointers.push_back(jacobians[i].data());
  }
  ASSERT_TRUE(cost.Evaluate(parameters.data(), residuals.data(), jacobian_pointers.data()));
  std::vector<double> plus(num_residuals), minus(num_residuals);
  for (size_t i = 0; i < sizes.size(); ++i) {
    for (int j = 0; j < sizes[i]; ++j) {
      double& x = blocks[i][static_cast<size_t>(j)];
      const double x0 = x, h = kRelativeStep * std::max(1.0, std::abs(x0));
      x = x0 + h;
      ASSERT_TRUE(cost.Evaluate(parameters.data(), plus.data(), nullptr));
      x = x0 - h;
      ASSERT_TRUE(cost.Evaluate(parameters.data(), minus.data(), nullptr));
      x = x0;
      for (int r = 0; r < num_residuals; ++r) {
        const double numeric = (plus[r] - minus[r]) / (2.0 * h);
        const double analytic = jacobians[i][static_cast<size_t>(r * sizes[i] + j)];  // row-major
        EXPECT_NEAR(analytic, numeric, kJacobianRelativeTolerance * std::max(1.0, std::abs(numeric)))
            << "block " << i << ", parameter " << j << ", residual " << r;
      }
    }
  }
}

TEST(BatchResiduals, JacobiansMatchNumericDifferences) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> position_m(-20.0, 20.0);
  std::uniform_real_distribution<double> heading_rad(-3.0, 3.0);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    auto pose = [&] { return std::vector<double>{position_m(rng), position_m(rng), heading_rad(rng)}; };
    const std::vector<double> calibration{0.9 + 0.2 * unit(rng), unit(rng) - 0.5};
    // Pose b's heading within 1 rad of a's plus the turn: the wrapped heading error stays away
    // from its (deliberate) jump at +-pi, where numeric differences straddle the cut.
    const double turn_rad = unit(rng) - 0.5;
    Eigen::Matrix3d sqrt_information;
    sqrt_information << 100.0, 3.0, -1.0, 0.0, 50.0, 2.0, 0.0, 0.0, 200.0;
    std::unique_ptr<ceres::CostFunction> odometry(OdometryResidual::create(
        Eigen::Vector3d(unit(rng), unit(rng) - 0.5, turn_rad), unit(rng), sqrt_information));
    std::vector<double> a = pose();
    std::vector<double> b = pose();
    b[2] = a[2] + turn_rad + 2.0 * unit(rng) - 1.0;
    checkJacobians(*odometry, {a, b, {0.9 + 0.2 * unit(rng), 0.02 * (unit(rng) - 0.5)}});
    std::unique_ptr<ceres::CostFunction> at_pose(RangeAtPoseResidual::create(10.0 * unit(rng), 0.3));
    checkJacobians(*at_pose, {pose(), {position_m(rng), position_m(rng)}, calibration, {unit(rng) - 0.5}});
    std::unique_ptr<ceres::CostFunction> along(
        RangeAlongStepResidual::create(10.0 * unit(rng), 0.3, unit(rng)));
    checkJacobians(*along, {pose(), pose(), {position_m(rng), position_m(rng)}, calibration, {unit(rng) - 0.5}});
  }
}

}  // namespace
}  // namespace spectral_batch
}  // namespace roam
