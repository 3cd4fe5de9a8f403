// Dead reckoning: the floor every SLAM estimator must beat.
//
// Model: from the known start pose (INITIAL_POSE, or the origin if none is given), each
// odometry step (d, dtheta) moves the robot forward along its heading and then turns it:
//   x_{k+1} = x_k + d cos(theta_k),  y_{k+1} = y_k + d sin(theta_k),  theta_{k+1} = theta_k + dtheta.
// (The same convention as GTSAM's Pose2.compose(Pose2(d, 0, dtheta)).) Ranges are ignored.
// Headings are published wrapped to (-pi, pi].
#pragma once

#include "roam/estimator.hpp"

namespace roam {

struct DeadReckoningConfig {
  // Odometry steps longer than this are rejected as jumps.
  double max_step_m = 10.0;
};

class DeadReckoning : public Estimator {
 public:
  explicit DeadReckoning(const DeadReckoningConfig& config) : config_(config) {}

  void setInitialPose(const Pose& start) override;
  void addOdometry(const Odometry& odometry) override;
  void addRange(const Range& range) override;
  bool trajectory(bool force, Path* path) override;

  const Path& path() const { return path_; }

 private:
  DeadReckoningConfig config_;
  Path path_;  // path_[0] is the start pose once known
};

}  // namespace roam
