#include "dead_reckoning.hpp"

#include <cmath>

namespace roam {

void DeadReckoning::setInitialPose(const Pose& start) {
  if (!path_.empty()) return;  // the start is fixed once integration has begun
  Pose first = start;
  first.heading_rad = wrapAngle(first.heading_rad);
  path_.push_back(first);
  setState(EstimatorState::kTracking);
  emitPose(first);
}

void DeadReckoning::addOdometry(const Odometry& odometry) {
  if (odometry.delta_distance_m < 0.0) {
    rejectOdometry("negative distance");
    return;
  }
  if (odometry.delta_distance_m > config_.max_step_m) {
    rejectOdometry("step longer than max_step_m");
    return;
  }
  if (path_.empty()) {
    // No INITIAL_POSE: start at the origin, one step before this odometry.
    Pose origin;
    origin.utime = odometry.utime;
    path_.push_back(origin);
    setState(EstimatorState::kTracking);
  }
  if (odometry.utime < path_.back().utime) {
    rejectOdometry("time went backwards");
    return;
  }
  const Pose& last = path_.back();
  Pose next;
  next.utime = odometry.utime;
  next.x_m = last.x_m + odometry.delta_distance_m * std::cos(last.heading_rad);
  next.y_m = last.y_m + odometry.delta_distance_m * std::sin(last.heading_rad);
  next.heading_rad = wrapAngle(last.heading_rad + odometry.delta_heading_rad);
  path_.push_back(next);
  acceptOdometry();
  emitPose(next);
}

void DeadReckoning::addRange(const Range& /*range*/) {
  // Dead reckoning ignores ranges; they are neither accepted nor rejected.
}

bool DeadReckoning::trajectory(bool /*force*/, Path* path) {
  if (path_.empty()) return false;
  *path = path_;
  return true;
}

}  // namespace roam
