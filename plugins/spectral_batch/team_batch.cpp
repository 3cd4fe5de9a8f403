#include "team_batch.hpp"

#include "batch_problem.hpp"
#include "roam/estimation/motion_model.hpp"

namespace roam {
namespace spectral_batch {

TeamBatch::TeamBatch(const SpectralBatchConfig& config, const std::vector<std::string>& robots)
    : config_(config), robots_(robots), have_start_(robots.size(), false) {
  input_.robots.resize(robots.size());
  for (size_t r = 0; r < robots.size(); ++r) input_.robots[r].start.robot = static_cast<int>(r);
}

void TeamBatch::setInitialPose(const Pose& start) {
  const auto r = static_cast<size_t>(start.robot);
  if (have_start_[r] || !input_.robots[r].odometry.empty()) return;  // fixed once integration began
  input_.robots[r].start = start;
  have_start_[r] = true;
}

bool TeamBatch::addOdometry(const Odometry& odometry) {
  TeamRobot& robot = input_.robots[static_cast<size_t>(odometry.robot)];
  const int64_t last_utime = robot.odometry.empty() ? robot.start.utime : robot.odometry.back().utime;
  if (robot.odometry.empty() && !have_start_[static_cast<size_t>(odometry.robot)]) {
    robot.start.utime = odometry.utime;  // no start pose: the origin, one step before this one
  } else if (odometry.utime < last_utime) {
    return false;
  }
  robot.odometry.push_back(odometry);
  return true;
}

bool TeamBatch::addRange(const Range& range) {
  if (range.toRobot()) {
    input_.robot_ranges.push_back(range);
  } else {
    input_.robots[static_cast<size_t>(range.robot)].beacon_ranges.push_back(range);
  }
  return true;
}

void TeamBatch::finish() {
  TeamSolveOptions options;
  options.range_sigma_m = config_.range_sigma_m;
  options.estimate_odometry_calibration = config_.estimate_odometry_calibration;
  options.distance_scale_prior_sigma = config_.distance_scale_sigma;
  const SpectralBatchConfig config = config_;
  options.increment_covariance = [config](const Odometry& odometry, double dt_s) {
    return odometryCovariance(config, odometry, dt_s);
  };
  result_ = solveTeam(input_, options);
}

Path TeamBatch::paths() const {
  Path out;
  if (result_) {
    for (const Path& path : result_->paths) out.insert(out.end(), path.begin(), path.end());
    return out;
  }
  for (size_t r = 0; r < input_.robots.size(); ++r) {
    Pose pose = input_.robots[r].start;
    pose.robot = static_cast<int>(r);
    out.push_back(pose);
    for (const Odometry& odometry : input_.robots[r].odometry) {
      pose = estimation::step(pose, odometry);
      pose.robot = static_cast<int>(r);
      out.push_back(pose);
    }
  }
  return out;
}

std::vector<std::string> TeamBatch::notes() const {
  std::vector<std::string> notes;
  for (size_t r = 0; r < robots_.size(); ++r) {
    if (!have_start_[r])
      notes.push_back("robot " + robots_[r] + " had no INITIAL_POSE_" + robots_[r] +
                      ": its path starts at the origin with heading 0, not in the team's frame");
  }
  if (result_) notes.insert(notes.end(), result_->notes.begin(), result_->notes.end());
  return notes;
}

}  // namespace spectral_batch
}  // namespace roam
