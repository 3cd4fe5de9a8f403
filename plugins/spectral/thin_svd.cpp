#include "thin_svd.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace roam::spectral {

LeftSvd topLeftSvdFromGram(const Eigen::MatrixXd& gram, int k) {
  if (k < 1 || k > gram.rows()) throw std::invalid_argument("topLeftSvd: k out of range");
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(gram);
  const int rows = static_cast<int>(gram.rows());
  LeftSvd out;
  out.U.resize(rows, k);
  out.singular_values.resize(k);
  for (int i = 0; i < k; ++i) {
    const int j = rows - 1 - i;  // eigenvalues ascending
    Eigen::VectorXd column = eigen.eigenvectors().col(j);
    Eigen::Index largest;
    column.cwiseAbs().maxCoeff(&largest);
    if (column(largest) < 0.0) column = -column;
    out.U.col(i) = column;
    out.singular_values(i) = std::sqrt(std::max(0.0, eigen.eigenvalues()(j)));
  }
  return out;
}

LeftSvd topLeftSvd(const Eigen::MatrixXd& Y, int k) {
  Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(Y.rows(), Y.rows());
  gram.selfadjointView<Eigen::Lower>().rankUpdate(Y);
  gram.triangularView<Eigen::StrictlyUpper>() = gram.transpose();
  return topLeftSvdFromGram(gram, k);
}

namespace {
// Columns per block of U (U^T Y): big enough for the matrix products to run at speed, small
// enough that the block's temporaries stay in cache and no T-sized temporary is allocated.
constexpr Eigen::Index kBlockColumns = 256;
}  // namespace

Eigen::MatrixXd lowRankProjection(const Eigen::MatrixXd& U, const Eigen::MatrixXd& Y) {
  Eigen::MatrixXd out(Y.rows(), Y.cols());
  Eigen::MatrixXd coefficients(U.cols(), kBlockColumns);
  for (Eigen::Index j = 0; j < Y.cols(); j += kBlockColumns) {
    const Eigen::Index width = std::min(kBlockColumns, Y.cols() - j);
    coefficients.leftCols(width).noalias() = U.transpose() * Y.middleCols(j, width);
    out.middleCols(j, width).noalias() = U * coefficients.leftCols(width);
  }
  return out;
}

Eigen::VectorXd residualNorms(const Eigen::MatrixXd& U, const Eigen::MatrixXd& Y) {
  Eigen::VectorXd out(Y.cols());
  Eigen::MatrixXd coefficients(U.cols(), kBlockColumns), residual(Y.rows(), kBlockColumns);
  for (Eigen::Index j = 0; j < Y.cols(); j += kBlockColumns) {
    const Eigen::Index width = std::min(kBlockColumns, Y.cols() - j);
    coefficients.leftCols(width).noalias() = U.transpose() * Y.middleCols(j, width);
    residual.leftCols(width) = Y.middleCols(j, width);
    residual.leftCols(width).noalias() -= U * coefficients.leftCols(width);
    out.segment(j, width) = residual.leftCols(width).colwise().norm().transpose();
  }
  return out;
}

}  // namespace roam::spectral
