#include "gap_fill.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

namespace roam::spectral {
namespace {

// The calibrated path's scale error (start pose: the odometry's own; beacons: fitted), a few %.
constexpr double kScaleSigma = 0.05;
// Translation drift of the odometry per metre travelled that the heading and scale terms leave
// (wheel odometry, 2 % of the distance: roam-sim's --odo-distance-sigma-rel of the development runs).
constexpr double kTranslationSigmaPerDistance = 0.02;
// Floors of the stretch fits' stated errors: a fit of many nearly collinear points can report a
// residual far below what the solved positions are good to (~ the range noise).
constexpr double kMinPositionSigma_m = 0.1;
constexpr double kMinHeadingSigma_rad = 0.01;
// A side without a stretch fit: its heading offset is the solved pose's own, barely trusted.
constexpr double kNoFitHeadingSigma_rad = 1.0;
constexpr int kGaussNewtonIterations = 5;
// A solved pose beside a gap further than this many times the stretch's scatter from it, and
// further than kEdgeOutlierFloor_m, is filled: the window-edge failures are metres off (4-6 m on
// the development runs); 2 m, because a rigid fit of 15 s of dead reckoning extrapolated over the
// next 15 s is itself good to ~0.5 m, and a lower floor (1 m) also moved good lawn-mower edges.
constexpr double kEdgeOutlierSigmas = 4.0;
constexpr double kEdgeOutlierFloor_m = 2.0;

Eigen::Matrix2d rotation(double angle_rad) {
  const double c = std::cos(angle_rad), s = std::sin(angle_rad);
  Eigen::Matrix2d r;
  r << c, -s, s, c;
  return r;
}

Eigen::Vector2d deadReckoned(const OdometryPath& path, int k) { return {path.x_m[k], path.y_m[k]}; }
Eigen::Vector2d solvedAt(const Path& out, int k) { return {out[k].x_m, out[k].y_m}; }

// The contiguous solved poses from `edge` stepping by `direction` (-1: back, +1: forward) within
// stretch_us of it, nearest first.
std::vector<int> stretchPoses(const OdometryPath& path, const std::vector<bool>& solved, int edge, int direction,
                              int64_t stretch_us) {
  std::vector<int> poses;
  for (int k = edge; k >= 0 && k < path.size() && solved[k] &&
                     std::llabs(path.utime[k] - path.utime[edge]) <= stretch_us;
       k += direction)
    poses.push_back(k);
  return poses;
}

// Rotation fit (centred point sets, closed form in 2-D) of the solved poses poses[first, n) onto
// dead reckoning: solved - b_mean ~ R(angle_rad) (dead reckoning - a_mean).
struct RigidFit {
  Eigen::Vector2d a_mean = Eigen::Vector2d::Zero();  // dead reckoning's centroid
  Eigen::Vector2d b_mean = Eigen::Vector2d::Zero();  // the solved positions' centroid
  double cross = 0.0, dot = 0.0, spread_m2 = 0.0;    // the fit's sums (spread: of dead reckoning)
  double angle_rad = 0.0;                             // 0 when the fit is degenerate
  Eigen::Matrix2d r = Eigen::Matrix2d::Identity();    // rotation(angle_rad)
  bool degenerate() const { return cross == 0.0 && dot == 0.0; }
  Eigen::Vector2d residual(const OdometryPath& path, const Path& out, int k) const {
    return (solvedAt(out, k) - b_mean) - r * (deadReckoned(path, k) - a_mean);
  }
};

RigidFit fitRigid(const OdometryPath& path, const Path& out, const std::vector<int>& poses, int first) {
  RigidFit fit;
  const int n = static_cast<int>(poses.size());
  for (int i = first; i < n; ++i) {
    fit.a_mean += deadReckoned(path, poses[i]);
    fit.b_mean += solvedAt(out, poses[i]);
  }
  fit.a_mean /= (n - first);
  fit.b_mean /= (n - first);
  for (int i = first; i < n; ++i) {
    const Eigen::Vector2d a = deadReckoned(path, poses[i]) - fit.a_mean, b = solvedAt(out, poses[i]) - fit.b_mean;
    fit.cross += a.x() * b.y() - a.y() * b.x();
    fit.dot += a.dot(b);
    fit.spread_m2 += a.squaredNorm();
  }
  fit.angle_rad = fit.degenerate() ? 0.0 : std::atan2(fit.cross, fit.dot);
  fit.r = rotation(fit.angle_rad);
  return fit;
}

// Calls run(begin, end) for each maximal run [begin, end) of poses with !solved[k], in order.
template <typename Run>
void forEachUnsolvedRun(const std::vector<bool>& solved, Run run) {
  const int T = static_cast<int>(solved.size());
  for (int k = 0; k < T;) {
    if (solved[k]) {
      ++k;
      continue;
    }
    int end = k;
    while (end < T && !solved[end]) ++end;
    run(k, end);
    k = end;
  }
}

struct StretchFit {
  double offset_rad = 0.0;     // solved path's heading - dead reckoning's, over the stretch
  double sigma_rad = kNoFitHeadingSigma_rad;
  double position_sigma_m = kMinPositionSigma_m;
  bool fitted = false;
};

// Rotation fit of the solved poses onto dead reckoning over the stretch from `edge` stepping by
// `direction` (-1: back, +1: forward) within stretch_us of it.
StretchFit fitStretch(const OdometryPath& path, const std::vector<bool>& solved, const Path& out,
                      const std::vector<double>& heading_offset_rad, int edge, int direction,
                      int64_t stretch_us) {
  StretchFit fit;
  fit.offset_rad = heading_offset_rad[edge];
  const std::vector<int> poses = stretchPoses(path, solved, edge, direction, stretch_us);
  const int n = static_cast<int>(poses.size());
  if (n < 3) return fit;
  const RigidFit rigid = fitRigid(path, out, poses, 0);
  if (!(rigid.spread_m2 > 0.0) || rigid.degenerate()) return fit;
  double residual_m2 = 0.0;
  for (int k : poses) residual_m2 += rigid.residual(path, out, k).squaredNorm();
  const double rms_m = std::sqrt(residual_m2 / n);
  const double radius_m = std::sqrt(rigid.spread_m2 / n);
  fit.offset_rad = rigid.angle_rad;
  fit.position_sigma_m = std::max(rms_m, kMinPositionSigma_m);
  // The solved positions' errors are smooth along the path (one window bends many of them alike):
  // counted as two independent points at the stretch's radius, not n.
  fit.sigma_rad = std::max(std::sqrt(2.0) * fit.position_sigma_m / std::max(radius_m, 1e-9), kMinHeadingSigma_rad);
  fit.fitted = true;
  return fit;
}

// Solved poses right beside a gap rest on windows that saw ranges on one side only; with an
// outlier among their few ranges they can be metres off. Over the contiguous solved poses within
// stretch_us of the gap edge, the half further from the gap is fitted rigidly onto dead reckoning;
// the nearer poses up to the last one off that fit by more than kEdgeOutlierSigmas x its scatter
// (and by more than kEdgeOutlierFloor_m) are left to the fill.
// Returns how many poses from the edge are untrusted.
int untrustedEdgePoses(const OdometryPath& path, const std::vector<bool>& solved, const Path& out, int edge,
                       int direction, int64_t stretch_us) {
  const std::vector<int> poses = stretchPoses(path, solved, edge, direction, stretch_us);
  const int n = static_cast<int>(poses.size());
  if (n < 6) return 0;
  const int half = n / 2;
  const RigidFit far_half = fitRigid(path, out, poses, half);
  auto residual = [&](int k) { return far_half.residual(path, out, k).norm(); };
  double far_m2 = 0.0;
  for (int i = half; i < n; ++i) far_m2 += residual(poses[i]) * residual(poses[i]);
  const double threshold_m =
      std::max(kEdgeOutlierSigmas * std::sqrt(far_m2 / (n - half)), kEdgeOutlierFloor_m);
  int untrusted = 0;
  for (int i = 0; i < half; ++i)
    if (residual(poses[i]) > threshold_m) untrusted = i + 1;
  return untrusted;
}

}  // namespace

void fillUnsolvedPoses(const OdometryPath& path, const std::vector<bool>& solved_given,
                       const std::vector<double>& heading_offset_rad, double stretch_s, Path& out) {
  const int T = path.size();
  const int64_t stretch_us = static_cast<int64_t>(std::llround(stretch_s * 1e6));
  std::vector<bool> solved = solved_given;
  forEachUnsolvedRun(solved_given, [&](int begin, int end) {
    if (begin == 0 || end == T) return;  // the gap's edges are checked where both sides are solved
    const int back = untrustedEdgePoses(path, solved_given, out, begin - 1, -1, stretch_us);
    const int forward = untrustedEdgePoses(path, solved_given, out, end, +1, stretch_us);
    for (int i = 0; i < back; ++i) solved[begin - 1 - i] = false;
    for (int i = 0; i < forward; ++i) solved[end + i] = false;
  });
  std::vector<double> distance_m(T, 0.0);
  for (int k = 1; k < T; ++k) distance_m[k] = distance_m[k - 1] + path.step_m[k - 1];
  forEachUnsolvedRun(solved, [&](int begin, int end) {
    const int before = begin - 1, after = end;  // solved neighbours (may be out of range)
    if (before < 0 && after >= T) return;       // nothing solved: nothing to hold the fill
    if (before < 0 || after >= T) {
      // One-ended: dead reckoning from the solved side, turned by that side's stretch heading.
      const int anchor = before < 0 ? after : before;
      const StretchFit fit =
          fitStretch(path, solved, out, heading_offset_rad, anchor, before < 0 ? +1 : -1, stretch_us);
      const Eigen::Matrix2d r = rotation(fit.offset_rad);
      for (int i = begin; i < end; ++i) {
        const Eigen::Vector2d xy = solvedAt(out, anchor) + r * (deadReckoned(path, i) - deadReckoned(path, anchor));
        out[i].x_m = xy.x();
        out[i].y_m = xy.y();
        out[i].heading_rad = path.heading_rad[i] + fit.offset_rad;
      }
      return;
    }
    const StretchFit fit_a = fitStretch(path, solved, out, heading_offset_rad, before, -1, stretch_us);
    const StretchFit fit_b = fitStretch(path, solved, out, heading_offset_rad, after, +1, stretch_us);
    const double span_m = distance_m[after] - distance_m[before];
    auto fraction = [&](double at_m) {
      return span_m > 0.0 ? (at_m - distance_m[before]) / span_m : 0.0;
    };
    // Heading offsets relative to phi_a (unwrapped across the gap).
    const double phi_a = fit_a.offset_rad;
    const double phi_b = phi_a + wrapAngle(fit_b.offset_rad - fit_a.offset_rad);
    // The end residual: both solved ends' scatter, and the translation the odometry itself drifts
    // over the segment (spread linearly along it below, so marginalised here).
    const double sigma_p = std::hypot(std::hypot(fit_a.position_sigma_m, fit_b.position_sigma_m),
                                      kTranslationSigmaPerDistance * span_m);
    Eigen::Vector3d theta(phi_a, phi_b - phi_a, 1.0);  // alpha, beta, s
    const Eigen::Vector2d target = solvedAt(out, after) - solvedAt(out, before);
    auto endDisplacement = [&](const Eigen::Vector3d& t, Eigen::Matrix<double, 2, 3>* jacobian) {
      Eigen::Vector2d sum = Eigen::Vector2d::Zero(), d_alpha = Eigen::Vector2d::Zero(),
                      d_beta = Eigen::Vector2d::Zero();
      for (int m = before; m < after; ++m) {
        const double f = span_m > 0.0 ? fraction(0.5 * (distance_m[m] + distance_m[m + 1]))
                                      : static_cast<double>(m - before + 0.5) / (after - before);
        const Eigen::Vector2d step = rotation(t(0) + t(1) * f) * (deadReckoned(path, m + 1) - deadReckoned(path, m));
        const Eigen::Vector2d perpendicular(-step.y(), step.x());
        sum += step;
        d_alpha += perpendicular;
        d_beta += f * perpendicular;
      }
      if (jacobian) *jacobian << t(2) * d_alpha, t(2) * d_beta, sum;
      return Eigen::Vector2d(t(2) * sum);
    };
    for (int iteration = 0; iteration < kGaussNewtonIterations; ++iteration) {
      Eigen::Matrix<double, 2, 3> J;
      const Eigen::Vector2d r_end = (endDisplacement(theta, &J) - target) / sigma_p;
      J /= sigma_p;
      Eigen::Matrix3d H = J.transpose() * J;
      Eigen::Vector3d g = J.transpose() * r_end;
      // Priors: alpha ~ phi_a, alpha + beta ~ phi_b, s ~ 1.
      const double wa = 1.0 / (fit_a.sigma_rad * fit_a.sigma_rad), wb = 1.0 / (fit_b.sigma_rad * fit_b.sigma_rad);
      const double ws = 1.0 / (kScaleSigma * kScaleSigma);
      H(0, 0) += wa + wb;
      H(0, 1) += wb;
      H(1, 0) += wb;
      H(1, 1) += wb;
      H(2, 2) += ws;
      g(0) += wa * (theta(0) - phi_a) + wb * (theta(0) + theta(1) - phi_b);
      g(1) += wb * (theta(0) + theta(1) - phi_b);
      g(2) += ws * (theta(2) - 1.0);
      const Eigen::Vector3d delta = H.ldlt().solve(-g);
      if (!delta.allFinite()) break;
      theta += delta;
      if (delta.norm() < 1e-10) break;
    }
    const Eigen::Vector2d mismatch = target - endDisplacement(theta, nullptr);
    Eigen::Vector2d xy = solvedAt(out, before);
    for (int m = before; m + 1 < after; ++m) {
      const double f_step = span_m > 0.0 ? fraction(0.5 * (distance_m[m] + distance_m[m + 1]))
                                         : static_cast<double>(m - before + 0.5) / (after - before);
      xy += theta(2) * rotation(theta(0) + theta(1) * f_step) * (deadReckoned(path, m + 1) - deadReckoned(path, m));
      const int i = m + 1;
      const double f = span_m > 0.0 ? fraction(distance_m[i]) : static_cast<double>(i - before) / (after - before);
      const Eigen::Vector2d p = xy + f * mismatch;
      out[i].x_m = p.x();
      out[i].y_m = p.y();
      out[i].heading_rad = path.heading_rad[i] + theta(0) + theta(1) * f;
    }
  });
}

}  // namespace roam::spectral
