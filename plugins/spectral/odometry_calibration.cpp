#include "odometry_calibration.hpp"

#include "roam/estimation/median.hpp"
#include "roam/estimation/range_model.hpp"

#include <algorithm>
#include <cmath>

namespace roam::spectral {
namespace {

struct Chunk {
  double t_s = 0.0;        // mean time from the path's start
  double angle_rad = 0.0;  // rotation taking dead reckoning onto the learned path
  double matched = 0.0;    // |sum b . R a| (learned . rotated dead reckoning)
  double spread = 0.0;     // sum |a|^2 (dead reckoning): the chunk's weight
};

std::vector<Chunk> chunkFits(const OdometryPath& path, const std::vector<int>& poses,
                             const Eigen::Matrix2Xd& xy_m, double chunk_s) {
  constexpr int kMinPoses = 3;
  constexpr double kMinSpread_m2 = 1.0;  // a chunk whose poses span under ~1 m holds no direction
  const int C = static_cast<int>(poses.size());
  const int64_t chunk_us = static_cast<int64_t>(std::llround(chunk_s * 1e6));
  std::vector<Chunk> chunks;
  for (int begin = 0; begin < C;) {
    int end = begin;
    while (end < C && path.utime[poses[end]] < path.utime[poses[begin]] + chunk_us) ++end;
    const int n = end - begin;
    if (n >= kMinPoses) {
      Eigen::Vector2d mean_a = Eigen::Vector2d::Zero(), mean_b = Eigen::Vector2d::Zero();
      double mean_t = 0.0;
      for (int j = begin; j < end; ++j) {
        mean_a += Eigen::Vector2d(path.x_m[poses[j]], path.y_m[poses[j]]);
        mean_b += xy_m.col(j);
        mean_t += static_cast<double>(path.utime[poses[j]] - path.utime.front()) * 1e-6;
      }
      mean_a /= n;
      mean_b /= n;
      double cross = 0.0, dot = 0.0, spread = 0.0;
      for (int j = begin; j < end; ++j) {
        const Eigen::Vector2d a = Eigen::Vector2d(path.x_m[poses[j]], path.y_m[poses[j]]) - mean_a;
        const Eigen::Vector2d b = xy_m.col(j) - mean_b;
        cross += a.x() * b.y() - a.y() * b.x();
        dot += a.dot(b);
        spread += a.squaredNorm();
      }
      if (spread > kMinSpread_m2)
        chunks.push_back({mean_t / n, std::atan2(cross, dot), std::hypot(cross, dot), spread});
    }
    begin = end;
  }
  for (size_t c = 1; c < chunks.size(); ++c)  // unwrap along the path
    chunks[c].angle_rad = chunks[c - 1].angle_rad + wrapAngle(chunks[c].angle_rad - chunks[c - 1].angle_rad);
  return chunks;
}

// Continuous piecewise-linear phi(t) with knots at i * segment (i = 0..M): the hat-function
// weights of time t.
struct Hat {
  int i = 0;
  double f = 0.0;  // phi(t) = (1 - f) c_i + f c_{i+1}
};
Hat hatAt(double t_s, double segment_s, int M) {
  const double x = std::clamp(t_s / segment_s, 0.0, static_cast<double>(M));
  Hat h;
  h.i = std::min(static_cast<int>(x), M - 1);
  h.f = x - h.i;
  return h;
}

}  // namespace

CalibrationFit fitOdometryCalibration(const OdometryPath& path, const std::vector<int>& poses,
                                      const Eigen::Matrix2Xd& xy_m, bool metric, double chunk_s,
                                      double segment_s) {
  constexpr int kMinChunks = 3;
  constexpr int kMinChunksPerSegment = 4;  // a rate from fewer rotations is mostly noise
  constexpr int kIterations = 10;
  CalibrationFit out;
  out.distance_scale = path.calibration.distance_scale;
  const std::vector<Chunk> chunks = chunkFits(path, poses, xy_m, chunk_s);
  const int K = static_cast<int>(chunks.size());
  if (K < kMinChunks) return out;
  const double duration_s = static_cast<double>(path.utime.back() - path.utime.front()) * 1e-6;
  if (!(duration_s > 0.0)) return out;
  const int M = std::max(1, std::min(static_cast<int>(std::ceil(duration_s / segment_s)), K / kMinChunksPerSegment));
  const double knot_s = duration_s / M;

  // IRLS: weighted least squares for the knot values c, a tiny second-difference penalty so that
  // a segment with no chunks is interpolated linearly; Tukey weights on normalised residuals.
  std::vector<double> robust(K, 1.0);
  Eigen::VectorXd c = Eigen::VectorXd::Zero(M + 1);
  for (int iteration = 0; iteration < kIterations; ++iteration) {
    Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(M + 1, M + 1);
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(M + 1);
    for (int k = 0; k < K; ++k) {
      const Hat h = hatAt(chunks[k].t_s, knot_s, M);
      const double w = chunks[k].spread * robust[k];
      const Eigen::Vector2d phi(1.0 - h.f, h.f);
      normal.block<2, 2>(h.i, h.i) += w * phi * phi.transpose();
      rhs.segment<2>(h.i) += w * phi * chunks[k].angle_rad;
    }
    const double penalty = 1e-9 * normal.trace();
    for (int i = 1; i < M; ++i) {
      const Eigen::Vector3d d(1.0, -2.0, 1.0);
      normal.block<3, 3>(i - 1, i - 1) += penalty * d * d.transpose();
    }
    const Eigen::LDLT<Eigen::MatrixXd> solver(normal);
    if (solver.info() != Eigen::Success) return out;
    c = solver.solve(rhs);
    if (!c.allFinite()) return out;
    std::vector<double> normalised(K), abs_normalised(K);
    for (int k = 0; k < K; ++k) {
      const Hat h = hatAt(chunks[k].t_s, knot_s, M);
      const double fitted = (1.0 - h.f) * c(h.i) + h.f * c(h.i + 1);
      normalised[k] = (chunks[k].angle_rad - fitted) * std::sqrt(chunks[k].spread);
      abs_normalised[k] = std::abs(normalised[k]);
    }
    const double scale = std::max(1.4826 * estimation::upperMedian(abs_normalised), 1e-12);
    double change = 0.0;
    for (int k = 0; k < K; ++k) {
      const double u = normalised[k] / (estimation::kTukey95 * scale);
      const double w = std::abs(u) < 1.0 ? (1.0 - u * u) * (1.0 - u * u) : 0.0;
      change = std::max(change, std::abs(w - robust[k]));
      robust[k] = w;
    }
    if (change < 1e-6) break;
  }

  // One constant rate through the kept chunks (reported), and the scale ratio.
  double sw = 0.0, st = 0.0, sa = 0.0, matched = 0.0, spread = 0.0;
  int used = 0;
  for (int k = 0; k < K; ++k) {
    if (robust[k] <= 0.0) continue;
    const double w = chunks[k].spread * robust[k];
    sw += w;
    st += w * chunks[k].t_s;
    sa += w * chunks[k].angle_rad;
    matched += robust[k] * chunks[k].matched;
    spread += robust[k] * chunks[k].spread;
    ++used;
  }
  if (used < kMinChunks || !(sw > 0.0)) return out;
  const double t_mean = st / sw, a_mean = sa / sw;
  double stt = 0.0, sta = 0.0;
  for (int k = 0; k < K; ++k) {
    const double w = chunks[k].spread * robust[k];
    stt += w * (chunks[k].t_s - t_mean) * (chunks[k].t_s - t_mean);
    sta += w * (chunks[k].t_s - t_mean) * (chunks[k].angle_rad - a_mean);
  }
  if (!(stt > 0.0)) return out;
  const double slope = sta / stt;
  double residual_sq = 0.0;
  for (int k = 0; k < K; ++k) {
    const double e = chunks[k].angle_rad - a_mean - slope * (chunks[k].t_s - t_mean);
    residual_sq += chunks[k].spread * robust[k] * e * e;
  }
  const double before_bias_rad_s = path.meanHeadingBias();
  out.bias_rad_s = before_bias_rad_s - slope;
  out.bias_sigma_rad_s = used > 2 ? std::sqrt(residual_sq / (used - 2) / stt) : 0.0;
  if (metric) out.distance_scale = path.calibration.distance_scale * matched / spread;
  // Per step: phi falls by the remaining bias, so each segment's rate is subtracted from it.
  const int steps = path.size() - 1;
  out.step_bias_rad_s.resize(steps);
  for (int k = 0; k < steps; ++k) {
    const double t_s = 0.5 * static_cast<double>(path.utime[k] + path.utime[k + 1] - 2 * path.utime.front()) * 1e-6;
    const Hat h = hatAt(t_s, knot_s, M);
    out.step_bias_rad_s[k] = path.stepHeadingBias(k) - (c(h.i + 1) - c(h.i)) / knot_s;
  }
  out.chunks = used;
  return out;
}

}  // namespace roam::spectral
