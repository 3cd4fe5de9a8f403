// The EKF proper: a Gaussian over
//   [x, y, theta, (range scale, range offset), (odometry distance scale s, heading-rate bias b),
//    m1x, m1y, (o1), m2x, m2y, (o2), ...]
// (o_i: beacon i's own range offset, where added with one).
//
// Model (world frame, metres, radians CCW):
//   motion: roam::estimation's SE(2) step (motion_model.hpp): the increment (u, v, w) reported
//     in the robot frame, calibrated to (s u, s v, w - b dt), composed onto the pose; with
//     noise Q on (u, v, w) (so diag(s, s, 1) Q diag(s, s, 1) on the calibrated increment).
//     Linearised with the shared Jacobians: pose rows x' = f(pose, s, b), so with A the 3 x n
//     Jacobian of f over the whole state (pose and calibration columns), P_p* <- A P and
//     P_pp <- A P A' + G Q_c G' (O(n) per step); b also walks: var_b += walk^2 dt.
//   range to beacon m: range_m = scale * |m - p| + offset + o_m + noise(sigma_m)
//     (scale = 1, offset = 0 when the bias states are off; o_m = 0 without per-beacon offsets:
//     an acoustic transponder's turn-around delay or a UWB anchor's antenna delay, its own per
//     beacon; prior 0 +- the sigma it is added with, uncorrelated with the rest);
//   bearing (robot-relative): bearing_rad = atan2(my - y, mx - x) - theta + noise.
// Updates use the Joseph form P <- (I - K H) P (I - K H)' + K R K', then symmetrise, so P stays
// symmetric positive (semi)definite; headings and bearing innovations are wrapped to (-pi, pi].
#pragma once

#include "ekf_smoother.hpp"

#include <map>

#include <Eigen/Dense>

#include "roam/calibration_priors.hpp"
#include "roam/types.hpp"

namespace roam {
namespace ekf {

// Prior of the odometry calibration states (off: s = 1, b = 0 exactly, no states).
struct EkfCalibrationPrior {
  bool estimated = false;
  double distance_scale_sigma = kDistanceScalePriorSigma;
  double heading_rate_bias_sigma_rad_s = kHeadingRateBiasPriorSigma_rad_s;
};

class EkfFilter {
 public:
  static constexpr int kX = 0, kY = 1, kHeading = 2, kScale = 3, kOffset = 4;

  using CalibrationPrior = EkfCalibrationPrior;

  // The pose (x, y, heading) with its covariance; with_bias adds scale and offset states,
  // calibration.estimated the odometry distance scale and heading-rate bias.
  void reset(const Eigen::Vector3d& world_T_robot, const Eigen::Matrix3d& pose_cov,
             bool with_bias, double scale_sigma, double offset_sigma_m,
             const CalibrationPrior& calibration = {});

  // One motion step through roam::estimation: the increment of odometry (forward, lateral,
  // heading change) over dt_s seconds, Q its 3 x 3 noise covariance, bias_walk_var the
  // heading-rate bias's random-walk variance over the step ((rad/s)^2).
  void predict(const Odometry& odometry, double dt_s, const Eigen::Matrix3d& Q,
               double bias_walk_var = 0.0);
  // Move-then-turn shorthand: forward d, turn dtheta, variances diag(var_d, 0, var_dtheta).
  void predict(double distance_m, double dheading_rad, double var_distance_m2,
               double var_dheading_rad2);

  // A beacon's own range offset (0 without one) and the index of its state (-1 without).
  double beaconOffset(int id) const {
    const int o = beaconOffsetIndex(id);
    return o >= 0 ? x_(o) : 0.0;
  }
  int beaconOffsetIndex(int id) const {
    auto it = offset_index_.find(id);
    return it == offset_index_.end() ? -1 : it->second;
  }

  // Appends a beacon, uncorrelated with the rest, with the given mean and covariance;
  // offset_sigma_m > 0: with its own range offset state o (prior 0 +- offset_sigma_m,
  // uncorrelated with the rest; 0: none, o = 0 exactly).
  void addBeacon(int id, const Eigen::Vector2d& world_m, const Eigen::Matrix2d& cov_m2,
                 double offset_sigma_m = 0.0);
  // Appends a beacon correlated with the rest: cross = cov(beacon, existing state) (2 x n).
  void addBeacon(int id, const Eigen::Vector2d& world_m, const Eigen::Matrix2d& cov_m2,
                 const Eigen::MatrixXd& cross);
  // Takes a beacon out of the state (its position and its own offset, rows and columns): what the
  // filter knew of it is dropped, the rest keeps its marginal. Recorded for the smoother.
  void removeBeacon(int id);
  bool hasBeacon(int id) const { return index_.count(id) > 0; }
  int beaconIndex(int id) const { return index_.at(id); }
  const std::map<int, int>& beacons() const { return index_; }

