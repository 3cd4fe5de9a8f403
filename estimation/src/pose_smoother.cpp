#include "roam/estimation/pose_smoother.hpp"

#include <cmath>
#include <stdexcept>

#include <Eigen/Dense>

#include "roam/estimation/motion_model.hpp"

namespace roam {
namespace estimation {

std::vector<PoseGaussian> smoothPoseChain(const std::vector<PoseGaussian>& filtered,
                                          const std::vector<PoseTransition>& transitions, size_t first) {
  if (!filtered.empty() && transitions.size() + 1 != filtered.size())
    throw std::invalid_argument("smoothPoseChain: transitions.size() must be filtered.size() - 1");
  std::vector<PoseGaussian> smoothed = filtered;
  for (PoseGaussian& pose : smoothed) pose.mean[2] = std::remainder(pose.mean[2], 2.0 * M_PI);
  if (filtered.size() < 2) return smoothed;
  for (size_t k = filtered.size() - 1; k-- > first;) {
    const PoseGaussian& now = filtered[k];
    const PoseTransition& t = transitions[k];
    // The shared Jacobians, for an odometry step that reports the calibrated increment itself.
    Odometry odometry;
    odometry.forward_m = t.increment[0];
    odometry.lateral_m = t.increment[1];
    odometry.delta_heading_rad = t.increment[2];
    const StepJacobians j = stepJacobians(now.mean, odometry, 0.0);
    const Eigen::Vector3d predicted = t.has_predicted_mean ? t.predicted_mean : step(now.mean, t.increment);
    const Eigen::Matrix3d predicted_covariance = j.wrt_pose * now.covariance * j.wrt_pose.transpose() +
                                                 j.wrt_increment * t.increment_covariance * j.wrt_increment.transpose();
    const Eigen::LDLT<Eigen::Matrix3d> ldlt(predicted_covariance);
    if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().array() > 0.0).all()) continue;  // no information
    // C' = P_{k+1|k}^-1 F P_k (both symmetric).
    const Eigen::Matrix3d gain = ldlt.solve(j.wrt_pose * now.covariance).transpose();
    Eigen::Vector3d innovation = smoothed[k + 1].mean - predicted;
    innovation[2] = std::remainder(innovation[2], 2.0 * M_PI);
    smoothed[k].mean = now.mean + gain * innovation;
    smoothed[k].mean[2] = std::remainder(smoothed[k].mean[2], 2.0 * M_PI);
    smoothed[k].covariance =
        now.covariance + gain * (smoothed[k + 1].covariance - predicted_covariance) * gain.transpose();
  }
  return smoothed;
}

}  // namespace estimation
}  // namespace roam
