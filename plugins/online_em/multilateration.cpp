#include "multilateration.hpp"

#include <cmath>

#include <Eigen/Dense>

namespace roam {

double positionSpread(const std::vector<Eigen::Vector2d>& positions_m) {
  if (positions_m.size() < 2) return 0.0;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& p : positions_m) mean += p;
  mean /= static_cast<double>(positions_m.size());
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();
  for (const auto& p : positions_m) covariance += (p - mean) * (p - mean).transpose();
  covariance /= static_cast<double>(positions_m.size());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(covariance);
  return std::sqrt(std::max(eigen.eigenvalues()[0], 0.0));
}

std::optional<Eigen::Vector2d> multilaterate(const std::vector<Eigen::Vector2d>& positions_m,
                                             const std::vector<double>& ranges_m, double min_spread_m) {
  const int n = static_cast<int>(positions_m.size());
  if (n < 3 || static_cast<int>(ranges_m.size()) != n) return std::nullopt;
  if (positionSpread(positions_m) < min_spread_m) return std::nullopt;
  Eigen::MatrixXd a(n, 3);
  Eigen::VectorXd b(n);
  for (int j = 0; j < n; ++j) {
    a.row(j) << 2.0 * positions_m[j].x(), 2.0 * positions_m[j].y(), -1.0;
    b[j] = positions_m[j].squaredNorm() - ranges_m[j] * ranges_m[j];
  }
  Eigen::Vector2d m = a.colPivHouseholderQr().solve(b).head<2>();
  constexpr int kIterations = 10;
  for (int it = 0; it < kIterations; ++it) {
    Eigen::MatrixXd j(n, 2);
    Eigen::VectorXd e(n);
    for (int k = 0; k < n; ++k) {
      const Eigen::Vector2d d = m - positions_m[k];
      const double distance_m = std::max(d.norm(), 1e-6);
      j.row(k) = d.transpose() / distance_m;
      e[k] = ranges_m[k] - distance_m;
    }
    const Eigen::Vector2d step = (j.transpose() * j).ldlt().solve(j.transpose() * e);
    m += step;
    if (step.norm() < 1e-9) break;
  }
  if (!m.allFinite()) return std::nullopt;
  return m;
}

}  // namespace roam
