#include "roam/self_check.hpp"

#include <cmath>

#include "roam/se2.hpp"

namespace roam {

void SelfCheck::startPose(const Pose& start) {
  if (have_start_ || odometry_before_start_) return;
  have_start_ = true;
  Pose pose = start;
  pose.covariance.fill(kNaN);
  dead_reckoned_.assign(1, pose);
}

void SelfCheck::odometry(const Odometry& step, bool accepted) {
  if (!have_start_) {
    odometry_before_start_ = true;
    return;
  }
  if (!accepted) return;
  const Pose& last = dead_reckoned_.back();
  const double pose[3] = {last.x_m, last.y_m, last.heading_rad};
  const double increment[3] = {step.forward_m, step.lateral_m, step.delta_heading_rad};
  double next[3];
  composeIncrement(pose, increment, next);
  Pose out;
  out.utime = step.utime;
  out.x_m = next[0];
  out.y_m = next[1];
  out.heading_rad = wrapAngle(next[2]);
  dead_reckoned_.push_back(out);
}

bool SelfCheck::apply(const Estimator& estimator, Path* path) {
  if (!finished_ || !have_start_ || estimator.rangesAccepted() > 0) return false;
  bool same = path->size() == dead_reckoned_.size();
  for (size_t k = 0; same && k < path->size(); ++k)
    same = std::abs((*path)[k].x_m - dead_reckoned_[k].x_m) <= 1e-9 &&
           std::abs((*path)[k].y_m - dead_reckoned_[k].y_m) <= 1e-9;
  if (same) return false;  // dead reckoning already (the deadreckoning plugin)
  *path = dead_reckoned_;
  replaced_ = true;
  return true;
}

}  // namespace roam
