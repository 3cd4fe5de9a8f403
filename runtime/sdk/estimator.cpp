#include "roam/estimator.hpp"

#include <stdexcept>
#include <utility>

namespace roam {

void Estimator::setTeam(const std::vector<std::string>& robots) {
  throw std::runtime_error("this estimator estimates one robot, not a team of " + std::to_string(robots.size()));
}

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
  ++outside_.odometry;
  outside_.last = last_rejection_;
  ++outside_.named[last_rejection_];
}

void Estimator::rejectInput(const std::string& input, const std::string& reason) {
  last_rejection_ = input + ": " + reason;
  ++rejections_[last_rejection_];
  outside_.last = last_rejection_;
  ++outside_.named[last_rejection_];
}

void Estimator::rejectRange(const std::string& reason) {
  ++ranges_rejected_;
  last_rejection_ = "range: " + reason;
  ++rejections_[last_rejection_];
  ++outside_.ranges;
  outside_.last = last_rejection_;
  ++outside_.named[last_rejection_];
}

void Estimator::reportAs(const Estimator& member) {
  state_ = member.state_;
  odometry_accepted_ = member.odometry_accepted_;
  ranges_accepted_ = member.ranges_accepted_;
  odometry_rejected_ = member.odometry_rejected_ + outside_.odometry;
  ranges_rejected_ = member.ranges_rejected_ + outside_.ranges;
  rejections_ = member.rejections_;
  for (const auto& [reason, count] : outside_.named) rejections_[reason] += count;
  last_rejection_ = member.last_rejection_.empty() ? outside_.last : member.last_rejection_;
  diagnostics_ = member.diagnostics_;
}

}  // namespace roam
