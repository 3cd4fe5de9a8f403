#include "metric_upgrade.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/Geometry>

namespace roam::spectral {
namespace {

// Real roots of c0 + c1 s + c2 s^2 + c3 s^3.
std::vector<double> realRoots(double c0, double c1, double c2, double c3) {
  std::vector<double> roots;
  const double magnitude = std::max({std::abs(c0), std::abs(c1), std::abs(c2), std::abs(c3)});
  if (magnitude == 0.0) return roots;
  if (std::abs(c3) > 1e-12 * magnitude) {
    Eigen::Matrix3d companion = Eigen::Matrix3d::Zero();
    companion(1, 0) = 1.0;
    companion(2, 1) = 1.0;
    companion(0, 2) = -c0 / c3;
    companion(1, 2) = -c1 / c3;
    companion(2, 2) = -c2 / c3;
    Eigen::EigenSolver<Eigen::Matrix3d> solver(companion, false);
    for (int i = 0; i < 3; ++i) {
      const std::complex<double> root = solver.eigenvalues()(i);
      if (std::abs(root.imag()) <= 1e-9 * (1.0 + std::abs(root.real()))) roots.push_back(root.real());
    }
  } else if (std::abs(c2) > 1e-12 * magnitude) {
    const double disc = c1 * c1 - 4.0 * c2 * c0;
    if (disc >= 0.0) {
      roots.push_back((-c1 + std::sqrt(disc)) / (2.0 * c2));
      roots.push_back((-c1 - std::sqrt(disc)) / (2.0 * c2));
    }
  } else if (c1 != 0.0) {
    roots.push_back(-c0 / c1);
  }
  return roots;
}

}  // namespace

BeaconUpgrade upgradeWithBeacons(const Eigen::MatrixXd& half_sq,
                                 const std::vector<std::optional<Eigen::Vector2d>>& surveyed) {
  std::vector<int> known;
  for (int n = 0; n < static_cast<int>(surveyed.size()); ++n)
    if (surveyed[n]) known.push_back(n);
  if (known.size() < 4)
    throw std::runtime_error("anchor = beacons needs >= 4 surveyed beacons that were ranged, got " +
                             std::to_string(known.size()));
  const int K = static_cast<int>(known.size());
  const Eigen::Index T = half_sq.cols();
  Eigen::MatrixXd C_rest(K, 3);  // [m_x, m_y, 1]
  Eigen::VectorXd C_first(K);     // |m|^2/2
  Eigen::MatrixXd H_known(K, T);
  for (int i = 0; i < K; ++i) {
    const Eigen::Vector2d& m = *surveyed[known[i]];
    C_rest.row(i) << m.x(), m.y(), 1.0;
    C_first(i) = 0.5 * m.squaredNorm();
    H_known.row(i) = half_sq.row(known[i]);
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(C_rest, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::Vector3d sv = svd.singularValues();
  if (!(sv(2) > 1e-6 * sv(0)))
    throw std::runtime_error("anchor = beacons: the surveyed beacons are collinear");
  // X[1:3](s) = P - s Q.
  const Eigen::MatrixXd P = svd.solve(H_known);
  const Eigen::Vector3d Q = svd.solve(C_first);

  // r_t(s) = s X3 - (X1^2 + X2^2)/2 = alpha_t + beta_t s + gamma s^2.
  const Eigen::ArrayXd p0 = P.row(0).transpose().array(), p1 = P.row(1).transpose().array(),
                       p2 = P.row(2).transpose().array();
  const Eigen::ArrayXd alpha = -0.5 * (p0.square() + p1.square());
  const Eigen::ArrayXd beta = p2 + p0 * Q(0) + p1 * Q(1);
  const double gamma = -Q(2) - 0.5 * (Q(0) * Q(0) + Q(1) * Q(1));
  // d/ds sum r^2 / 2 = sum (alpha + beta s + gamma s^2)(beta + 2 gamma s).
  const double c0 = (alpha * beta).sum();
  const double c1 = (2.0 * gamma * alpha + beta.square()).sum();
  const double c2 = 3.0 * gamma * beta.sum();
  const double c3 = 2.0 * gamma * gamma * static_cast<double>(T);
  auto cost = [&](double s) { return (alpha + beta * s + gamma * s * s).square().sum(); };
  double best_s = 1.0, best_cost = std::numeric_limits<double>::infinity();
  for (double s : realRoots(c0, c1, c2, c3)) {
    if (!(s > 0.0)) continue;
    const double c = cost(s);
    if (c < best_cost) {
      best_cost = c;
      best_s = s;
    }
  }
  // No positive root: the learned states fit no metric map through the surveyed beacons. That is
  // the data (windows that outliers bent: half the ranges NLOS), not the estimator, so it is a
  // refusal, and a longer window is tried first (spectral_solver.cpp), as for the start pose.
  if (!std::isfinite(best_cost))
    throw InsufficientData(
        "anchor = beacons: no positive state scale fits the surveyed beacons (the learned states do not fit "
        "the ranges: outliers, or too few ranges per window)");

  BeaconUpgrade out;
  out.state_scale = best_s;
  out.xy_m.resize(2, T);
  out.xy_m.row(0) = -(P.row(0).array() - best_s * Q(0)) / best_s;
  out.xy_m.row(1) = -(P.row(1).array() - best_s * Q(1)) / best_s;
  return out;
}

std::vector<Eigen::Matrix2Xd> pathCandidatesUpToSimilarity(const Eigen::MatrixXd& half_sq) {
  const Eigen::Index N = half_sq.rows(), T = half_sq.cols();
  if (N < 4) throw InsufficientData("anchor = start_pose needs >= 4 beacons");
  if (T < 10) throw InsufficientData("anchor = start_pose needs >= 10 poses with ranges");
  // A basis W (4 x T) of the row space.
  Eigen::MatrixXd W(4, T);
  if (N == 4) {
    W = half_sq;
  } else {
    Eigen::MatrixXd gram = half_sq * half_sq.transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(gram);
    W = eigen.eigenvectors().rightCols(4).transpose() * half_sq;
  }
  // t0: t0^T W = 1^T in the least-squares sense.
  const Eigen::Vector4d t0 =
      W.transpose().colPivHouseholderQr().solve(Eigen::VectorXd::Ones(T));
  // Orthonormal complement of t0.
  Eigen::HouseholderQR<Eigen::Vector4d> qr(t0);
  const Eigen::Matrix4d basis = qr.householderQ();
  const Eigen::Matrix<double, 3, Eigen::Dynamic> z = basis.rightCols(3).transpose() * W;
  const Eigen::Vector3d mean = z.rowwise().mean();
  const Eigen::Matrix<double, 3, Eigen::Dynamic> centred = z.colwise() - mean;
  const double spread = std::sqrt(centred.squaredNorm() / static_cast<double>(T));
  if (!(spread > 0.0)) throw InsufficientData("anchor = start_pose: the robot did not move");
  const Eigen::Matrix<double, 3, Eigen::Dynamic> zn = centred / spread;

  // Quadric through the points: monomials [z1^2, z2^2, z3^2, 2z1z2, 2z1z3, 2z2z3, z1, z2, z3, 1].
  Eigen::Matrix<double, Eigen::Dynamic, 10> D(T, 10);
  D.col(0) = zn.row(0).array().square().transpose();
  D.col(1) = zn.row(1).array().square().transpose();
  D.col(2) = zn.row(2).array().square().transpose();
  D.col(3) = (2.0 * zn.row(0).array() * zn.row(1).array()).transpose();
  D.col(4) = (2.0 * zn.row(0).array() * zn.row(2).array()).transpose();
  D.col(5) = (2.0 * zn.row(1).array() * zn.row(2).array()).transpose();
  D.col(6) = zn.row(0).transpose();
  D.col(7) = zn.row(1).transpose();
  D.col(8) = zn.row(2).transpose();
  D.col(9).setOnes();
  // Dynamic size (10 x 10 at run time): a fixed-size solver's unrolled templates took 30 s of this
  // file's compile time.
  Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(10, 10);
  gram.selfadjointView<Eigen::Lower>().rankUpdate(D.transpose());
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> quadric(
      gram.selfadjointView<Eigen::Lower>());
  if (!(quadric.eigenvalues()(1) > 1e-9 * quadric.eigenvalues()(9)))
    throw InsufficientData(
        "anchor = start_pose: the path does not fix the metric upgrade (a straight or degenerate path)");
  auto quadraticPart = [](const Eigen::Matrix<double, 10, 1>& q) {
    Eigen::Matrix3d Qm;
    Qm << q(0), q(3), q(4), q(3), q(1), q(5), q(4), q(5), q(2);
    return Qm;
  };
  // The path up to a similarity from a quadric whose quadratic part has two positive eigenvalues
  // (a paraboloid); empty if it has not.
  std::vector<Eigen::Matrix2Xd> out;
  auto addShape = [&](const Eigen::Matrix<double, 10, 1>& q) {
    Eigen::Matrix3d Qm = quadraticPart(q);
    if (Qm.trace() < 0.0) Qm = -Qm;
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> rank2(Qm);
    const double l1 = rank2.eigenvalues()(2), l2 = rank2.eigenvalues()(1);
    if (!(l2 > 0.0)) return;
    Eigen::Matrix<double, 2, 3> R;
    R.row(0) = std::sqrt(2.0 * l1) * rank2.eigenvectors().col(2).transpose();
    R.row(1) = std::sqrt(2.0 * l2) * rank2.eigenvectors().col(1).transpose();
    out.push_back(-R * zn);
  };
  // The least-squares quadric (smallest eigenvector) first.
  const Eigen::Matrix<double, 10, 1> qa = quadric.eigenvectors().col(0);
  addShape(qa);
  // A path on two circles (a figure-8) puts the lifted states on two plane sections of the
  // paraboloid, so a pencil of quadrics passes through them: the paraboloid plus multiples of the
  // pair of planes. Noise then mixes the two smallest eigenvectors, and the smallest alone is
  // not a paraboloid (or a wrong one). The paraboloids of the pencil q_a + t q_b are where its
  // quadratic part is singular: det(Qa + t Qb) = 0, a cubic in t (and q_b itself, t = infinity).
  const Eigen::Matrix<double, 10, 1> qb = quadric.eigenvectors().col(1);
  const Eigen::Matrix3d Qa = quadraticPart(qa), Qb = quadraticPart(qb);
  auto det = [&](double t) { return (Qa + t * Qb).determinant(); };
  // Cubic through t = -1, 0, 1, 2 (exact).
  const double dm = det(-1.0), d0 = det(0.0), d1 = det(1.0), d2 = det(2.0);
  const double c0 = d0;
  const double c3 = (d2 - 3.0 * d1 + 3.0 * d0 - dm) / 6.0;
  const double c2 = 0.5 * (d1 + dm) - d0;
  const double c1 = d1 - d0 - c2 - c3;
  for (double t : realRoots(c0, c1, c2, c3)) addShape((qa + t * qb).normalized());
  addShape(qb);
  if (out.empty())
    throw InsufficientData(
        "anchor = start_pose: the path does not fix the metric upgrade (the learned quadric is not a "
        "paraboloid: poses on or near one circle?)");
  return out;
}

Eigen::Matrix2Xd pathUpToSimilarity(const Eigen::MatrixXd& half_sq) {
  return pathCandidatesUpToSimilarity(half_sq).front();
}

namespace {

// Sums over consecutive chunks of chunk_s of time (>= 3 poses each), both paths centred per
// chunk, for the shape as it is (f = 0) and reflected (f = 1): the residual after each chunk's
// own best rotation and scale, the matched terms |b . R a|, and the variances of shape and dead
// reckoning.
struct LocalShapeSums {
  double residual[2] = {0.0, 0.0};
  double matched[2] = {0.0, 0.0};
  double variance_shape = 0.0;
  double variance_dead_reckoned = 0.0;
};

LocalShapeSums localShapeSums(const Eigen::Matrix2Xd& shape, const Eigen::Matrix2Xd& dead_reckoned,
                              const std::vector<int64_t>& utime, double chunk_s) {
  const int C = static_cast<int>(shape.cols());
  const int64_t chunk_us = static_cast<int64_t>(std::llround(chunk_s * 1e6));
  LocalShapeSums sums;
  for (int begin = 0; begin < C;) {
    int end = begin;
    while (end < C && utime[end] < utime[begin] + chunk_us) ++end;
    if (end - begin >= 3) {
      const Eigen::Matrix2Xd a = shape.middleCols(begin, end - begin).colwise() -
                                 shape.middleCols(begin, end - begin).rowwise().mean();
      const Eigen::Matrix2Xd b = dead_reckoned.middleCols(begin, end - begin).colwise() -
                                 dead_reckoned.middleCols(begin, end - begin).rowwise().mean();
      const double var_a = a.squaredNorm(), var_b = b.squaredNorm();
      sums.variance_shape += var_a;
      sums.variance_dead_reckoned += var_b;
      for (int f = 0; f < 2; ++f) {
        const double flip = f == 0 ? 1.0 : -1.0;
        // a reflected is (a_x, flip a_y).
        const double cross = (a.row(0).array() * b.row(1).array() - flip * a.row(1).array() * b.row(0).array()).sum();
        const double dot = (a.row(0).array() * b.row(0).array() + flip * a.row(1).array() * b.row(1).array()).sum();
        const double m = std::hypot(cross, dot);
        sums.matched[f] += m;
        sums.residual[f] += var_b - (var_a > 0.0 ? m * m / var_a : 0.0);
      }
    }
    begin = end;
  }
  return sums;
}

}  // namespace

double localShapeMisfit(const Eigen::Matrix2Xd& shape, const Eigen::Matrix2Xd& dead_reckoned,
                        const std::vector<int64_t>& utime, double chunk_s) {
  const LocalShapeSums sums = localShapeSums(shape, dead_reckoned, utime, chunk_s);
  const double total = sums.variance_dead_reckoned;
  return total > 0.0 ? std::min(sums.residual[0], sums.residual[1]) / total : 0.0;
}

Eigen::Matrix2Xd Similarity::apply(const Eigen::Matrix2Xd& points) const {
  return (linear * points).colwise() + translation;
}

Similarity fitSimilarity(const Eigen::Matrix2Xd& src, const Eigen::Matrix2Xd& dst) {
  // 2-D Procrustes with scale (Umeyama 1991) in closed form, for a rotation and for a
  // reflection; the better fit wins.
  const Eigen::Vector2d src_mean = src.rowwise().mean(), dst_mean = dst.rowwise().mean();
  const Eigen::Matrix2Xd a = src.colwise() - src_mean, b = dst.colwise() - dst_mean;
  const double src_var = a.squaredNorm();
  Similarity best;
  double best_cost = std::numeric_limits<double>::infinity();
  for (double flip : {1.0, -1.0}) {
    const Eigen::Matrix2d reflect = Eigen::Vector2d(1.0, flip).asDiagonal();
    const Eigen::Matrix2Xd af = reflect * a;
    // Rotation angle maximising sum b . R af; scale = sum b . R af / sum |af|^2.
    const double cross = (af.row(0).array() * b.row(1).array() - af.row(1).array() * b.row(0).array()).sum();
    const double dot = (af.array() * b.array()).sum();
    const double angle = std::atan2(cross, dot);
    const double scale = src_var > 0.0 ? std::hypot(cross, dot) / src_var : 1.0;
    Similarity candidate;
    candidate.linear = scale * Eigen::Rotation2Dd(angle).toRotationMatrix() * reflect;
    candidate.translation = dst_mean - candidate.linear * src_mean;
    const double cost = (candidate.apply(src) - dst).squaredNorm();
    if (cost < best_cost) {
      best_cost = cost;
      best = candidate;
    }
  }
  return best;
}

Similarity alignToDeadReckoning(const Eigen::Matrix2Xd& shape, const Eigen::Matrix2Xd& dead_reckoned,
                                const std::vector<int64_t>& utime, const std::vector<double>& travelled_m,
                                double chunk_s, double align_m) {
  const int C = static_cast<int>(shape.cols());
  // Per reflection: residual after a local fit, |b . R a| terms; var(a).
  const LocalShapeSums sums = localShapeSums(shape, dead_reckoned, utime, chunk_s);
  const double* residual = sums.residual;
  const double* matched = sums.matched;
  const double variance = sums.variance_shape;
  const int f = residual[1] < residual[0] ? 1 : 0;
  const double scale = variance > 0.0 ? matched[f] / variance : 1.0;
  const Eigen::Matrix2d reflect = Eigen::Vector2d(1.0, f == 0 ? 1.0 : -1.0).asDiagonal();

  // Rotation and translation over the first align_m of travel, with that reflection and scale.
  int count = 0;
  while (count < C && travelled_m[count] <= align_m) ++count;
  count = std::max(count, std::min(C, 3));
  const Eigen::Matrix2Xd src = scale * reflect * shape.leftCols(count);
  const Eigen::Matrix2Xd dst = dead_reckoned.leftCols(count);
  const Eigen::Vector2d src_mean = src.rowwise().mean(), dst_mean = dst.rowwise().mean();
  const Eigen::Matrix2Xd a = src.colwise() - src_mean, b = dst.colwise() - dst_mean;
  const double cross = (a.row(0).array() * b.row(1).array() - a.row(1).array() * b.row(0).array()).sum();
  const double dot = (a.array() * b.array()).sum();
  Similarity out;
  const Eigen::Matrix2d rotation = Eigen::Rotation2Dd(std::atan2(cross, dot)).toRotationMatrix();
  out.linear = scale * rotation * reflect;
  out.translation = dst_mean - rotation * src_mean;
  return out;
}

Eigen::Matrix2Xd learnBeacons(const Eigen::MatrixXd& half_sq, const Eigen::Matrix2Xd& xy_m) {
  const Eigen::Index T = xy_m.cols();
  Eigen::MatrixX4d features(T, 4);
  features.col(0).setOnes();
  features.col(1) = -xy_m.row(0).transpose();
  features.col(2) = -xy_m.row(1).transpose();
  features.col(3) = 0.5 * xy_m.colwise().squaredNorm().transpose();
  const Eigen::ColPivHouseholderQR<Eigen::MatrixX4d> qr(features);
  Eigen::Matrix2Xd beacons(2, half_sq.rows());
  for (Eigen::Index n = 0; n < half_sq.rows(); ++n) {
    const Eigen::Vector4d theta = qr.solve(half_sq.row(n).transpose());
    beacons.col(n) = theta.segment<2>(1) / theta(3);
  }
  return beacons;
}

Eigen::VectorXd headingsFromRangeRates(const Eigen::MatrixXd& range_rate,
                                       const Eigen::Matrix2Xd& beacons_m) {
  const Eigen::Index N = beacons_m.cols();
  Eigen::MatrixXd C(N, 3);
  C.leftCols(2) = beacons_m.transpose();
  C.col(2).setOnes();
  // The least-squares solution is linear in the right-hand side: one N x N solve gives the 3 x N
  // pseudo-inverse, then one product covers every pose.
  const Eigen::MatrixXd pseudo_inverse =
      C.colPivHouseholderQr().solve(Eigen::MatrixXd::Identity(N, N));
  const Eigen::MatrixXd X = pseudo_inverse * range_rate;  // [-cos; -sin; p.u]
  Eigen::VectorXd heading(range_rate.cols());
  for (Eigen::Index t = 0; t < heading.size(); ++t) heading(t) = std::atan2(-X(1, t), -X(0, t));
  return heading;
}

}  // namespace roam::spectral
