#include "incremental_svd.hpp"

#include <algorithm>
#include <cmath>

namespace roam::spectral {

void IncrementalSvd::reset(int rows, int rank) {
  rows_ = rows;
  max_rank_ = rank;
  U_.resize(rows, 0);
  singular_values_.resize(0);
}

void IncrementalSvd::addColumns(const Eigen::MatrixXd& B) {
  if (B.cols() == 0) return;
  const int k = rank();
  const Eigen::MatrixXd m = U_.transpose() * B;  // k x b
  const Eigen::MatrixXd residual = B - U_ * m;    // rows x b
  // Orthonormal basis J of the residual's column space (rank-revealing QR; at most rows - k).
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(residual);
  const double scale = std::max(residual.cwiseAbs().maxCoeff(), B.cwiseAbs().maxCoeff());
  qr.setThreshold(1e-12);
  int r = scale > 0.0 ? static_cast<int>(qr.rank()) : 0;
  r = std::min(r, rows_ - k);
  Eigen::MatrixXd J = Eigen::MatrixXd(qr.householderQ()).leftCols(r);
  // Re-orthogonalise J against U (the QR ignores U) and get K = J^T residual.
  if (r > 0 && k > 0) J -= U_ * (U_.transpose() * J);
  if (r > 0) {
    Eigen::HouseholderQR<Eigen::MatrixXd> qr2(J);
    J = Eigen::MatrixXd(qr2.householderQ()).leftCols(r);
  }
  const Eigen::MatrixXd K = J.transpose() * residual;  // r x b
  // Middle matrix M = [[diag(s), m], [0, K]], (k + r) x (k + b).
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(k + r, k + B.cols());
  M.topLeftCorner(k, k) = singular_values_.asDiagonal();
  M.topRightCorner(k, B.cols()) = m;
  M.bottomRightCorner(r, B.cols()) = K;
  // Left singular vectors of M from its (small) Gram matrix.
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(M * M.transpose());
  const int keep = std::min(max_rank_, k + r);
  Eigen::MatrixXd basis(rows_, k + r);
  basis << U_, J;
  Eigen::MatrixXd U_new(rows_, keep);
  Eigen::VectorXd s_new(keep);
  for (int i = 0; i < keep; ++i) {
    const int j = k + r - 1 - i;  // eigenvalues ascending
    Eigen::VectorXd column = basis * eigen.eigenvectors().col(j);
    Eigen::Index largest;
    column.cwiseAbs().maxCoeff(&largest);
    if (column(largest) < 0.0) column = -column;
    U_new.col(i) = column;
    s_new(i) = std::sqrt(std::max(0.0, eigen.eigenvalues()(j)));
  }
  U_ = U_new;
  singular_values_ = s_new;
}

}  // namespace roam::spectral
