// Dead reckoning: the floor every SLAM estimator must beat.
//
// Model: from the known start pose (INITIAL_POSE, or the origin if none is given), each
// odometry step (forward u, lateral v, turn w) is composed onto the pose by the shared motion
// model with no calibration (roam/estimation/motion_model.hpp):
//   x' = x + u cos(theta) - v sin(theta),  y' = y + u sin(theta) + v cos(theta),  theta' = theta + w
// (GTSAM's Pose2.compose(Pose2(u, v, w))). Ranges are ignored. Headings are published wrapped to
// (-pi, pi]. Jumps and time going backwards are rejected by the SDK (max_speed_mps).
#pragma once

#include "roam/estimator.hpp"

namespace roam::deadreckoning {

class DeadReckoning : public Estimator {
 public:

  void setInitialPose(const Pose& start) override;
  void addOdometry(const Odometry& odometry) override;
  void addRange(const Range& range) override;
  bool trajectory(bool force, Path* path) override;

  const Path& path() const { return path_; }

 private:
  Path path_;  // path_[0] is the start pose once known
};

}  // namespace roam::deadreckoning
