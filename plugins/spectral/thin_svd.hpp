// Top-k thin SVD of a short, wide matrix Y (rows = N or 2N beacons, T columns), Eq. 12.
//
// Y Y^T = U diag(sigma^2) U^T: the Gram matrix of the rows (O(rows^2 T)) and a small symmetric
// eigen-decomposition give the left singular vectors; the weighted right factor is
// diag(sigma) V^T = U^T Y (O(rows k T)). No SVD of the wide matrix is formed.
#pragma once

#include <Eigen/Dense>

namespace roam::spectral {

struct LeftSvd {
  Eigen::MatrixXd U;               // rows x k, orthonormal columns, singular values descending
  Eigen::VectorXd singular_values; // k
};

// k <= Y.rows(). The sign of each column of U is fixed (largest-magnitude entry positive) so
// results repeat bit for bit.
LeftSvd topLeftSvd(const Eigen::MatrixXd& Y, int k);

// Same from a precomputed Gram matrix Y Y^T.
LeftSvd topLeftSvdFromGram(const Eigen::MatrixXd& gram, int k);

// The rank-k reconstruction U (U^T Y), one column at a time: the inner dimensions are only k and
// rows, where a blocked GEMM spends its time packing, zeroing and allocating temporaries.
Eigen::MatrixXd lowRankProjection(const Eigen::MatrixXd& U, const Eigen::MatrixXd& Y);
// The norm of each column's residual off span(U), |y_j - U U^T y_j|, without forming U U^T Y.
Eigen::VectorXd residualNorms(const Eigen::MatrixXd& U, const Eigen::MatrixXd& Y);

}  // namespace roam::spectral
