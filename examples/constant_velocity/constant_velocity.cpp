// An out-of-tree roam plugin: a constant-velocity range-only filter (no odometry used).
//
// Model: state (x, y, vx, vy) in the world frame; between times the velocity is a random walk,
// white acceleration with sigma accel_sigma_mps2. Each range to a surveyed beacon b is
// r = |b - (x, y)| + e, e ~ N(0, range_sigma_m) (the message's sigma when it has one), applied
// as an EKF update; ranges more than 5 sigma off the prediction are rejected. It starts at
// INITIAL_POSE at rest and publishes it, then a pose at every odometry time (odometry is only a clock).
// Built against an installed roam: see README.md beside this file.
#include <Eigen/Dense>
#include <cmath>
#include <map>

#include "roam/plugin_shim.hpp"

namespace {

struct CvConfig {
  double accel_sigma_mps2 = 0.5;
  double range_sigma_m = 0.3;
};

class ConstantVelocity : public roam::Estimator {
 public:
  explicit ConstantVelocity(const CvConfig& config) : config_(config) {}

  void setInitialPose(const roam::Pose& start) override {
    x_ << start.x_m, start.y_m, 0.0, 0.0;
    P_ = Eigen::Vector4d(0.01, 0.01, 1.0, 1.0).asDiagonal();
    utime_ = start.utime;
    started_ = true;
    setState(roam::EstimatorState::kTracking);
    emitPose(start);
  }
  void setBeacons(const roam::Map& surveyed) override {
    for (const roam::Beacon& b : surveyed) beacons_[b.id] = Eigen::Vector2d(b.x_m, b.y_m);
  }
  void addOdometry(const roam::Odometry& odometry) override {
    if (!started_) return rejectOdometry("no INITIAL_POSE yet");
    predictTo(odometry.utime);
    acceptOdometry();
    roam::Pose pose;
    pose.utime = utime_;
    pose.x_m = x_[0];
    pose.y_m = x_[1];
    pose.heading_rad = std::atan2(x_[3], x_[2]);
    emitPose(pose);
  }
  void addRange(const roam::Range& range) override {
    const auto beacon = beacons_.find(range.beacon_id);
    if (!started_ || beacon == beacons_.end()) return rejectRange("no surveyed beacon or start yet");
    predictTo(range.utime);
    const Eigen::Vector2d d = x_.head<2>() - beacon->second;
    const double predicted_m = std::max(d.norm(), 1e-6);
    Eigen::RowVector4d H(d.x() / predicted_m, d.y() / predicted_m, 0.0, 0.0);
    const double sigma_m = range.sigma_m > 0.0 ? range.sigma_m : config_.range_sigma_m;
    const double S = (H * P_ * H.transpose())(0, 0) + sigma_m * sigma_m;
    const double innovation = range.range_m - predicted_m;
    if (innovation * innovation > 25.0 * S) return rejectRange("more than 5 sigma off");
    const Eigen::Vector4d K = P_ * H.transpose() / S;
    x_ += K * innovation;
    P_ = (Eigen::Matrix4d::Identity() - K * H) * P_;
    acceptRange();
  }

 private:
  void predictTo(int64_t utime) {
    const double dt = std::max(0.0, 1e-6 * static_cast<double>(utime - utime_));
    if (utime > utime_) utime_ = utime;
    Eigen::Matrix4d F = Eigen::Matrix4d::Identity();
    F(0, 2) = F(1, 3) = dt;
    const double q = config_.accel_sigma_mps2 * config_.accel_sigma_mps2;
    Eigen::Matrix4d Q = Eigen::Matrix4d::Zero();
    Q(0, 0) = Q(1, 1) = q * dt * dt * dt / 3.0;
    Q(0, 2) = Q(2, 0) = Q(1, 3) = Q(3, 1) = q * dt * dt / 2.0;
    Q(2, 2) = Q(3, 3) = q * dt;
    x_ = F * x_;
    P_ = F * P_ * F.transpose() + Q;
  }

  CvConfig config_;
  Eigen::Vector4d x_ = Eigen::Vector4d::Zero();
  Eigen::Matrix4d P_ = Eigen::Matrix4d::Identity();
  int64_t utime_ = 0;
  bool started_ = false;
  std::map<int, Eigen::Vector2d> beacons_;
};

std::unique_ptr<roam::Estimator> makeConstantVelocity(roam::Options& options) {
  CvConfig config;
  options.add("accel_sigma_mps2", &config.accel_sigma_mps2, "white acceleration noise (m/s^2)").min(0.0, false);
  options.add("range_sigma_m", &config.range_sigma_m, "range noise when the message has none (m)").min(0.0, false);
  options.parse();
  return std::make_unique<ConstantVelocity>(config);
}

}  // namespace

ROAM_DEFINE_PLUGIN("constant_velocity", "constant-velocity range-only filter (out-of-tree example)",
                   makeConstantVelocity)