  enum class Update { kApplied, kGated, kDegenerate };
  // Range (or range-bearing) update; nis receives the normalised innovation squared.
  // A measurement whose nis exceeds gate_chi2 is not applied (kGated).
  // huber_k > 0: ranges beyond huber_k sigma of the innovation are down-weighted (Huber).
  // innovation_m and innovation_var_m2, where given, receive the innovation and its predicted
  // variance H P H' + sigma^2 before the update (gated or not).
  Update updateRange(int beacon_id, double range_m, double sigma_m, double gate_chi2,
                     double* nis, double huber_k = 0.0, double* innovation_m = nullptr,
                     double* innovation_var_m2 = nullptr);
  Update updateRangeBearing(int beacon_id, double range_m, double sigma_m, double bearing_rad,
                            double sigma_bearing_rad, double gate_chi2, double* nis);

  // Zero-rate update: a stationary robot's reported turn is the bias, turn_rad = b dt + noise.
  Update updateHeadingRateBias(double turn_rad, double dt_s, double var_turn_rad2, double gate_chi2);

  // A beacon's position less the robot's (m): a range to it reads |delta - e| - |delta| long when
  // the robot is e away from where the filter has it.
  Eigen::Vector2d beaconFromRobot_m(int beacon_id) const {
    return x_.segment<2>(index_.at(beacon_id)) - x_.head<2>();
  }
  // Predicted range (scale * |m - p| + offset + o_m) and its Jacobian row (1 x n).
  double predictRange(int beacon_id, Eigen::RowVectorXd* jacobian) const;
  // Predicted robot-relative bearing and its Jacobian row (1 x n).
  double predictBearing(int beacon_id, Eigen::RowVectorXd* jacobian) const;

  bool withBias() const { return with_bias_; }
  // Moves the range-bias mean (covariance unchanged): used only while the bias is at its prior.
  void recentreBias(double scale, double offset_m) {
    if (!with_bias_) return;
    x_(kScale) = scale;
    x_(kOffset) = offset_m;
  }
  bool withCalibration() const { return calib_index_ >= 0; }
  int calibrationIndex() const { return calib_index_; }  // s at this index, b at the next
  double odometryScale() const { return withCalibration() ? x_(calib_index_) : 1.0; }
  double headingRateBias() const { return withCalibration() ? x_(calib_index_ + 1) : 0.0; }
  // Moves the calibration means (covariance unchanged).
  void recentreCalibration(double distance_scale, double heading_rate_bias_rad_s) {
    if (!withCalibration()) return;
    x_(calib_index_) = distance_scale;
    x_(calib_index_ + 1) = heading_rate_bias_rad_s;
  }
  // Takes the heading-rate bias out of the estimate: b = 0 exactly (mean and covariance row).
  void fixHeadingRateBias() {
    if (!withCalibration()) return;
    x_(calib_index_ + 1) = 0.0;
    P_.row(calib_index_ + 1).setZero();
    P_.col(calib_index_ + 1).setZero();
  }
  // Puts it back: b uncorrelated with the rest, its mean kept, variance var_rad2_s2.
  void releaseHeadingRateBias(double var_rad2_s2) {
    if (!withCalibration()) return;
    P_.row(calib_index_ + 1).setZero();
    P_.col(calib_index_ + 1).setZero();
    P_(calib_index_ + 1, calib_index_ + 1) = var_rad2_s2;
  }
  // Adds var to the pose block's diagonal (x, y, heading): re-opens a starved filter.
  void inflatePose(double var_m2, double var_rad2);
  // Adds var_m2 to the variance of a beacon's own range offset (no-op without one).
  void inflateBeaconOffset(int id, double var_m2);
  double scale() const { return with_bias_ ? x_(kScale) : 1.0; }
  double offset() const { return with_bias_ ? x_(kOffset) : 0.0; }
  const Eigen::VectorXd& mean() const { return x_; }
  const Eigen::MatrixXd& covariance() const { return P_; }
  int size() const { return static_cast<int>(x_.size()); }
  // While set, every predict and applied update is appended to *operations (for the smoother,
  // ekf_smoother.hpp); nullptr: not recorded. Not owned; copies of the filter copy the pointer,
  // so set it only around the operations to record.
  void record(std::vector<SmootherOperation>* operations) { record_ = operations; }

 private:
  Update applyUpdate(const Eigen::MatrixXd& H, const Eigen::VectorXd& innovation,
                     const Eigen::MatrixXd& R, double gate_chi2, double* nis);

  bool with_bias_ = false;
  int calib_index_ = -1;
  Eigen::VectorXd x_;
  Eigen::MatrixXd P_;
  std::map<int, int> index_;  // beacon id -> index of its x in the state
  std::map<int, int> offset_index_;  // beacon id -> index of its own range offset (if any)
  std::vector<SmootherOperation>* record_ = nullptr;
};

}  // namespace ekf
}  // namespace roam
