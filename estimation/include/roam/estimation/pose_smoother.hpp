// Rauch-Tung-Striebel smoothing of a chain of SE(2) poses driven by the shared motion model.
//
// Model: x_{k+1} = step(x_k, q_k + e_k), e_k ~ N(0, Q_k) (q_k the calibrated increment of step k,
// Q_k its covariance; motion_model.hpp), and a Gaussian summary N(m_k, P_k) of the filter's
// posterior after each step's update (for a particle filter: the weighted mean and covariance
// of its cloud). Linearised at the filtered mean (estimation::stepJacobians):
//   predict:  m_{k+1|k} = step(m_k, q_k),  P_{k+1|k} = F_k P_k F_k' + G_k Q_k G_k',
//   backward: C_k = P_k F_k' P_{k+1|k}^-1,
//             m_{k|N} = m_k + C_k (m_{k+1|N} - m_{k+1|k}),
//             P_{k|N} = P_k + C_k (P_{k+1|N} - P_{k+1|k}) C_k',
// with F_k = d step / d pose, G_k = d step / d increment, headings differenced on the circle.
// The last pose is its own smoothed pose. Every range after pose k reaches it through the
// filtered poses after it: the filter's own updates are not re-done, only carried backwards.
#pragma once

#include <vector>

#include <Eigen/Core>

namespace roam {
namespace estimation {

struct PoseGaussian {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();  // (x_m, y_m, heading_rad)
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
};

struct PoseTransition {
  Eigen::Vector3d increment = Eigen::Vector3d::Zero();  // calibrated (u_c, v_c, w_c), robot frame
  Eigen::Matrix3d increment_covariance = Eigen::Matrix3d::Zero();
  // The filter's own prediction m_{k+1|k}, where it has one that is not step(m_k, q_k): a particle
  // cloud's mean moves less than its mean pose's step where the headings spread (E cos th =
  // cos E th exp(-var / 2)), and that difference, taken for an innovation, would pile up
  // backwards over every step without a range.
  bool has_predicted_mean = false;
  Eigen::Vector3d predicted_mean = Eigen::Vector3d::Zero();
};

// filtered: N poses; transitions: N - 1 (transitions[k] takes pose k to pose k + 1). Poses
// before `first` are returned as filtered (the backward pass stops there). Returned headings are
// wrapped to (-pi, pi]. Throws std::invalid_argument if the sizes do not match.
std::vector<PoseGaussian> smoothPoseChain(const std::vector<PoseGaussian>& filtered,
                                          const std::vector<PoseTransition>& transitions, size_t first = 0);

}  // namespace estimation
}  // namespace roam
