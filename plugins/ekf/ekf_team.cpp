// The EKF's centralised team filter (model: ekf_team.hpp).
#include "ekf_team.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <sstream>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "roam/estimation/motion_model.hpp"
#include "roam/estimation/range_model.hpp"

namespace roam {
namespace ekf {

namespace {

// Below this the two positions of a range coincide and its direction is undefined (its
// Jacobian): the range is not applied. Far below any range a radio or a camera reports.
constexpr double kMinLinearisableRange_m = 1e-6;

}  // namespace

EkfTeam::EkfTeam(const EkfConfig& config, const std::vector<std::string>& robots)
    : config_(config), robots_(robots), robot_(robots.size()) {
  const Eigen::Index n = 3 * static_cast<Eigen::Index>(robots.size());
  x_ = Eigen::VectorXd::Zero(n);
  P_ = Eigen::MatrixXd::Zero(n, n);
  gate_1dof_ = chiSquareQuantile(1, config.gate_probability);
  gate_2dof_ = chiSquareQuantile(2, config.gate_probability);
}

std::string EkfTeam::robotProblem(int robot, const char* role) const {
  if (robot < 0 || robot >= static_cast<int>(robots_.size()))
    return std::string(role) + " " + std::to_string(robot) + " is not in the team of " + std::to_string(robots_.size());
  return "";
}

std::string EkfTeam::setInitialPose(const Pose& start) {
  if (std::string problem = robotProblem(start.robot, "robot"); !problem.empty()) return problem;
  Robot& r = robot_[start.robot];
  if (r.started) return "";  // the start is fixed once given (as the one-robot EKF)
  r.started = true;
  r.state_utime = r.last_odometry_utime = r.step_start_utime = start.utime;
  x_.segment<3>(3 * start.robot) << start.x_m, start.y_m, start.heading_rad;
  Pose first = poseOf(start.robot, start.utime);
  r.path.push_back(first);
  pending_poses_.push_back(first);
  return "";
}

void EkfTeam::setBeacons(const Map& surveyed) {
  // Every robot's start and the survey share the team's world frame (INITIAL_POSE_<robot>, BEACONS),
  // so the survey is used whichever the anchor, as the team solve uses it.
  for (const Beacon& beacon : surveyed) surveyed_[beacon.id] = beacon;
}

std::string EkfTeam::addOdometry(const Odometry& odometry) {
  if (std::string problem = robotProblem(odometry.robot, "robot"); !problem.empty()) return problem;
  Robot& r = robot_[odometry.robot];
  if (!r.started) return "robot " + robots_[odometry.robot] + " before its start pose";
  if (odometry.utime < r.last_odometry_utime) return "robot " + robots_[odometry.robot] + ": time went backwards";
  r.steps.push_back(odometry);
  r.last_odometry_utime = odometry.utime;
  drain(false);
  return "";
}

std::string EkfTeam::addRange(const Range& range) {
  if (std::string problem = robotProblem(range.robot, "robot"); !problem.empty()) return problem;
  if (range.toRobot()) {
    if (std::string problem = robotProblem(range.other_robot, "other robot"); !problem.empty()) return problem;
    if (range.other_robot == range.robot) return "from robot " + robots_[range.robot] + " to itself";
  }
  if (!(range.range_m > 0.0)) return "range not positive";
  if (!range.toRobot() && !surveyed_.count(range.beacon_id)) {
    ++counts_.set_aside_unsurveyed;  // the team filter places no beacon
    return "";
  }
  if (!robot_[range.robot].started || (range.toRobot() && !robot_[range.other_robot].started)) {
    ++counts_.set_aside_unstarted;
    return "";
  }
  held_.emplace(range.utime, range);
  drain(false);
  return "";
}

void EkfTeam::finish() {
  drain(true);
  for (size_t k = 0; k < robot_.size(); ++k) predictThrough(static_cast<int>(k), std::numeric_limits<int64_t>::max());
}

bool EkfTeam::ready(const Range& range, bool at_end) const {
  if (at_end) return true;
  if (robot_[range.robot].last_odometry_utime < range.utime) return false;
  return !range.toRobot() || robot_[range.other_robot].last_odometry_utime >= range.utime;
}

void EkfTeam::drain(bool at_end) {
  // Ranges in time order, each robot's in its own order: a range waits while its robots' odometry
  // has not reached it, and holds back every later range of those robots.
  std::set<int> blocked;
  for (auto it = held_.begin(); it != held_.end();) {
    const Range& range = it->second;
    const bool other_blocked = range.toRobot() && blocked.count(range.other_robot);
    if (blocked.count(range.robot) || other_blocked || !ready(range, at_end)) {
      blocked.insert(range.robot);
      if (range.toRobot()) blocked.insert(range.other_robot);
      ++it;
      continue;
    }
    std::vector<int> involved{range.robot};
    if (range.toRobot()) involved.push_back(range.other_robot);
    bool usable = true;
    for (int k : involved) {
      predictThrough(k, range.utime);
      if (robot_[k].state_utime > range.utime) {
        ++counts_.set_aside_late;
        usable = false;
        break;
      }
      if (robot_[k].state_utime < range.utime && robot_[k].steps.empty()) {
        ++counts_.set_aside_after_end;  // at the end of input: no odometry reaches it
        usable = false;
        break;
      }
    }
    if (usable) {
      for (int k : involved) advanceInto(k, range.utime);
      apply(range);
    }
    it = held_.erase(it);
  }
  // Each robot's steps up to its first held range (a step ending at a range's time included).
  if (at_end) return;
  for (size_t k = 0; k < robot_.size(); ++k) {
    int64_t limit = std::numeric_limits<int64_t>::max();
    for (const auto& [utime, range] : held_) {
      if (range.robot == static_cast<int>(k) || range.other_robot == static_cast<int>(k)) {
        limit = utime;
        break;
      }
    }
    predictThrough(static_cast<int>(k), limit);
  }
}

void EkfTeam::predictThrough(int k, int64_t utime) {
  while (!robot_[k].steps.empty() && robot_[k].steps.front().utime <= utime) completeFrontStep(k);
}

Eigen::Matrix3d EkfTeam::stepNoise(const Odometry& odometry, double dt_s) const {
  return estimation::incrementCovariance(odometry, dt_s, configuredMotionNoise(config_, odometry));
}

void EkfTeam::advanceInto(int k, int64_t utime) {
  Robot& r = robot_[k];
  if (r.steps.empty() || r.state_utime >= utime) return;
  const Odometry& odo = r.steps.front();
  const int64_t t0 = r.step_start_utime, t1 = odo.utime;
  const double fraction = std::clamp(static_cast<double>(utime - t0) / static_cast<double>(t1 - t0), 0.0, 1.0);
  if (fraction > r.done) {
    const Eigen::Matrix3d Q = stepNoise(odo, std::max<int64_t>(0, t1 - t0) * 1e-6);
    Odometry part;  // straight: no turn before the step's end
    part.forward_m = (fraction - r.done) * odo.forward_m;
    part.lateral_m = (fraction - r.done) * odo.lateral_m;
    Eigen::Matrix3d Q_part = Eigen::Matrix3d::Zero();
    Q_part.topLeftCorner<2, 2>() = (fraction - r.done) * Q.topLeftCorner<2, 2>();
    predictRobot(k, part, Q_part);
    r.done = fraction;
  }
  r.state_utime = utime;
}

void EkfTeam::completeFrontStep(int k) {
  Robot& r = robot_[k];
  const Odometry odo = r.steps.front();
  r.steps.pop_front();
  const double dt_s = std::max<int64_t>(0, odo.utime - r.step_start_utime) * 1e-6;
  const Eigen::Matrix3d Q = stepNoise(odo, dt_s);
  // The rest of the step: translation (1 - done) (u, v) and the whole turn.
  const double rest = 1.0 - r.done;
  Odometry increment = odo;
  increment.forward_m = rest * odo.forward_m;
  increment.lateral_m = rest * odo.lateral_m;
  Eigen::Matrix3d Q_rest = Q;
  Q_rest.topLeftCorner<2, 2>() *= rest;
  Q_rest.topRightCorner<2, 1>() *= rest;
  Q_rest.bottomLeftCorner<1, 2>() *= rest;
  predictRobot(k, increment, Q_rest);
  r.done = 0.0;
  r.step_start_utime = r.state_utime = odo.utime;
  const Pose pose = poseOf(k, odo.utime);
  r.path.push_back(pose);
  pending_poses_.push_back(pose);
}

void EkfTeam::predictRobot(int k, const Odometry& increment, const Eigen::Matrix3d& Q) {
  const Eigen::Index row = 3 * k;
  const Eigen::Vector3d pose = x_.segment<3>(row);
  const estimation::StepJacobians J = estimation::stepJacobians(pose, increment, 0.0);
  x_.segment<3>(row) = estimation::step(pose, estimation::calibratedIncrement(increment, 0.0));
  // P_kk -> F P_kk F' + G Q G', P_kj -> F P_kj: the other robots' blocks are untouched.
  P_.middleRows<3>(row) = (J.wrt_pose * P_.middleRows<3>(row)).eval();
  P_.middleCols<3>(row) = (P_.middleCols<3>(row) * J.wrt_pose.transpose()).eval();
  P_.block<3, 3>(row, row) += J.wrt_increment * Q * J.wrt_increment.transpose();
}

void EkfTeam::apply(const Range& range) {
  const Eigen::Index n = x_.size();
  const Eigen::Index i = 3 * range.robot;
  const double sigma_m = std::max(range.sigma_m, config_.range_sigma_m);
  bool downweighted = false;
  if (range.toRobot()) {
    const Eigen::Index j = 3 * range.other_robot;
    const Eigen::Vector2d d = x_.segment<2>(i) - x_.segment<2>(j);
    const double h_m = d.norm();
    if (h_m < kMinLinearisableRange_m) {
      ++counts_.robot_ranges_gated;
      return;
    }
    Eigen::MatrixXd H = Eigen::MatrixXd::Zero(1, n);
    H.block<1, 2>(0, i) = d.transpose() / h_m;
    H.block<1, 2>(0, j) = -d.transpose() / h_m;
    Eigen::VectorXd innovation(1);
    innovation << range.range_m - h_m;
    Eigen::MatrixXd R(1, 1);
    R << sigma_m * sigma_m;
    if (!update(innovation, H, R, &downweighted)) {
      ++counts_.robot_ranges_gated;
      return;
    }
    ++counts_.robot_ranges_used;
    if (downweighted) ++counts_.robot_ranges_downweighted;
    return;
  }
  const Beacon& beacon = surveyed_.at(range.beacon_id);
  const Eigen::Vector2d d = Eigen::Vector2d(beacon.x_m, beacon.y_m) - x_.segment<2>(i);
  const double r_m = d.norm();
  if (r_m < kMinLinearisableRange_m) {
    ++counts_.beacon_ranges_gated;
    return;
  }
  const int rows = range.has_bearing ? 2 : 1;
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(rows, n);
  Eigen::VectorXd innovation(rows);
  Eigen::MatrixXd R = Eigen::MatrixXd::Zero(rows, rows);
  // The survey's sigma (per axis) adds beacon_sigma_m^2 along the line of sight to the range and
  // (beacon_sigma_m / r)^2 across it to the bearing: the beacon is known, not estimated.
  const double survey_var_m2 = config_.beacon_sigma_m * config_.beacon_sigma_m;
  H.block<1, 2>(0, i) = -d.transpose() / r_m;
  innovation[0] = range.range_m - r_m;
  R(0, 0) = sigma_m * sigma_m + survey_var_m2;
  if (range.has_bearing) {
    const double r2 = r_m * r_m;
    H(1, i) = d.y() / r2;
    H(1, i + 1) = -d.x() / r2;
    H(1, i + 2) = -1.0;
    innovation[1] = wrapAngle(range.bearing_rad - (std::atan2(d.y(), d.x()) - x_[i + 2]));
    R(1, 1) = config_.bearing_sigma_rad * config_.bearing_sigma_rad + survey_var_m2 / r2;
  }
  if (!update(innovation, H, R, &downweighted)) {
    ++counts_.beacon_ranges_gated;
    return;
  }
  ++counts_.beacon_ranges_used;
  if (range.has_bearing) ++counts_.bearings_used;
  if (downweighted) ++counts_.beacon_ranges_downweighted;
}

bool EkfTeam::update(const Eigen::VectorXd& innovation, const Eigen::MatrixXd& H, Eigen::MatrixXd R, bool* downweighted) {
  const Eigen::MatrixXd HP = H * P_;
  Eigen::MatrixXd S = HP * H.transpose() + R;
  const double nis = innovation.dot(S.ldlt().solve(innovation));
  const double gate = innovation.size() == 1 ? gate_1dof_ : gate_2dof_;
  if (!(nis <= gate)) return false;
  if (config_.range_huber_k > 0.0) {
    for (Eigen::Index c = 0; c < innovation.size(); ++c) {
      const double weight = estimation::huberWeight(innovation[c] / std::sqrt(S(c, c)), config_.range_huber_k);
      if (weight < 1.0) {
        R(c, c) /= weight;
        *downweighted = true;
      }
    }
    if (*downweighted) S = HP * H.transpose() + R;
  }
  const Eigen::MatrixXd K = S.ldlt().solve(HP).transpose();  // P H' S^-1
  x_ += K * innovation;
  // Joseph form: (I - K H) P (I - K H)' + K R K', symmetric and positive semi-definite.
  const Eigen::MatrixXd IKH = Eigen::MatrixXd::Identity(x_.size(), x_.size()) - K * H;
  P_ = IKH * P_ * IKH.transpose() + K * R * K.transpose();
  P_ = 0.5 * (P_ + P_.transpose()).eval();
  return true;
}

Pose EkfTeam::poseOf(int k, int64_t utime) const {
  Pose pose;
  pose.utime = utime;
  pose.robot = k;
  pose.x_m = x_[3 * k];
  pose.y_m = x_[3 * k + 1];
  pose.heading_rad = wrapAngle(x_[3 * k + 2]);
  const Eigen::Matrix3d block = P_.block<3, 3>(3 * k, 3 * k);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) pose.covariance[3 * r + c] = block(r, c);
  return pose;
}

Path EkfTeam::takePoses() {
  Path out;
  out.swap(pending_poses_);
  return out;
}

Path EkfTeam::paths() const {
  Path out;
  for (const Robot& r : robot_) out.insert(out.end(), r.path.begin(), r.path.end());
  return out;
}

std::vector<std::string> EkfTeam::notes() const {
  std::vector<std::string> out;
  const auto say = [&](int64_t count, const std::string& text) {
    if (count > 0) out.push_back(std::to_string(count) + " " + text);
  };
  say(counts_.set_aside_unsurveyed, "ranges to beacons not in BEACONS set aside: the team filter places no beacon");
  say(counts_.set_aside_late, "ranges older than their robot's filtered pose set aside (they came after later odometry)");
  say(counts_.set_aside_unstarted, "ranges of a robot with no start pose (INITIAL_POSE_<robot>) set aside");
  say(counts_.set_aside_after_end, "ranges after their robot's last odometry set aside");
  return out;
}

}  // namespace ekf
}  // namespace roam
