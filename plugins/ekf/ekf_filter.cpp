#include "ekf_filter.hpp"

#include <cmath>
#include <stdexcept>

#include "roam/types.hpp"

namespace roam {

void EkfFilter::reset(const Eigen::Vector3d& world_T_robot, const Eigen::Matrix3d& pose_cov,
                      bool with_bias, double scale_sigma, double offset_sigma_m) {
  with_bias_ = with_bias;
  const int n = with_bias ? 5 : 3;
  x_ = Eigen::VectorXd::Zero(n);
  P_ = Eigen::MatrixXd::Zero(n, n);
  x_.head<3>() = world_T_robot;
  x_(kHeading) = wrapAngle(x_(kHeading));
  P_.topLeftCorner<3, 3>() = pose_cov;
  if (with_bias) {
    x_(kScale) = 1.0;
    x_(kOffset) = 0.0;
    P_(kScale, kScale) = scale_sigma * scale_sigma;
    P_(kOffset, kOffset) = offset_sigma_m * offset_sigma_m;
  }
  index_.clear();
}

void EkfFilter::predict(double distance_m, double dheading_rad, double var_distance_m2,
                        double var_dheading_rad2) {
  const double c = std::cos(x_(kHeading)), s = std::sin(x_(kHeading));
  x_(kX) += distance_m * c;
  x_(kY) += distance_m * s;
  x_(kHeading) = wrapAngle(x_(kHeading) + dheading_rad);

  Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
  F(kX, kHeading) = -distance_m * s;
  F(kY, kHeading) = distance_m * c;
  Eigen::Matrix<double, 3, 2> G;
  G << c, 0.0, s, 0.0, 0.0, 1.0;
  const Eigen::Vector2d q(var_distance_m2, var_dheading_rad2);

  const int n = size();
  const Eigen::Matrix3d P_pp = P_.topLeftCorner<3, 3>();
  P_.topLeftCorner<3, 3>() = F * P_pp * F.transpose() + G * q.asDiagonal() * G.transpose();
  if (n > 3) {
    const Eigen::MatrixXd P_pr = F * P_.topRightCorner(3, n - 3);
    P_.topRightCorner(3, n - 3) = P_pr;
    P_.bottomLeftCorner(n - 3, 3) = P_pr.transpose();
  }
}

void EkfFilter::addBeacon(int id, const Eigen::Vector2d& world_m, const Eigen::Matrix2d& cov_m2) {
  addBeacon(id, world_m, cov_m2, Eigen::MatrixXd::Zero(2, size()));
}

void EkfFilter::addBeacon(int id, const Eigen::Vector2d& world_m, const Eigen::Matrix2d& cov_m2,
                          const Eigen::MatrixXd& cross) {
  if (hasBeacon(id)) throw std::logic_error("beacon " + std::to_string(id) + " already in the state");
  const int n = size();
  x_.conservativeResize(n + 2);
  x_.tail<2>() = world_m;
  P_.conservativeResize(n + 2, n + 2);
  P_.bottomLeftCorner(2, n) = cross;
  P_.topRightCorner(n, 2) = cross.transpose();
  P_.bottomRightCorner<2, 2>() = cov_m2;
  index_[id] = n;
}

double EkfFilter::predictRange(int beacon_id, Eigen::RowVectorXd* jacobian) const {
  const int m = index_.at(beacon_id);
  const Eigen::Vector2d delta_m = x_.segment<2>(m) - x_.head<2>();
  const double distance_m = delta_m.norm();
  const double scale = this->scale();
  if (jacobian) {
    jacobian->setZero(size());
    if (distance_m > 0.0) {
      const Eigen::Vector2d u = delta_m / distance_m;
      jacobian->segment<2>(kX) = -scale * u.transpose();
      jacobian->segment<2>(m) = scale * u.transpose();
    }
    if (with_bias_) {
      (*jacobian)(kScale) = distance_m;
      (*jacobian)(kOffset) = 1.0;
    }
  }
  return scale * distance_m + offset();
}

double EkfFilter::predictBearing(int beacon_id, Eigen::RowVectorXd* jacobian) const {
  const int m = index_.at(beacon_id);
  const Eigen::Vector2d delta_m = x_.segment<2>(m) - x_.head<2>();
  const double q = delta_m.squaredNorm();
  if (jacobian) {
    jacobian->setZero(size());
    if (q > 0.0) {
      // d atan2(dy, dx) = (dx d(dy) - dy d(dx)) / q, with dx = mx - x, dy = my - y.
      (*jacobian)(kX) = delta_m.y() / q;
      (*jacobian)(kY) = -delta_m.x() / q;
      (*jacobian)(m) = -delta_m.y() / q;
      (*jacobian)(m + 1) = delta_m.x() / q;
    }
    (*jacobian)(kHeading) = -1.0;
  }
  return wrapAngle(std::atan2(delta_m.y(), delta_m.x()) - x_(kHeading));
}

EkfFilter::Update EkfFilter::updateRange(int beacon_id, double range_m, double sigma_m,
                                         double gate_chi2, double* nis) {
  const int m = index_.at(beacon_id);
  if ((x_.segment<2>(m) - x_.head<2>()).norm() < 1e-9) return Update::kDegenerate;
  Eigen::RowVectorXd H;
  const double predicted_m = predictRange(beacon_id, &H);
  Eigen::VectorXd innovation(1);
  innovation(0) = range_m - predicted_m;
  Eigen::MatrixXd R(1, 1);
  R(0, 0) = sigma_m * sigma_m;
  return applyUpdate(H, innovation, R, gate_chi2, nis);
}

EkfFilter::Update EkfFilter::updateRangeBearing(int beacon_id, double range_m, double sigma_m,
                                                double bearing_rad, double sigma_bearing_rad,
                                                double gate_chi2, double* nis) {
  const int m = index_.at(beacon_id);
  if ((x_.segment<2>(m) - x_.head<2>()).norm() < 1e-9) return Update::kDegenerate;
  Eigen::RowVectorXd H_range, H_bearing;
  const double predicted_m = predictRange(beacon_id, &H_range);
  const double predicted_rad = predictBearing(beacon_id, &H_bearing);
  Eigen::MatrixXd H(2, size());
  H.row(0) = H_range;
  H.row(1) = H_bearing;
  Eigen::VectorXd innovation(2);
  innovation << range_m - predicted_m, wrapAngle(bearing_rad - predicted_rad);
  Eigen::MatrixXd R = Eigen::MatrixXd::Zero(2, 2);
  R(0, 0) = sigma_m * sigma_m;
  R(1, 1) = sigma_bearing_rad * sigma_bearing_rad;
  return applyUpdate(H, innovation, R, gate_chi2, nis);
}

EkfFilter::Update EkfFilter::applyUpdate(const Eigen::MatrixXd& H,
                                         const Eigen::VectorXd& innovation,
                                         const Eigen::MatrixXd& R, double gate_chi2,
                                         double* nis) {
  const Eigen::MatrixXd PHt = P_ * H.transpose();
  const Eigen::MatrixXd S = H * PHt + R;
  const Eigen::LLT<Eigen::MatrixXd> S_llt(S);
  if (S_llt.info() != Eigen::Success) return Update::kDegenerate;
  const double chi2 = innovation.dot(S_llt.solve(innovation));
  if (nis) *nis = chi2;
  if (!(chi2 <= gate_chi2)) return Update::kGated;

  const Eigen::MatrixXd K = S_llt.solve(PHt.transpose()).transpose();  // P H' S^-1
  x_ += K * innovation;
  x_(kHeading) = wrapAngle(x_(kHeading));
  // Joseph form: (I - K H) P (I - K H)' + K R K'.
  Eigen::MatrixXd I_KH = -K * H;
  I_KH.diagonal().array() += 1.0;
  const Eigen::MatrixXd P_new = I_KH * P_ * I_KH.transpose() + K * R * K.transpose();
  P_ = 0.5 * (P_new + P_new.transpose());
  return Update::kApplied;
}

}  // namespace roam
