#include "roam/estimation/multilateration.hpp"
#include "roam/estimation/range_model.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdint>

#include <optional>

namespace roam {
namespace estimation {
namespace {


// The whitened range residual e = (|m - p| - r) / sigma.
double whitenedResidual(const std::array<double, 2>& position_m, double range_m, double sigma_m,
                        const Eigen::Vector2d& m) {
  return (std::hypot(m.x() - position_m[0], m.y() - position_m[1]) - range_m) / sigma_m;
}

// sum_i rho(e_i^2) / 2 with the Cauchy loss at scale c.
double cauchyCost(const std::vector<std::array<double, 2>>& positions_m, const std::vector<double>& ranges_m,
                  double sigma_m, double c, const Eigen::Vector2d& m) {
  double cost = 0.0;
  for (size_t i = 0; i < positions_m.size(); ++i) {
    const double e = whitenedResidual(positions_m[i], ranges_m[i], sigma_m, m);
    cost += 0.5 * c * c * std::log1p(e * e / (c * c));
  }
  return cost;
}

// Minimises cauchyCost over m from *m by Newton's method with step halving, so every accepted
// step lowers the cost. Per range, with u = (m - p_i) / d_i, e_i = (d_i - r_i) / sigma,
// s = e_i^2, rho' = 1 / (1 + s / c^2) and rho'' = -rho'^2 / c^2:
//   gradient  sum_i rho' e_i u / sigma,
//   Hessian   sum_i (rho' + 2 rho'' s) u u^T / sigma^2 + rho' e_i (I - u u^T) / (d_i sigma).
// Where an outlier's negative curvature leaves the Hessian indefinite, the Gauss-Newton matrix
// with the Cauchy weights (sum_i rho' u u^T / sigma^2, what Ceres uses for a loss with
// rho'' <= 0) takes its place; that is a descent direction too, but converges only linearly
// (~40 iterations on a Plaza-sized beacon against ~5). A 2-parameter problem: a Ceres solve per
// call cost more in set-up and Jacobian bookkeeping than in arithmetic, and spectral_batch's
// heading-rate bias scan makes ~100 of them. False if the cost or the step is not finite.
bool minimiseCauchy(const std::vector<std::array<double, 2>>& positions_m, const std::vector<double>& ranges_m,
                    double sigma_m, double c, Eigen::Vector2d* m) {
  constexpr int kMaxIterations = 100;
  constexpr int kMaxHalvings = 40;
  double cost = cauchyCost(positions_m, ranges_m, sigma_m, c, *m);
  if (!std::isfinite(cost)) return false;
  for (int iteration = 0; iteration < kMaxIterations; ++iteration) {
    Eigen::Matrix2d newton = Eigen::Matrix2d::Zero(), gauss_newton = Eigen::Matrix2d::Zero();
    Eigen::Vector2d g = Eigen::Vector2d::Zero();
    for (size_t i = 0; i < positions_m.size(); ++i) {
      const Eigen::Vector2d d = *m - Eigen::Vector2d(positions_m[i][0], positions_m[i][1]);
      const double distance_m = std::max(d.norm(), 1e-9);
      const Eigen::Vector2d u = d / distance_m;
      const double e = (distance_m - ranges_m[i]) / sigma_m;
      const double rho1 = cauchyWeight(e, c);
      const double rho2 = -rho1 * rho1 / (c * c);
      const Eigen::Matrix2d uu = u * u.transpose();
      gauss_newton += rho1 / (sigma_m * sigma_m) * uu;
      newton += (rho1 + 2.0 * rho2 * e * e) / (sigma_m * sigma_m) * uu +
                rho1 * e / (distance_m * sigma_m) * (Eigen::Matrix2d::Identity() - uu);
      g += rho1 * e / sigma_m * u;
    }
    const Eigen::LDLT<Eigen::Matrix2d> newton_ldlt(newton);
    const bool positive = newton_ldlt.info() == Eigen::Success && newton_ldlt.isPositive() &&
                          (newton_ldlt.vectorD().array() > 0.0).all();
    const Eigen::Vector2d step =
        positive ? Eigen::Vector2d(-newton_ldlt.solve(g)) : Eigen::Vector2d(-gauss_newton.ldlt().solve(g));
    if (!step.allFinite()) return false;
    double t = 1.0;
    bool progressing = false;  // a lower cost, by more than rounding, at a step above rounding
    for (int halving = 0; halving < kMaxHalvings; ++halving, t *= 0.5) {
      const Eigen::Vector2d trial = *m + t * step;
      const double trial_cost = cauchyCost(positions_m, ranges_m, sigma_m, c, trial);
      if (trial_cost < cost) {
        const double decrease = cost - trial_cost;
        *m = trial;
        cost = trial_cost;
        progressing = decrease > 1e-12 * cost && t * step.norm() > 1e-10 * (1.0 + m->norm());
        break;
      }
    }
    if (!progressing) break;
  }
  return m->allFinite();
}

// Consensus: Gauss-Newton on the ranges flagged in `use`, from m.
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

double positionSpread(const std::vector<std::array<double, 2>>& positions_m) {
  if (positions_m.size() < 2) return 0.0;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& p : positions_m) mean += Eigen::Vector2d(p[0], p[1]);
  mean /= static_cast<double>(positions_m.size());
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();
  for (const auto& p : positions_m) {
    const Eigen::Vector2d d = Eigen::Vector2d(p[0], p[1]) - mean;
    covariance += d * d.transpose();
  }
  covariance /= static_cast<double>(positions_m.size());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(covariance);
  return std::sqrt(std::max(eigen.eigenvalues()[0], 0.0));
}

bool multilaterateLinear(const std::vector<std::array<double, 2>>& positions_m,
                         const std::vector<double>& ranges_m, std::array<double, 2>* beacon_m) {
  const Eigen::Index n = static_cast<Eigen::Index>(positions_m.size());
  if (n < 3 || ranges_m.size() != positions_m.size()) return false;
  Eigen::Vector2d centre_m = Eigen::Vector2d::Zero();
  for (const auto& p : positions_m) centre_m += Eigen::Vector2d(p[0], p[1]);
  centre_m /= static_cast<double>(n);
  Eigen::MatrixXd a(n, 3);
  Eigen::VectorXd b(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector2d p_m = Eigen::Vector2d(positions_m[i][0], positions_m[i][1]) - centre_m;
    a.row(i) << -2.0 * p_m.x(), -2.0 * p_m.y(), 1.0;
    b(i) = ranges_m[i] * ranges_m[i] - p_m.squaredNorm();
  }
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a);
  qr.setThreshold(1e-9);
  if (qr.rank() < 3) return false;
  const Eigen::Vector3d u = qr.solve(b);
  (*beacon_m)[0] = u.x() + centre_m.x();
  (*beacon_m)[1] = u.y() + centre_m.y();
  return std::isfinite((*beacon_m)[0]) && std::isfinite((*beacon_m)[1]);
}

bool multilaterateRobust(const std::vector<std::array<double, 2>>& positions_m,
                         const std::vector<double>& ranges_m, double sigma_m,
                         RobustMultilateration* result) {
  if (!(sigma_m > 0.0)) return false;
  std::array<double, 2> linear{0.0, 0.0};
  if (!multilaterateLinear(positions_m, ranges_m, &linear)) return false;
  Eigen::Vector2d beacon(linear[0], linear[1]);
  for (const double factor : {16.0, 4.0, 1.0})
    if (!minimiseCauchy(positions_m, ranges_m, sigma_m, kCauchy95 * factor, &beacon)) return false;
  result->beacon_m = {beacon.x(), beacon.y()};
  result->cost = cauchyCost(positions_m, ranges_m, sigma_m, kCauchy95, beacon);
  result->inliers = 0;
  for (size_t i = 0; i < positions_m.size(); ++i)
    if (std::abs(whitenedResidual(positions_m[i], ranges_m[i], sigma_m, beacon)) <= 3.0 * kCauchy95)
      ++result->inliers;
  return beacon.allFinite();
}

namespace {

// The (up to two) intersections of circles (a, ra) and (b, rb); where they miss, the point on
// the line a-b between the circles (one candidate).
int circleIntersections(const Eigen::Vector2d& a, double ra, const Eigen::Vector2d& b, double rb,
                        Eigen::Vector2d out[2]) {
  const Eigen::Vector2d ab = b - a;
  const double d = ab.norm();
  if (!(d > 1e-9)) return 0;
  const Eigen::Vector2d u = ab / d;
  const double along = (d * d + ra * ra - rb * rb) / (2.0 * d);
  const double h2 = ra * ra - along * along;
  if (h2 <= 0.0) {
    // Disjoint or nested: the point along the line between the two circles' nearest points.
    const double ta = (d >= ra + rb) ? ra : (ra > rb ? ra : -ra);
    const double tb = (d >= ra + rb) ? d - rb : (ra > rb ? d + rb : d - rb);
    out[0] = a + 0.5 * (ta + tb) * u;
    return 1;
  }
  const double h = std::sqrt(h2);
  const Eigen::Vector2d n(-u.y(), u.x());
  out[0] = a + along * u + h * n;
  out[1] = a + along * u - h * n;
  return 2;
}

struct Score {
  int inliers = 0;
  double cost = 0.0;
};

Score scoreCandidate(const Eigen::Vector2d& c, const std::vector<std::array<double, 2>>& p,
                     const std::vector<double>& r, const std::vector<double>& tol) {
  Score s;
  for (size_t i = 0; i < p.size(); ++i) {
    const double e = std::hypot(c.x() - p[i][0], c.y() - p[i][1]) - r[i];
    if (std::abs(e) <= tol[i]) {
      ++s.inliers;
      s.cost += (e * e) / (tol[i] * tol[i]);
    }
  }
  return s;
}

// Gauss-Newton on the ranges within tolerance of c (weights 1 / tol^2), a few iterations.
Eigen::Vector2d refine(Eigen::Vector2d c, const std::vector<std::array<double, 2>>& p,
                       const std::vector<double>& r, const std::vector<double>& tol) {
  for (int iteration = 0; iteration < 10; ++iteration) {
    Eigen::Matrix2d A = Eigen::Matrix2d::Zero();
    Eigen::Vector2d g = Eigen::Vector2d::Zero();
    for (size_t i = 0; i < p.size(); ++i) {
      const Eigen::Vector2d diff = c - Eigen::Vector2d(p[i][0], p[i][1]);
      const double dist = diff.norm();
      if (!(dist > 1e-9)) continue;
      const double e = dist - r[i];
      if (std::abs(e) > tol[i]) continue;
      const Eigen::Vector2d J = diff / dist;
      const double w = 1.0 / (tol[i] * tol[i]);
      A += w * J * J.transpose();
      g += w * J * e;
    }
    if (std::abs(A.determinant()) < 1e-12 * (A.trace() * A.trace() + 1e-300)) break;
    const Eigen::Vector2d step = A.ldlt().solve(g);
    if (!step.allFinite()) break;
    c -= step;
    if (step.norm() < 1e-9) break;
  }
  return c;
}

// A fixed pseudo-random sequence (splitmix64), so runs that draw from it are bit-identical.
class FixedSequence {
 public:
  uint64_t next() {
    uint64_t z = (state_ += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  // An index in [0, n).
  template <typename Index>
  Index index(Index n) { return static_cast<Index>(next() % static_cast<uint64_t>(n)); }

 private:
  uint64_t state_ = 0x9e3779b97f4a7c15ULL;
};

}  // namespace

bool multilaterateConsensus(const std::vector<std::array<double, 2>>& positions_m,
                            const std::vector<double>& ranges_m, const std::vector<double>& tolerance_m,
                            ConsensusMultilateration* result, int max_pairs) {
  const size_t n = positions_m.size();
  if (n < 2 || ranges_m.size() != n || tolerance_m.size() != n) return false;
  const size_t all_pairs = n * (n - 1) / 2;
  const bool every_pair = all_pairs <= static_cast<size_t>(std::max(1, max_pairs));
  const size_t tries = every_pair ? all_pairs : static_cast<size_t>(max_pairs);
  Eigen::Vector2d best = Eigen::Vector2d::Zero();
  Score best_score;
  bool found = false;
  FixedSequence sequence;
  size_t i = 0, j = 1;
  for (size_t t = 0; t < tries; ++t) {
    if (every_pair) {
      if (t > 0 && ++j == n) j = ++i + 1;
    } else {
      i = sequence.index(n);
      j = sequence.index(n - 1);
      if (j >= i) ++j;
    }
    const Eigen::Vector2d a(positions_m[i][0], positions_m[i][1]), b(positions_m[j][0], positions_m[j][1]);
    Eigen::Vector2d candidates[2];
    const int k = circleIntersections(a, ranges_m[i], b, ranges_m[j], candidates);
    for (int c = 0; c < k; ++c) {
      const Score s = scoreCandidate(candidates[c], positions_m, ranges_m, tolerance_m);
      if (!found || s.inliers > best_score.inliers || (s.inliers == best_score.inliers && s.cost < best_score.cost)) {
        best = candidates[c];
        best_score = s;
        found = true;
      }
    }
  }
  if (!found) return false;
  for (int round = 0; round < 2; ++round) {
    const Eigen::Vector2d refined = refine(best, positions_m, ranges_m, tolerance_m);
    const Score s = scoreCandidate(refined, positions_m, ranges_m, tolerance_m);
    if (s.inliers < best_score.inliers) break;
    best = refined;
    best_score = s;
  }
  result->point_m = {best.x(), best.y()};
  result->inlier.assign(n, false);
  result->inliers = 0;
  for (size_t m = 0; m < n; ++m) {
    const double e = std::hypot(best.x() - positions_m[m][0], best.y() - positions_m[m][1]) - ranges_m[m];
    result->inlier[m] = std::abs(e) <= tolerance_m[m];
    result->inliers += result->inlier[m] ? 1 : 0;
  }
  return std::isfinite(best.x()) && std::isfinite(best.y());
}

bool multilaterateTriples(const std::vector<std::array<double, 2>>& positions,
                          const std::vector<double>& ranges_m, double inlier_threshold_m,
                          std::array<double, 2>* beacon_m, int max_triples) {
  const int n = static_cast<int>(positions.size());
  if (n < 3 || static_cast<int>(ranges_m.size()) != n || !(inlier_threshold_m > 0.0)) return false;
  std::vector<Eigen::Vector2d> positions_m;
  for (const auto& p : positions) positions_m.emplace_back(p[0], p[1]);
  // Consensus over the triples (deterministic): the exact 3-range solution (linear in
  // (m_x, m_y, |m|^2)) refined on its inliers; the one with the most inliers (then the smallest
  // inlier residual) wins. Every triple while there are at most max_triples, else max_triples
  // drawn by the fixed sequence multilaterateConsensus draws its pairs by: every triple, each scored
  // and refined over all n ranges, took 17 s for one landmark of ~170 ranges (50 Hz odometry,
  // 10 Hz ranges, a 60 m first lane).
  const int64_t all_triples = static_cast<int64_t>(n) * (n - 1) * (n - 2) / 6;
  const bool every_triple = all_triples <= std::max<int64_t>(1, max_triples);
  const int64_t tries = every_triple ? all_triples : max_triples;
  FixedSequence sequence;
  std::optional<Eigen::Vector2d> best;
  int best_count = 0;
  double best_cost = 0.0;
  std::vector<bool> use(n);
  int a = 0, b = 1, c = 1;
  for (int64_t t = 0; t < tries; ++t) {
    if (every_triple) {  // the next a < b < c in lexicographic order, from (0, 1, 2)
      if (++c == n) {
        if (++b == n - 1) b = ++a + 1;
        c = b + 1;
      }
    } else {  // three distinct indices
      a = sequence.index(n);
      do b = sequence.index(n); while (b == a);
      do c = sequence.index(n); while (c == a || c == b);
    }
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
      for (int k = 0; k < n; ++k) use[k] = std::abs((m - positions_m[k]).norm() - ranges_m[k]) < inlier_threshold_m;
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
  if (!best) return false;
  (*beacon_m)[0] = best->x();
  (*beacon_m)[1] = best->y();
  return true;
}

}  // namespace estimation
}  // namespace roam
