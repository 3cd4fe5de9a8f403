#include "thin_svd.hpp"

#include <cmath>
#include <stdexcept>

namespace roam {

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

}  // namespace roam
