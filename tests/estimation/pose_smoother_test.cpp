// The pose chain's RTS smoother: a hand-worked standing-still case, exact agreement with
// conditioning the joint Gaussian of a linearised two-pose chain on a later measurement, headings
// differenced across +-pi, the `first` cut and a clear error on mismatched sizes.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include <Eigen/Dense>

#include "roam/estimation/motion_model.hpp"
#include "roam/estimation/pose_smoother.hpp"

namespace roam {
namespace estimation {
namespace {

constexpr double kSmootherTolerance = 1e-12;

TEST(PoseSmoother, StandingStillHalvesTheInnovation) {
  // Increment 0: F = G = I, P_{1|0} = P0 + Q = 2 I, C = P0 P_{1|0}^-1 = I / 2.
  // m_{0|N} = 0 + (2, -4, 0.2) / 2 = (1, -2, 0.1); P_{0|N} = 1 + (0.5 - 2) / 4 = 0.625.
  std::vector<PoseGaussian> filtered(2);
  filtered[0].covariance = Eigen::Matrix3d::Identity();
  filtered[1].mean = Eigen::Vector3d(2.0, -4.0, 0.2);
  filtered[1].covariance = 0.5 * Eigen::Matrix3d::Identity();
  std::vector<PoseTransition> transitions(1);
  transitions[0].increment_covariance = Eigen::Matrix3d::Identity();
  const std::vector<PoseGaussian> smoothed = smoothPoseChain(filtered, transitions);
  ASSERT_EQ(smoothed.size(), 2u);
  EXPECT_NEAR(smoothed[0].mean[0], 1.0, kSmootherTolerance);
  EXPECT_NEAR(smoothed[0].mean[1], -2.0, kSmootherTolerance);
  EXPECT_NEAR(smoothed[0].mean[2], 0.1, kSmootherTolerance);
  EXPECT_TRUE(smoothed[0].covariance.isApprox(0.625 * Eigen::Matrix3d::Identity(), kSmootherTolerance));
  EXPECT_TRUE(smoothed[1].mean.isApprox(filtered[1].mean, kSmootherTolerance));  // the last pose is its own
}

TEST(PoseSmoother, UsesTheFiltersOwnPrediction) {
  // As above, but the filter predicted (1, 0, 0) rather than step(m0, 0) = 0: the innovation is
  // (2, -4, 0.2) - (1, 0, 0), so m_{0|N} = (1, -4, 0.2) / 2 = (0.5, -2, 0.1).
  std::vector<PoseGaussian> filtered(2);
  filtered[0].covariance = Eigen::Matrix3d::Identity();
  filtered[1].mean = Eigen::Vector3d(2.0, -4.0, 0.2);
  filtered[1].covariance = 0.5 * Eigen::Matrix3d::Identity();
  std::vector<PoseTransition> transitions(1);
  transitions[0].increment_covariance = Eigen::Matrix3d::Identity();
  transitions[0].has_predicted_mean = true;
  transitions[0].predicted_mean = Eigen::Vector3d(1.0, 0.0, 0.0);
  const std::vector<PoseGaussian> smoothed = smoothPoseChain(filtered, transitions);
  EXPECT_NEAR(smoothed[0].mean[0], 0.5, kSmootherTolerance);
  EXPECT_NEAR(smoothed[0].mean[1], -2.0, kSmootherTolerance);
  EXPECT_NEAR(smoothed[0].mean[2], 0.1, kSmootherTolerance);
}

TEST(PoseSmoother, EqualsConditioningTheJointGaussian) {
  // x0 ~ N(m0, P0); x1 = step(x0, q + e) linearised: x1 = f(m0) + F (x0 - m0) + G e; z = x1 + v,
  // v ~ N(0, R). The filter at 1 is the Kalman update of the prediction on z; the smoother must
  // give E[x0 | z] and Cov[x0 | z] of the joint Gaussian.
  const Eigen::Vector3d m0(1.0, 2.0, 0.7), q(3.0, 0.5, -0.2);
  Eigen::Matrix3d p0;
  p0 << 0.5, 0.1, 0.02, 0.1, 0.3, -0.01, 0.02, -0.01, 0.01;
  const Eigen::Matrix3d qn = Eigen::Vector3d(0.04, 0.01, 0.001).asDiagonal();
  const Eigen::Matrix3d r = Eigen::Vector3d(0.2, 0.3, 0.05).asDiagonal();
  const Eigen::Vector3d z(3.4, 4.9, 0.45);
  Odometry odometry;
  odometry.forward_m = q[0];
  odometry.lateral_m = q[1];
  odometry.delta_heading_rad = q[2];
  const StepJacobians j = stepJacobians(m0, odometry, 0.0);
  const Eigen::Vector3d m1_pred = step(m0, q);
  const Eigen::Matrix3d p1_pred = j.wrt_pose * p0 * j.wrt_pose.transpose() + j.wrt_increment * qn * j.wrt_increment.transpose();
  const Eigen::Matrix3d cross = p0 * j.wrt_pose.transpose();  // Cov(x0, x1)
  const Eigen::Matrix3d s_inv = (p1_pred + r).inverse();
  std::vector<PoseGaussian> filtered(2);
  filtered[0].mean = m0;
  filtered[0].covariance = p0;
  filtered[1].mean = m1_pred + p1_pred * s_inv * (z - m1_pred);
  filtered[1].covariance = p1_pred - p1_pred * s_inv * p1_pred;
  std::vector<PoseTransition> transitions(1);
  transitions[0].increment = q;
  transitions[0].increment_covariance = qn;
  const std::vector<PoseGaussian> smoothed = smoothPoseChain(filtered, transitions);
  const Eigen::Vector3d expected_mean = m0 + cross * s_inv * (z - m1_pred);
  const Eigen::Matrix3d expected_covariance = p0 - cross * s_inv * cross.transpose();
  EXPECT_LT((smoothed[0].mean - expected_mean).norm(), 1e-10);
  EXPECT_LT((smoothed[0].covariance - expected_covariance).norm(), 1e-10);
}

TEST(PoseSmoother, HeadingsAreDifferencedOnTheCircle) {
  // Standing still at heading pi - 0.1, the next filtered heading -pi + 0.1 is 0.2 rad further
  // on, not 2 pi - 0.2 back: with C = I / 2 the smoothed heading is pi - 0.1 + 0.1 = pi.
  std::vector<PoseGaussian> filtered(2);
  filtered[0].mean[2] = M_PI - 0.1;
  filtered[0].covariance = Eigen::Matrix3d::Identity();
  filtered[1].mean[2] = -M_PI + 0.1;
  filtered[1].covariance = Eigen::Matrix3d::Identity();
  std::vector<PoseTransition> transitions(1);
  transitions[0].increment_covariance = Eigen::Matrix3d::Identity();
  const std::vector<PoseGaussian> smoothed = smoothPoseChain(filtered, transitions);
  EXPECT_NEAR(std::abs(smoothed[0].mean[2]), M_PI, 1e-12);
}

TEST(PoseSmoother, StopsAtFirstAndChecksSizes) {
  std::vector<PoseGaussian> filtered(3);
  for (PoseGaussian& pose : filtered) pose.covariance = Eigen::Matrix3d::Identity();
  filtered[2].mean = Eigen::Vector3d(4.0, 0.0, 0.0);
  std::vector<PoseTransition> transitions(2);
  for (PoseTransition& t : transitions) t.increment_covariance = Eigen::Matrix3d::Identity();
  const std::vector<PoseGaussian> smoothed = smoothPoseChain(filtered, transitions, 1);
  EXPECT_NEAR(smoothed[1].mean[0], 2.0, kSmootherTolerance);  // C = I / 2
  EXPECT_NEAR(smoothed[0].mean[0], 0.0, kSmootherTolerance);  // before `first`: as filtered
  transitions.pop_back();
  EXPECT_THROW(smoothPoseChain(filtered, transitions), std::invalid_argument);
}

}  // namespace
}  // namespace estimation
}  // namespace roam
