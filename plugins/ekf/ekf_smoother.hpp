// Fixed-interval smoothing of the EKF's path (the modified Bryson-Frazier form of the
// Rauch-Tung-Striebel smoother).
//
// Model: the filter is a sequence of linear(ised) operations on its Gaussian (x, P):
//   predict:  x' = f(x), P' = F P F' + Q, where F is the identity but for the pose rows, which
//             are A (3 x n: the motion Jacobians over the pose and calibration columns);
//   update:   x+ = x- + K v, P+ = (I - K H) P-, with K = P- H' S^-1 (the gain actually used:
//             a Huber-weighted range is an update with its inflated R, so its K is optimal for
//             that R and the Joseph form equals (I - K H) P-);
//   augment:  states appended at the end (beacons), uncorrelated with the rest;
//   noise:    P += Q with x unchanged (bias release, starvation widening): nothing to undo;
//   remove:   a beacon's rows and columns dropped (x' = E x, E selecting the kept rows).
// The smoothed mean at any point of the sequence is x + P lambda, where the adjoint lambda
// (0 after the last operation) is carried backwards:
//   across an update:   lambda- = lambda+ + H' (S^-1 v - K' lambda+);
//   across a predict:   lambda  = F' lambda'  (only the pose part of lambda' is mixed, by A');
//   across an augment:  lambda is cut to the older, shorter state;
//   across a removal:   lambda = E' lambda' (zeros at the removed rows), Lambda = E' Lambda' E;
// and the smoothed covariance P - P Lambda P with
//   across an update:   Lambda- = H' S^-1 H + (I - K H)' Lambda+ (I - K H);
//   across a predict:   Lambda  = F' Lambda' F.
// This is the RTS answer (x_k|N = x_k|k + C_k (x_k+1|N - x_k+1|k)) without inverting P_k+1|k;
// it is exact for the linearised model the filter ran, i.e. the smoothed path uses every range,
// before and after each pose, through the same linearisation as the filter.
#pragma once

#include <vector>

#include <Eigen/Dense>

#include "roam/types.hpp"

namespace roam {
namespace ekf {

// One linear operation of the filter, as the backward pass needs it.
struct SmootherOperation {
  enum class Kind { kPredict, kUpdate, kRemove };
  Kind kind = Kind::kPredict;
  Eigen::MatrixXd A;          // predict: the pose rows of F (3 x n)
  Eigen::MatrixXd H;          // update: m x n
  Eigen::MatrixXd K;          // update: n x m
  Eigen::MatrixXd S_inverse;  // update: m x m
  Eigen::VectorXd y;          // update: S^-1 v (m)
  std::vector<int> kept;      // remove: the indices kept, in the state before
  int size_before = 0;        // remove: the state's size before
};

// The filter at one published pose, and the operations since the previous one.
struct SmootherNode {
  std::vector<SmootherOperation> before;  // from the previous node to this one, in order
  Eigen::Vector3d pose = Eigen::Vector3d::Zero();
  Eigen::MatrixXd pose_rows;  // P's pose rows (3 x n) at this node
};

// The smoothed path: path[k] (the filtered pose of nodes[k], same times) moved by the backward
// pass; trailing: operations after the last node (updates at the end of input). Headings are
// wrapped; each pose's covariance is its smoothed one. Poses before `first` (whose nodes were
// released to bound memory) are the filtered ones; those from `first` on are exactly what the
// whole pass gives (a pose's smoothed value depends only on the operations after it).
Path smoothPath(const Path& path, const std::vector<SmootherNode>& nodes,
                const std::vector<SmootherOperation>& trailing, size_t first = 0);

// Bytes a node holds (its matrices), for the memory bound.
size_t memoryBytes(const SmootherNode& node);

}  // namespace ekf
}  // namespace roam
