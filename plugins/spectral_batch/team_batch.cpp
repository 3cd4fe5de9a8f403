#include "team_batch.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

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
    robot.start.utime = odometry.utime;  // no start pose: set at finish(), one step before this one
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
  for (size_t r = 0; r < robots_.size(); ++r) {
    TeamRobot& robot = input_.robots[r];
    robot.start_known = have_start_[r];
    // No start pose: the start is one step before the first odometry, as long as the step after.
    const auto& odometry = robot.odometry;
    if (!have_start_[r] && !odometry.empty())
      robot.start.utime =
          odometry.front().utime - std::max<int64_t>(1, odometry.size() > 1 ? odometry[1].utime - odometry[0].utime : 1);
  }
  TeamSolveOptions options;
  options.range_sigma_m = config_.range_sigma_m;
  options.estimate_odometry_calibration = config_.estimate_odometry_calibration;
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

namespace {

std::string fixed(double value, int decimals) {
  std::ostringstream out;
  out.precision(decimals);
  out << std::fixed << value;
  return out.str();
}

constexpr double kDegreesPerRadian = 57.29577951308232;

// Where robot `name`'s start came from, when it was not given.
std::string startNote(const std::string& name, const TeamStart& start) {
  const estimation::StartRegistration& found = start.registration;
  const std::string head = "robot " + name + " had no INITIAL_POSE_" + name + ": ";
  using Status = estimation::StartRegistration::Status;
  if (start.source == TeamStart::Source::kFound) {
    return head + "its start was found from " + std::to_string(found.ranges) + " range(s) to robots and beacons placed before it, (" +
           fixed(found.start.x(), 2) + ", " + fixed(found.start.y(), 2) + ") m heading " +
           fixed(found.start.z() * kDegreesPerRadian, 1) + " deg, +/- " +
           fixed(std::sqrt(0.5 * (found.covariance(0, 0) + found.covariance(1, 1))), 2) + " m and " +
           fixed(std::sqrt(found.covariance(2, 2)) * kDegreesPerRadian, 1) + " deg, then solved with the team (its dead reckoning has no frame: the self-check cannot judge its path)";
  }
  std::string why;
  if (found.ranges == 0) {
    why = "it has no range to a robot or surveyed beacon whose place is known";
  } else if (found.status == Status::kTooFew) {
    why = "its " + std::to_string(found.ranges) + " range(s) to what is placed are too few to fix a start";
  } else if (found.status == Status::kAmbiguous) {
    why = "its " + std::to_string(found.ranges) + " range(s) cannot tell its heading: " +
          fixed(found.start.z() * kDegreesPerRadian, 0) + " and " + fixed(found.rival_heading_rad * kDegreesPerRadian, 0) +
          " deg fit alike (one beacon, or one robot seen along a line, fixes no heading)";
  } else {
    why = "its ranges to what is placed have no solution";
  }
  return head + "its start cannot be found from the ranges (" + why +
         "): its path is its dead reckoning from the origin with heading 0, not in the team's frame, and its ranges "
         "are set aside; give its start (INITIAL_POSE_" + name + ", [team] starts) or more ranges";
}

}  // namespace

std::vector<std::string> TeamBatch::notes() const {
  std::vector<std::string> notes;
  for (size_t r = 0; r < robots_.size(); ++r) {
    if (have_start_[r]) continue;
    if (result_) {
      notes.push_back(startNote(robots_[r], result_->starts[r]));
    } else {
      notes.push_back("robot " + robots_[r] + " had no INITIAL_POSE_" + robots_[r] + ": its start is found from its ranges at the end");
    }
  }
  if (result_) notes.insert(notes.end(), result_->notes.begin(), result_->notes.end());
  return notes;
}

}  // namespace spectral_batch
}  // namespace roam
