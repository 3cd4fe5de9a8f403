#include "multilateration.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>
#include <Eigen/LU>

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

namespace {

// Gauss-Newton on the ranges flagged in `use`, from m.
Eigen::Vector2d refine(const std::vector<Eigen::Vector2d>& positions_m, const std::vector<double>& ranges_m,
                       const std::vector<bool>& use, Eigen::Vector2d m) {
  constexpr int kIterations = 10;
  for (int it = 0; it < kIterations; ++it) {
    Eigen::Matrix2d h = Eigen::Matrix2d::Zero();
    Eigen::Vector2d g = Eigen::Vector2d::Zero();
    for (size_t k = 0; k < positions_m.size(); ++k) {
      if (!use[k]) continue;
      const Eigen::Vector2d d = m - positions_m[k];
      const double distance_m = std::max(d.norm(), 1e-6);
      const Eigen::Vector2d j = d / distance_m;
      h += j * j.transpose();
      g += j * (ranges_m[k] - distance_m);
    }
    const Eigen::Vector2d step = h.ldlt().solve(g);
    if (!step.allFinite()) break;
    m += step;
    if (step.norm() < 1e-9) break;
  }
  return m;
}

}  // namespace

std::optional<Eigen::Vector2d> multilaterate(const std::vector<Eigen::Vector2d>& positions_m,
                                             const std::vector<double>& ranges_m, double min_spread_m,
                                             double inlier_threshold_m) {
  const int n = static_cast<int>(positions_m.size());
  if (n < 3 || static_cast<int>(ranges_m.size()) != n) return std::nullopt;
  if (positionSpread(positions_m) < min_spread_m) return std::nullopt;
  if (inlier_threshold_m > 0.0) {
    // Consensus over every triple (deterministic): the exact 3-range solution (linear in
    // (m_x, m_y, |m|^2)) refined on its inliers; the one with the most inliers (then the
    // smallest inlier residual) wins.
    std::optional<Eigen::Vector2d> best;
    int best_count = 0;
    double best_cost = 0.0;
    std::vector<bool> use(n);
    for (int a = 0; a < n; ++a)
      for (int b = a + 1; b < n; ++b)
        for (int c = b + 1; c < n; ++c) {
          Eigen::Matrix3d lhs;
          Eigen::Vector3d rhs;
          const int idx[3] = {a, b, c};
          for (int r = 0; r < 3; ++r) {
            lhs.row(r) << 2.0 * positions_m[idx[r]].x(), 2.0 * positions_m[idx[r]].y(), -1.0;
            rhs[r] = positions_m[idx[r]].squaredNorm() - ranges_m[idx[r]] * ranges_m[idx[r]];
          }
          const Eigen::FullPivLU<Eigen::Matrix3d> lu(lhs);
          if (!lu.isInvertible()) continue;
          Eigen::Vector2d m = lu.solve(rhs).head<2>();
          if (!m.allFinite()) continue;
          for (int pass = 0; pass < 2; ++pass) {
            for (int k = 0; k < n; ++k)
              use[k] = std::abs((m - positions_m[k]).norm() - ranges_m[k]) < inlier_threshold_m;
            if (std::count(use.begin(), use.end(), true) < 3) break;
            m = refine(positions_m, ranges_m, use, m);
          }
          int count = 0;
          double cost = 0.0;
          for (int k = 0; k < n; ++k) {
            const double e = (m - positions_m[k]).norm() - ranges_m[k];
            if (std::abs(e) < inlier_threshold_m) {
              ++count;
              cost += e * e;
            }
          }
          if (m.allFinite() && count >= 3 && (count > best_count || (count == best_count && cost < best_cost))) {
            best = m;
            best_count = count;
            best_cost = cost;
          }
        }
    return best;
  }
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
