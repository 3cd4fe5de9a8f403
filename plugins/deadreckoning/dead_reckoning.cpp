#include "dead_reckoning.hpp"

#include "roam/estimation/motion_model.hpp"

namespace roam::deadreckoning {

void DeadReckoning::setInitialPose(const Pose& start) {
  if (!path_.empty()) return;  // the start is fixed once integration has begun
  Pose first = start;
  first.heading_rad = wrapAngle(first.heading_rad);
  path_.push_back(first);
  setState(EstimatorState::kTracking);
  emitPose(first);
}

void DeadReckoning::addOdometry(const Odometry& odometry) {
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
  const Pose next = estimation::step(path_.back(), odometry);
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

}  // namespace roam::deadreckoning
