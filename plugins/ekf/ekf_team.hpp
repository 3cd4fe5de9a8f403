// The EKF's centralised team filter: every robot's pose in one state (the "ekf" plugin in a team
// run, [team] robots = ...). Small and separate from the one-robot filter (EkfSlam): no beacon
// SLAM, no calibration states, no recovery rules.
//
// Model. State x = (x_0, y_0, theta_0, ..., x_{N-1}, y_{N-1}, theta_{N-1}), 3N, with covariance P.
//  - Anchor: each robot's start pose (INITIAL_POSE_<R>), exact (zero covariance); a robot's odometry
//    before its start pose is rejected.
//  - Predict: robot k's odometry step (u, v, w) moves its pose by the shared motion model
//    (estimation::step: straight along the heading, then the turn), with the increment's
//    covariance Q from estimation::incrementCovariance and the one-robot EKF's noise keys
//    (odo_distance_sigma_rel/_m, odo_heading_sigma_*; a reported covariance where larger). Only
//    robot k's block P_kk = F P_kk F' + G Q G' and its cross-covariances P_kj = F P_kj change.
//  - Update, a range z between robots i and j at time t: h = |p_i - p_j|, sigma = max(the range's
//    sigma, range_sigma_m). A range to a surveyed beacon m (BEACONS, whichever the anchor: the starts
//    and the survey share the team's world frame; held as known,
//    not in the state): h = |m - p_i|, its survey sigma (beacon_sigma_m) added to the range's
//    variance; with a bearing, also h_b = atan2(m - p_i) - theta_i (bearing_sigma_rad, plus the
//    survey's beacon_sigma_m / range across the line of sight).
//  - Robust: innovations beyond the chi-square gate at gate_probability (1 dof; 2 with a bearing)
//    are not applied; within it, each component whose whitened innovation e passes range_huber_k
//    has its measurement variance divided by the Huber weight k / |e| (estimation::huberWeight).
//  - Timing: a range is taken by the robots' poses at its time t. It is held until every robot it
//    involves has odometry up to t; each robot's steps are held (not predicted) while a range of
//    its within them waits, so each robot's timeline sees its steps and ranges in time order. At
//    the range, each robot is advanced part-way into the step (t0, t1] that contains t: the
//    straight part a (u, v), a = (t - t0) / (t1 - t0), with translation noise a Q_tt — exact for the
//    motion model, as the one-robot EKF does; a range at t1 sees the whole step (turn included), the
//    pose the path reports at t1. Ranges are applied in time order across the team. A robot's
//    predict changes no other robot's pose, so the mixed times of the robots in the state are
//    exact for a linear model (predict and update on disjoint blocks commute).
//  - Set aside (counted, with a note): ranges to beacons not surveyed (the team filter places no
//    beacon), ranges older than a robot's filtered time,
//    ranges involving a robot with no start pose, ranges after a robot's last odometry (at finish).
//
// Output: a pose per odometry step (robot set, covariance its 3x3 block); the filtered paths.
#pragma once

#include <cstdint>
#include <deque>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ekf_config.hpp"
#include "roam/types.hpp"

namespace roam {
namespace ekf {

class EkfTeam {
 public:
  // Counts of what the ranges did, by kind (diagnostics).
  struct Counts {
    int64_t robot_ranges_used = 0, robot_ranges_gated = 0, robot_ranges_downweighted = 0;
    int64_t beacon_ranges_used = 0, beacon_ranges_gated = 0, beacon_ranges_downweighted = 0;
    int64_t bearings_used = 0;
    int64_t set_aside_unsurveyed = 0, set_aside_late = 0, set_aside_unstarted = 0, set_aside_after_end = 0;
  };

  EkfTeam(const EkfConfig& config, const std::vector<std::string>& robots);

  // Each returns "" if the input was taken, else why it was not, naming the robot ("robot B before
  // its start pose"; the estimator prefixes the input: "odometry: robot B ...").
  std::string setInitialPose(const Pose& start);
  void setBeacons(const Map& surveyed);
  std::string addOdometry(const Odometry& odometry);
  std::string addRange(const Range& range);
  // End of input: the ranges still held are applied where their robots' odometry reaches them
  // (the rest set aside), and every step still held is predicted.
  void finish();

  // Poses of the steps predicted since the last call (robot set), oldest first.
  Path takePoses();
  // Every robot's filtered path (start pose, then one pose per odometry step), robot by robot.
  Path paths() const;
  const Counts& counts() const { return counts_; }
  // The choices the user should hear of at the end of the run.
  std::vector<std::string> notes() const;
  const Eigen::VectorXd& mean() const { return x_; }
  const Eigen::MatrixXd& covariance() const { return P_; }
  size_t robotCount() const { return robots_.size(); }

 private:
  struct Robot {
    bool started = false;
    int64_t state_utime = 0;     // the time of the pose in the state
    int64_t last_odometry_utime = 0;
    std::deque<Odometry> steps;  // received, not yet predicted through
    int64_t step_start_utime = 0;  // start of steps.front()
    double done = 0.0;             // fraction of steps.front() already predicted (its straight part)
    Path path;                     // filtered: start pose, then one per predicted step
  };

  std::string robotProblem(int robot, const char* role) const;
  void drain(bool at_end);
  bool ready(const Range& range, bool at_end) const;
  // Predicts robot k's held steps that end at or before utime (all: utime = max).
  void predictThrough(int k, int64_t utime);
  // Moves robot k's pose to time t inside its front held step (its straight part only).
  void advanceInto(int k, int64_t utime);
  void completeFrontStep(int k);
  void predictRobot(int k, const Odometry& increment, const Eigen::Matrix3d& Q);
  Eigen::Matrix3d stepNoise(const Odometry& odometry, double dt_s) const;
  void apply(const Range& range);
  // A scalar or 2-vector EKF update on the state's rows; false if gated.
  bool update(const Eigen::VectorXd& innovation, const Eigen::MatrixXd& H, Eigen::MatrixXd R, bool* downweighted);
  Pose poseOf(int k, int64_t utime) const;

  EkfConfig config_;
  std::vector<std::string> robots_;
  std::vector<Robot> robot_;
  std::map<int, Beacon> surveyed_;
  Eigen::VectorXd x_;
  Eigen::MatrixXd P_;
  // Held ranges by time (stable within a time: arrival order).
  std::multimap<int64_t, Range> held_;
  double gate_1dof_ = 0.0, gate_2dof_ = 0.0;
  Path pending_poses_;
  Counts counts_;
};

}  // namespace ekf
}  // namespace roam
