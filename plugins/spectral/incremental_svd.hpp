// Incremental rank-k thin SVD (Brand, "Fast low-rank modifications of the thin singular value
// decomposition", Linear Algebra Appl. 2006), left factor only.
//
// Given Y ~ U diag(s) V^T (rank k) and new columns B: m = U^T B, the residual P = B - U m with
// orthonormal basis J (P = J K), and
//   [U diag(s), B] = [U, J] [[diag(s), m], [0, K]] (blockdiag(V, I))^T.
// The SVD of the small middle matrix M = U' diag(s') V'^T gives the new left factor [U, J] U',
// truncated to rank k. V is not kept: the states of any column y are diag(s) V^T y = U^T y.
// Without truncation loss (rank(Y) <= k) the result equals the batch SVD's left subspace.
#pragma once

#include <Eigen/Dense>

namespace roam::spectral {

class IncrementalSvd {
 public:
  IncrementalSvd() = default;
  IncrementalSvd(int rows, int rank) { reset(rows, rank); }
  void reset(int rows, int rank);

  void addColumns(const Eigen::MatrixXd& B);

  int rank() const { return static_cast<int>(singular_values_.size()); }
  const Eigen::MatrixXd& U() const { return U_; }  // rows x rank()
  const Eigen::VectorXd& singularValues() const { return singular_values_; }

 private:
  int rows_ = 0;
  int max_rank_ = 0;
  Eigen::MatrixXd U_;
  Eigen::VectorXd singular_values_;
};

}  // namespace roam::spectral
