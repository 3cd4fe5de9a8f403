#include "ekf_filter.hpp"

#include "roam/estimation/range_model.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "roam/estimation/motion_model.hpp"
#include "roam/types.hpp"

namespace roam {
namespace ekf {

void EkfFilter::reset(const Eigen::Vector3d& world_T_robot, const Eigen::Matrix3d& pose_cov,
                      bool with_bias, double scale_sigma, double offset_sigma_m,
                      const CalibrationPrior& calibration) {
  with_bias_ = with_bias;
  const int n_bias = with_bias ? 5 : 3;
  calib_index_ = calibration.estimated ? n_bias : -1;
  const int n = n_bias + (calibration.estimated ? 2 : 0);
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
  if (calibration.estimated) {
    x_(calib_index_) = 1.0;
    x_(calib_index_ + 1) = 0.0;
    P_(calib_index_, calib_index_) = std::pow(calibration.distance_scale_sigma, 2);
    P_(calib_index_ + 1, calib_index_ + 1) = std::pow(calibration.heading_rate_bias_sigma_rad_s, 2);
  }
  index_.clear();
  offset_index_.clear();
}

void EkfFilter::predict(const Odometry& odometry, double dt_s, const Eigen::Matrix3d& Q,
                        double bias_walk_var) {
  estimation::OdometryCalibration calib;
  calib.distance_scale = odometryScale();
  calib.heading_rate_bias_rad_s = headingRateBias();
  const Eigen::Vector3d pose = x_.head<3>();
  const estimation::StepJacobians J = estimation::stepJacobians(pose, odometry, dt_s, calib);
  const Eigen::Vector3d next =
      estimation::step(pose, estimation::calibratedIncrement(odometry, dt_s, calib));
  x_.head<3>() = next;
  x_(kHeading) = wrapAngle(x_(kHeading));

  // T = A P, A = [wrt_pose at the pose columns, wrt_calibration at the calibration columns].
  Eigen::MatrixXd T = J.wrt_pose * P_.topRows(3);
  if (withCalibration()) T += J.wrt_calibration * P_.middleRows(calib_index_, 2);
  Eigen::Matrix3d P_pp = T.leftCols(3) * J.wrt_pose.transpose();
  if (withCalibration()) P_pp += T.middleCols(calib_index_, 2) * J.wrt_calibration.transpose();
  const Eigen::Vector3d d(calib.distance_scale, calib.distance_scale, 1.0);
  const Eigen::Matrix3d Q_c = d.asDiagonal() * Q * d.asDiagonal();
  P_pp += J.wrt_increment * Q_c * J.wrt_increment.transpose();
  T.leftCols(3) = 0.5 * (P_pp + P_pp.transpose());
  P_.topRows(3) = T;
  P_.leftCols(3) = T.transpose();
  if (withCalibration()) P_(calib_index_ + 1, calib_index_ + 1) += bias_walk_var;
  if (record_) {
    SmootherOperation op;
    op.kind = SmootherOperation::Kind::kPredict;
    op.A = Eigen::MatrixXd::Zero(3, size());
    op.A.leftCols(3) = J.wrt_pose;
    if (withCalibration()) op.A.middleCols(calib_index_, 2) = J.wrt_calibration;
    record_->push_back(std::move(op));
  }
}

void EkfFilter::predict(double distance_m, double dheading_rad, double var_distance_m2,
                        double var_dheading_rad2) {
  Odometry odometry;
  odometry.forward_m = distance_m;
  odometry.delta_heading_rad = dheading_rad;
  const Eigen::Matrix3d Q = Eigen::Vector3d(var_distance_m2, 0.0, var_dheading_rad2).asDiagonal();
  predict(odometry, 0.0, Q);
}

void EkfFilter::inflatePose(double var_m2, double var_rad2) {
  P_(kX, kX) += var_m2;
  P_(kY, kY) += var_m2;
  P_(kHeading, kHeading) += var_rad2;
}

void EkfFilter::inflateBeaconOffset(int id, double var_m2) {
  const int o = beaconOffsetIndex(id);
  if (o >= 0) P_(o, o) += var_m2;
}

void EkfFilter::addBeacon(int id, const Eigen::Vector2d& world_m, const Eigen::Matrix2d& cov_m2,
                          double offset_sigma_m) {
  addBeacon(id, world_m, cov_m2, Eigen::MatrixXd::Zero(2, size()));
  if (!(offset_sigma_m > 0.0)) return;
  const int n = size();
  x_.conservativeResize(n + 1);
  x_(n) = 0.0;
  P_.conservativeResize(n + 1, n + 1);
  P_.row(n).setZero();
  P_.col(n).setZero();
  P_(n, n) = offset_sigma_m * offset_sigma_m;
  offset_index_[id] = n;
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

void EkfFilter::removeBeacon(int id) {
  std::vector<int> removed{index_.at(id), index_.at(id) + 1};
  if (const int o = beaconOffsetIndex(id); o >= 0) removed.push_back(o);
  std::vector<int> kept;
  for (int i = 0; i < size(); ++i)
    if (std::find(removed.begin(), removed.end(), i) == removed.end()) kept.push_back(i);
  if (record_) {
    SmootherOperation op;
    op.kind = SmootherOperation::Kind::kRemove;
    op.kept = kept;
    op.size_before = size();
    record_->push_back(std::move(op));
  }
  const Eigen::VectorXd x = x_(kept);
  const Eigen::MatrixXd P = P_(kept, kept);
  x_ = x;
  P_ = P;
  index_.erase(id);
  offset_index_.erase(id);
  // Each index moves down by the removed indices below it.
  auto shifted = [&](int i) {
    return i - static_cast<int>(std::count_if(removed.begin(), removed.end(), [&](int r) { return r < i; }));
  };
  for (auto& [beacon, i] : index_) i = shifted(i);
  for (auto& [beacon, i] : offset_index_) i = shifted(i);
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
    const int o = beaconOffsetIndex(beacon_id);
    if (o >= 0) (*jacobian)(o) = 1.0;
  }
  return estimation::predictedRange_m(distance_m, scale, offset() + beaconOffset(beacon_id));
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
                                         double gate_chi2, double* nis, double huber_k,
                                         double* innovation_m, double* innovation_var_m2) {
  const int m = index_.at(beacon_id);
  if ((x_.segment<2>(m) - x_.head<2>()).norm() < 1e-9) return Update::kDegenerate;
  Eigen::RowVectorXd H;
  const double predicted_m = predictRange(beacon_id, &H);
  Eigen::VectorXd innovation(1);
  innovation(0) = range_m - predicted_m;
  Eigen::MatrixXd R(1, 1);
  R(0, 0) = sigma_m * sigma_m;
  if (innovation_m) *innovation_m = innovation(0);
  const double HPHt = huber_k > 0.0 || innovation_var_m2 ? H.dot(P_ * H.transpose()) : 0.0;
  if (innovation_var_m2) *innovation_var_m2 = HPHt + R(0, 0);
  if (huber_k > 0.0) {
    // Huber: beyond k sigma of the innovation's own spread S, the range counts with weight
    // k / |z| (z = innovation / sqrt(S)), i.e. S -> S |z| / k: its pull grows linearly, not
    // quadratically, so a non-line-of-sight range that slips through the gate moves the state
    // (and the calibration and bias states with it) by at most k sigma's worth.
    // The weight is judged without the range-bias states' own uncertainty: while their prior
    // is wide (10 % of a 150 m range is 15 m) every outlier fits by moving them, which is how
    // they learn a wrong scale from the first few ranges.
    const double S = HPHt + R(0, 0);
    const double z2 = innovation(0) * innovation(0) / S;
    if (nis) *nis = z2;
    if (!(z2 <= gate_chi2)) return Update::kGated;
    Eigen::RowVectorXd H0 = H;
    if (with_bias_) H0(kScale) = H0(kOffset) = 0.0;
    const int o = beaconOffsetIndex(beacon_id);
    if (o >= 0) H0(o) = 0.0;
    const double S0 = H0.dot(P_ * H0.transpose()) + R(0, 0);
    const double z = std::abs(innovation(0)) / std::sqrt(S0);
    if (z > huber_k) R(0, 0) += (z / huber_k - 1.0) * S;
    return applyUpdate(H, innovation, R, std::numeric_limits<double>::infinity(), nullptr);
  }
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

EkfFilter::Update EkfFilter::updateHeadingRateBias(double turn_rad, double dt_s, double var_turn_rad2,
                                                   double gate_chi2) {
  if (!withCalibration()) return Update::kDegenerate;
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(1, size());
  H(0, calib_index_ + 1) = dt_s;
  Eigen::VectorXd innovation(1);
  innovation(0) = turn_rad - dt_s * x_(calib_index_ + 1);
  Eigen::MatrixXd R(1, 1);
  R(0, 0) = var_turn_rad2;
  return applyUpdate(H, innovation, R, gate_chi2, nullptr);
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
  if (record_) {
    SmootherOperation op;
    op.kind = SmootherOperation::Kind::kUpdate;
    op.H = H;
    op.K = K;
    op.S_inverse = S_llt.solve(Eigen::MatrixXd::Identity(S.rows(), S.cols()));
    op.y = S_llt.solve(innovation);
    record_->push_back(std::move(op));
  }
  x_ += K * innovation;
  x_(kHeading) = wrapAngle(x_(kHeading));
  // Joseph form: (I - K H) P (I - K H)' + K R K'.
  Eigen::MatrixXd I_KH = -K * H;
  I_KH.diagonal().array() += 1.0;
  const Eigen::MatrixXd P_new = I_KH * P_ * I_KH.transpose() + K * R * K.transpose();
  P_ = 0.5 * (P_new + P_new.transpose());
  return Update::kApplied;
}

}  // namespace ekf
}  // namespace roam
