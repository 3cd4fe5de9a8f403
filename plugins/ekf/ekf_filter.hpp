// The EKF proper: a Gaussian over [x, y, theta, (scale, offset), m1x, m1y, m2x, m2y, ...].
//
// Model (world frame, metres, radians CCW):
//   motion, "move then turn" (the convention of roam::sim and dead reckoning):
//     x' = x + d cos(theta),  y' = y + d sin(theta),  theta' = theta + dtheta,
//     with (d, dtheta) the odometry plus zero-mean noise of covariance diag(var_d, var_dtheta);
//     linearised: F = d(x', y', theta')/d(x, y, theta) = [1 0 -d sin; 0 1 d cos; 0 0 1],
//     G = d(x', y', theta')/d(d, dtheta) = [cos 0; sin 0; 0 1]; only the pose rows change, so
//     P_pp <- F P_pp F' + G Q G' and P_p* <- F P_p* (O(n) per step).
//   range to beacon m: range_m = scale * |m - p| + offset + noise(sigma_m)
//     (scale = 1, offset = 0 when the bias states are off);
//   bearing (robot-relative): bearing_rad = atan2(my - y, mx - x) - theta + noise.
// Updates use the Joseph form P <- (I - K H) P (I - K H)' + K R K', then symmetrise, so P stays
// symmetric positive (semi)definite; headings and bearing innovations are wrapped to (-pi, pi].
#pragma once

#include <map>

#include <Eigen/Dense>

namespace roam {

class EkfFilter {
 public:
  static constexpr int kX = 0, kY = 1, kHeading = 2, kScale = 3, kOffset = 4;

  // The pose (x, y, heading) with its covariance; with_bias adds scale and offset states.
  void reset(const Eigen::Vector3d& world_T_robot, const Eigen::Matrix3d& pose_cov,
             bool with_bias, double scale_sigma, double offset_sigma_m);

  // One motion step (distance d along the current heading, then turn dtheta) with
  // var_d, var_dtheta the variances of the odometry noise.
  void predict(double distance_m, double dheading_rad, double var_distance_m2,
               double var_dheading_rad2);

  // Appends a beacon, uncorrelated with the rest, with the given mean and covariance.
  void addBeacon(int id, const Eigen::Vector2d& world_m, const Eigen::Matrix2d& cov_m2);
  // Appends a beacon correlated with the rest: cross = cov(beacon, existing state) (2 x n).
  void addBeacon(int id, const Eigen::Vector2d& world_m, const Eigen::Matrix2d& cov_m2,
                 const Eigen::MatrixXd& cross);
  bool hasBeacon(int id) const { return index_.count(id) > 0; }
  int beaconIndex(int id) const { return index_.at(id); }
  const std::map<int, int>& beacons() const { return index_; }

  enum class Update { kApplied, kGated, kDegenerate };
  // Range (or range-bearing) update; nis receives the normalised innovation squared.
  // A measurement whose nis exceeds gate_chi2 is not applied (kGated).
  Update updateRange(int beacon_id, double range_m, double sigma_m, double gate_chi2,
                     double* nis);
  Update updateRangeBearing(int beacon_id, double range_m, double sigma_m, double bearing_rad,
                            double sigma_bearing_rad, double gate_chi2, double* nis);

  // Predicted range (scale * |m - p| + offset) and its Jacobian row (1 x n).
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
  double scale() const { return with_bias_ ? x_(kScale) : 1.0; }
  double offset() const { return with_bias_ ? x_(kOffset) : 0.0; }
  const Eigen::VectorXd& mean() const { return x_; }
  const Eigen::MatrixXd& covariance() const { return P_; }
  int size() const { return static_cast<int>(x_.size()); }

 private:
  Update applyUpdate(const Eigen::MatrixXd& H, const Eigen::VectorXd& innovation,
                     const Eigen::MatrixXd& R, double gate_chi2, double* nis);

  bool with_bias_ = false;
  Eigen::VectorXd x_;
  Eigen::MatrixXd P_;
  std::map<int, int> index_;  // beacon id -> index of its x in the state
};

}  // namespace roam
