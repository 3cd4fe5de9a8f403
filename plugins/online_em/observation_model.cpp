#include "observation_model.hpp"

#include "roam/estimation/range_model.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

namespace roam {
namespace online_em {

namespace {
constexpr double kMinDistance_m = 1e-3;  // Jacobian of |m - p| is undefined at the landmark
constexpr double kLog2Pi = 1.8378770664093453;
}  // namespace

ObservationModel::ObservationModel(const OnlineEmConfig& config)
    : sigma0_(config.mixture_sigma0),
      sigma1_(config.mixture_sigma1),
      range_sigma_m_(config.range_sigma_m),
      bearing_sigma_rad_(config.bearing_sigma_rad),
      range_bearing_cov_(config.range_bearing_cov) {}

int ObservationModel::linearise(const RangeObservation& y, double x_m, double y_m,
                                double heading_rad, const Eigen::Vector4d& phi, int component,
                                Eigen::Vector2d* residual, Eigen::Matrix<double, 2, 4>* jacobian,
                                Eigen::Matrix2d* weight) const {
  const double dx = phi[0] - x_m, dy = phi[1] - y_m;
  const double distance_m = std::max(std::hypot(dx, dy), kMinDistance_m);
  const double scale = phi[2], offset_m = phi[3];
  const double sr = y.sigma_m > 0.0 ? y.sigma_m : range_sigma_m_;
  const double k2 = componentScale(component) * componentScale(component);
  jacobian->setZero();
  // d(s |m - p| + b)/dm = s (m - p)^T / |m - p|; d/ds = |m - p|; d/db = 1.
  (*jacobian)(0, 0) = scale * dx / distance_m;
  (*jacobian)(0, 1) = scale * dy / distance_m;
  (*jacobian)(0, 2) = distance_m;
  (*jacobian)(0, 3) = 1.0;
  (*residual)[0] = y.range_m - estimation::predictedRange_m(distance_m, scale, offset_m);
  if (!y.has_bearing) {
    (*residual)[1] = 0.0;
    weight->setZero();
    (*weight)(0, 0) = 1.0 / (k2 * sr * sr);
    return 1;
  }
  // d atan2(dy, dx)/dm = (-dy, dx) / |m - p|^2.
  const double d2 = distance_m * distance_m;
  (*jacobian)(1, 0) = -dy / d2;
  (*jacobian)(1, 1) = dx / d2;
  (*residual)[1] = std::remainder(y.bearing_rad - (std::atan2(dy, dx) - heading_rad), 2.0 * M_PI);
  Eigen::Matrix2d r;
  r << sr * sr, range_bearing_cov_, range_bearing_cov_, bearing_sigma_rad_ * bearing_sigma_rad_;
  *weight = (k2 * r).inverse();
  return 2;
}

double ObservationModel::logLikelihood(const RangeObservation& y, double x_m, double y_m,
                                       double heading_rad, const Eigen::Vector4d& phi,
                                       int component) const {
  if (component == 1 && uniformOutlier(y)) return -std::log(outlier_span_m_);
  Eigen::Vector2d e;
  Eigen::Matrix<double, 2, 4> j;
  Eigen::Matrix2d w;
  const int rows = linearise(y, x_m, y_m, heading_rad, phi, component, &e, &j, &w);
  if (rows == 1) return -0.5 * (e[0] * e[0] * w(0, 0) - std::log(w(0, 0)) + kLog2Pi);
  return -0.5 * (e.dot(w * e) - std::log(w.determinant()) + 2.0 * kLog2Pi);
}

void ObservationModel::statistic(const RangeObservation& y, double x_m, double y_m,
                                 double heading_rad, const Eigen::Vector4d& phi, int component,
                                 double* out) const {
  if (component == 1 && uniformOutlier(y)) {
    std::fill(out, out + kStatSize, 0.0);
    return;
  }
  Eigen::Vector2d e;
  Eigen::Matrix<double, 2, 4> j;
  Eigen::Matrix2d w;
  linearise(y, x_m, y_m, heading_rad, phi, component, &e, &j, &w);
  // z = y - h(phi^) + J phi^ = e + J phi^  (rows beyond the observation are zero in J and W).
  const Eigen::Vector2d z = e + j * phi;
  const Eigen::Matrix4d information = j.transpose() * w * j;
  const Eigen::Vector4d vector = j.transpose() * (w * z);
  int n = 0;
  for (int r = 0; r < 4; ++r)
    for (int c = r; c < 4; ++c) out[n++] = information(r, c);
  for (int r = 0; r < 4; ++r) out[n++] = vector[r];
}

void ObservationModel::unpack(const double* stat, Eigen::Matrix4d* information, Eigen::Vector4d* vector) {
  int n = 0;
  for (int r = 0; r < 4; ++r)
    for (int c = r; c < 4; ++c) {
      (*information)(r, c) = stat[n];
      (*information)(c, r) = stat[n];
      ++n;
    }
  for (int r = 0; r < 4; ++r) (*vector)[r] = stat[n++];
}

}  // namespace online_em
}  // namespace roam
