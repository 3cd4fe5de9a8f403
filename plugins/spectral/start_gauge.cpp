#include "start_gauge.hpp"

#include <algorithm>
#include <cmath>

namespace roam::spectral {
namespace {

constexpr double kPi = 3.14159265358979323846;
// Chunks beyond this many are not used: by then dead reckoning's heading variance is far above
// the early chunks' and they carry no weight (bounds the dense solve at 200^3 / 3 flops).
constexpr int kMaxChunks = 200;

}  // namespace

StartGauge fitStartGauge(const OdometryPath& path, const std::vector<int>& poses,
                         const Eigen::Matrix2Xd& shape_m, double chunk_s, const GaugeNoise& noise) {
  StartGauge out;
  const int C = static_cast<int>(poses.size());
  if (C < 3 || path.size() < 2) return out;
  // Heading variance accumulated from the start pose to each pose.
  std::vector<double> variance(path.size(), 0.0);
  for (int k = 0; k + 1 < path.size(); ++k) {
    double step = estimation::wheelHeadingVariance_rad2(path.step_m[k], path.turn_rad[k], noise);
    if (path.odometry[k].hasCovariance()) step = std::max(step, path.odometry[k].covariance[8]);
    variance[k + 1] = variance[k] + step;
  }
  // Per chunk: rotation of the learned path onto dead reckoning, spread, heading variance.
  std::vector<double> y, spread, heading_var;
  double residual_m2 = 0.0;
  std::vector<double> own_k2;  // each chunk's own scatter (per axis, m^2)
  int residual_points = 0;
  const int64_t chunk_us = std::max<int64_t>(1, static_cast<int64_t>(std::llround(chunk_s * 1e6)));
  for (int begin = 0; begin < C && static_cast<int>(y.size()) < kMaxChunks;) {
    int end = begin;
    while (end < C && path.utime[poses[end]] < path.utime[poses[begin]] + chunk_us) ++end;
    const int n = end - begin;
    if (n >= 3) {
      Eigen::Matrix2Xd a = shape_m.middleCols(begin, n);
      Eigen::Matrix2Xd b(2, n);
      double v = 0.0;
      for (int j = 0; j < n; ++j) {
        const int k = poses[begin + j];
        b.col(j) << path.x_m[k], path.y_m[k];
        v += variance[k] / n;
      }
      a = a.colwise() - a.rowwise().mean();
      b = b.colwise() - b.rowwise().mean();
      const double cross = (a.row(0).array() * b.row(1).array() - a.row(1).array() * b.row(0).array()).sum();
      const double dot = (a.array() * b.array()).sum();
      const double s = a.squaredNorm() / n;  // mean squared radius
      if (s > 0.0 && (cross != 0.0 || dot != 0.0)) {
        const double chunk_residual_m2 = std::max(0.0, b.squaredNorm() - (cross * cross + dot * dot) / a.squaredNorm());
        residual_m2 += chunk_residual_m2;
        residual_points += n;
        own_k2.push_back(chunk_residual_m2 / (2.0 * n));
        double angle = std::atan2(cross, dot);
        if (!y.empty()) angle = y.back() + std::remainder(angle - y.back(), 2.0 * kPi);  // unwrap
        y.push_back(angle);
        spread.push_back(s);
        heading_var.push_back(v);
      }
    }
    begin = end;
  }
  const int M = static_cast<int>(y.size());
  if (M == 0) return out;
  // k^2: the learned path's scatter about dead reckoning after each chunk's own rotation (per
  // axis, at least 1 cm). Its errors are smooth within a chunk, so a chunk's rotation error is
  // about k / its RMS radius (not k / sqrt(n) / radius, which would hold for independent errors).
  const double k2 = std::max(1e-4, residual_points > 0 ? residual_m2 / (2.0 * residual_points) : 0.0);
  // Chunks whose rotation the learned path's noise leaves undetermined (a robot standing still, a
  // few decimetres of spread: sigma above kMaxChunkSigma_rad, where the angle stops being Gaussian)
  // are left out.
  constexpr double kMaxChunkSigma_rad = 0.25;
  std::vector<int> kept;
  for (int c = 0; c < M; ++c)
    if (std::max(k2, own_k2[c]) / spread[c] < kMaxChunkSigma_rad * kMaxChunkSigma_rad) kept.push_back(c);
  const int K = static_cast<int>(kept.size());
  if (K == 0) return out;
  Eigen::VectorXd yk(K), noise_var(K);
  for (int i = 0; i < K; ++i) {
    yk(i) = y[kept[i]];
    noise_var(i) = std::max(k2, own_k2[kept[i]]) / spread[kept[i]];
  }
  // Robust GLS: a chunk the learned path got wrong (an edge of the solved region, a window the
  // ranges bent) would pull the intercept, and the early ones weigh most. Iteratively reweighted:
  // each chunk's own error n_c = D C^-1 (y - alpha 1) (D = its noise variances), standardised by its
  // sigma, gets Tukey's biweight (c = 4.685, 95 % efficiency on Gaussian noise).
  constexpr double kTukey = 4.685;
  constexpr int kIterations = 5;
  Eigen::VectorXd weight = Eigen::VectorXd::Ones(K);
  Eigen::VectorXd w;
  double information = 0.0, alpha = 0.0;
  for (int iteration = 0; iteration < kIterations; ++iteration) {
    Eigen::MatrixXd cov(K, K);
    for (int a = 0; a < K; ++a)
      for (int b = 0; b < K; ++b) cov(a, b) = heading_var[kept[std::min(a, b)]];
    for (int a = 0; a < K; ++a) cov(a, a) += noise_var(a) / std::max(weight(a), 1e-6);
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(cov);
    w = ldlt.solve(Eigen::VectorXd::Ones(K));
    information = w.sum();
    if (!(information > 0.0)) return out;
    alpha = w.dot(yk) / information;
    const Eigen::VectorXd n = (noise_var.array() / weight.array().max(1e-6)).matrix().asDiagonal() *
                              ldlt.solve((yk.array() - alpha).matrix());
    for (int a = 0; a < K; ++a) {
      const double u = n(a) / (kTukey * std::sqrt(noise_var(a)));
      weight(a) = std::abs(u) < 1.0 ? (1.0 - u * u) * (1.0 - u * u) : 0.0;
    }
  }
  out.rotation_rad = alpha;
  out.rotation_sigma_rad = 1.0 / std::sqrt(information);
  out.shape_noise = std::sqrt(k2);
  out.chunks = static_cast<int>((weight.array() > 0.0).count());
  return out;
}

}  // namespace roam::spectral
