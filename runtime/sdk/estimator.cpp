#include "roam/estimator.hpp"

#include <utility>

namespace roam {

Path Estimator::takePoses() {
  Path out;
  out.swap(pending_poses_);
  return out;
}

bool Estimator::takeMap(Map* map) {
  if (!map_changed_) return false;
  *map = map_;
  map_changed_ = false;
  return true;
}

void Estimator::rejectOdometry(const std::string& reason) {
  ++odometry_rejected_;
  last_rejection_ = "odometry: " + reason;
  ++rejections_[last_rejection_];
}

void Estimator::rejectInput(const std::string& input, const std::string& reason) {
  last_rejection_ = input + ": " + reason;
  ++rejections_[last_rejection_];
}

void Estimator::rejectRange(const std::string& reason) {
  ++ranges_rejected_;
  last_rejection_ = "range: " + reason;
  ++rejections_[last_rejection_];
}

}  // namespace roam
