// Observation model of the online EM SLAM (paper Eqs. 2, 3, 7, 8), with the range scale and
// offset added to the parameter:
//   y = h(x, phi) + delta,  h = ( s |m - p| + b ,  atan2(m_y - p_y, m_x - p_x) - th )
// for a landmark m = (m_x, m_y), robot pose x = (p, th), phi = (m_x, m_y, s, b); range-only
// observations keep the first row. delta | I ~ N(0, sigma_I^2 R), I in {0, 1} the mixture
// component (R = [[sr^2, rho], [rho, sb^2]]).
//
// Linearised at the current estimate phi^ (Eq. 8): h(x, phi) ~ h(x, phi^) + J (phi - phi^), so
// the complete-data log-likelihood of one observation is quadratic in phi,
//   -1/2 (z - J phi)^T W (z - J phi),  z = y - h(x, phi^) + J phi^,  W = (sigma_I^2 R)^-1,
// with sufficient statistic S = (J^T W J, J^T W z): 10 + 4 numbers (kStatSize). The M-step
// maximises the sum of these quadratics in closed form.
#pragma once

#include <Eigen/Core>

#include "online_em_config.hpp"

namespace roam {
namespace online_em {

constexpr int kStatSize = 14;  // upper triangle of the 4x4 J^T W J (10), then J^T W z (4)

struct RangeObservation {
  double range_m = 0.0;
  double sigma_m = 0.0;  // > 0: replaces range_sigma_m
  bool has_bearing = false;
  double bearing_rad = 0.0;
};

class ObservationModel {
 public:
  explicit ObservationModel(const OnlineEmConfig& config);

  // log g(y | pose, phi, component), normalising constant included (it differs by component).
  double logLikelihood(const RangeObservation& y, double x_m, double y_m, double heading_rad,
                       const Eigen::Vector4d& phi, int component) const;

  // S(pose, component, y) linearised at phi (see above), written to out[0 .. kStatSize).
  void statistic(const RangeObservation& y, double x_m, double y_m, double heading_rad,
                 const Eigen::Vector4d& phi, int component, double* out) const;

  // Unpacks a statistic into the 4x4 matrix J^T W J and the vector J^T W z.
  static void unpack(const double* stat, Eigen::Matrix4d* information, Eigen::Vector4d* vector);

  double componentScale(int component) const { return component == 0 ? sigma0_ : sigma1_; }

  // Outlier component of a range-only observation: uniform over [0, span_m] (span_m > 0; its
  // statistic is zero: an outlier says nothing about theta), else the wide Gaussian.
  void setOutlierSpan(double span_m) { outlier_span_m_ = span_m; }
  // The inlier component's scale (in units of sr), as estimated by the M-step.
  void setInlierScale(double sigma0) { sigma0_ = sigma0; }
  bool uniformOutlier(const RangeObservation& y) const { return !y.has_bearing && outlier_span_m_ > 0.0; }

 private:
  // Residual y - h(x, phi) (bearing wrapped), Jacobian J = dh/dphi and W for the component.
  int linearise(const RangeObservation& y, double x_m, double y_m, double heading_rad,
                const Eigen::Vector4d& phi, int component, Eigen::Vector2d* residual,
                Eigen::Matrix<double, 2, 4>* jacobian, Eigen::Matrix2d* weight) const;

  double sigma0_, sigma1_;
  double outlier_span_m_ = 0.0;
  double range_sigma_m_, bearing_sigma_rad_, range_bearing_cov_;
};

}  // namespace online_em
}  // namespace roam
