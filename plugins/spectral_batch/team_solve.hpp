// The team solve: one nonlinear least-squares problem over every robot of a team (no LCM).
//
// Unknowns: each robot r's poses world_T_robot x_r,k = (x_m, y_m, heading_rad) at its start and at
// the end of each odometry step k; its odometry calibration c_r = (distance scale s_r,
// heading-rate bias b_r) of estimation/motion_model.hpp; the range calibration of the ranges
// between robots, c_rr = (s, o) (held at (1, 0) by default: see TeamSolveOptions), and of the ranges to beacons, c_b, each with the shared priors
// (calibration_priors.hpp). Surveyed beacons are held at the survey; a beacon the survey lacks is
// placed from its ranges (the consensus of their circles at the dead-reckoned positions) and solved.
//
// Cost (Ceres' 1/2 sum; residuals whitened, robust loss rho on every range and bearing):
//   sum_r sum_k |r_odo(x_r,k, x_r,k+1, c_r)|^2               OdometryResidual (batch_residuals.hpp)
// + sum_r |r_prior(c_r)|^2                                    OdometryCalibrationPrior
// + sum_(i,j,t) rho(((s_rr |p_i(t) - p_j(t)| + o_rr - r) / (f_rr sigma))^2)  a range between robots
// + sum_(r,m,t) rho(((s_b |m - p_r(t)| + o_b - r) / (f_b sigma))^2)         a range to beacon m
// + |((s - 1) / sigma_s, o / sigma_o)|^2 for each range calibration
// + sum_(r,m,t) rho((wrap(atan2(m - p_r(t)) - th_r(t) - beta) / (f_b sigma / max(r, sigma)))^2)
// where p_r(t) = p_r,k + alpha (p_r,k+1 - p_r,k), alpha = (t - t_k) / (t_k+1 - t_k), is robot r's
// position interpolated linearly along the step containing t (and th_r(t) its heading, the same
// way along the wrapped turn of the step). The bearing's sigma is the line-of-sight model of the
// pyfg importer: a sighting's isotropic position sigma seen across a distance r subtends
// sigma / r radians (floored at r = sigma: nearer, a bearing says next to nothing, ~1 rad).
//
// The odometry's whitening is its increment covariance (estimation::incrementCovariance: the
// message's covariance floored by options.motion_noise), with the translation rows scaled by
// 1 / f_t and the heading row by 1 / f_h. The noise factors f_t, f_h, f_rr, f_b are learned from
// the data: after a solve, each group's whitened squares over its redundancy number
// (batch_redundancy.hpp) scales its factor, and the problem is solved again from the solution.
//
// Gauge: each robot's start pose that is known (TeamRobot::start_known) is held constant. A robot
// whose start is not known is placed first from its ranges to what is placed (team_starts.hpp)
// and its start is then solved with the rest; one its ranges cannot place keeps its own frame
// (its start at the origin), out of the solve. With no start known and no beacon surveyed,
// robot 0's start is held where it was given, and the team's frame is robot 0's.
#pragma once

#include <Eigen/Core>
#include <array>
#include <functional>
#include <string>
#include <vector>

#include "roam/calibration_priors.hpp"
#include "roam/estimation/motion_model.hpp"
#include "roam/estimation/start_registration.hpp"
#include "roam/types.hpp"

namespace roam {
namespace spectral_batch {

struct TeamRobot {
  Pose start;                        // world_T_robot at start.utime; step 0 begins there
  bool start_known = true;           // false: start's x, y, heading are not used (utime is)
  std::vector<Odometry> odometry;    // in time order; step k ends at odometry[k].utime
  std::vector<Range> beacon_ranges;  // other_robot = -1, beacon_id in the survey; some with bearing
};

struct TeamInput {
  std::vector<TeamRobot> robots;    // the team: robot r is robots[r]
  std::vector<Range> robot_ranges;  // robot and other_robot index robots
  Map beacons;                      // surveyed (may be empty)
};

struct TeamSolveOptions {
  // The odometry noise where a message states none, and the floor of a stated one.
  estimation::MotionNoise motion_noise;
  // If set, each step's increment covariance instead (the plugin gives the one-robot batch's own,
  // batch_problem.hpp odometryCovariance, so both solves read odometry alike).
  std::function<Eigen::Matrix3d(const Odometry&, double dt_s)> increment_covariance;
  double range_sigma_m = 0.1;  // where a range states none (sigma_m <= 0)
  bool estimate_odometry_calibration = true;
  // Calibration priors (<= 0: none): the shared ones (calibration_priors.hpp).
  double distance_scale_prior_sigma = kDistanceScalePriorSigma;
  double heading_rate_bias_prior_sigma_rad_s = kHeadingRateBiasPriorSigma_rad_s;
  // Huber's scale on the whitened range and bearing residuals: see team_solve.cpp.
  double huber_scale = 2.0;
  // Re-estimations of the noise factors after the first solve, each followed by a warm re-solve.
  int noise_rounds = 2;
  bool use_beacon_ranges = true;
  // Beacons the survey lacks are placed from their ranges (team_solve.cpp) and solved for.
  bool place_unsurveyed_beacons = true;
  // The ranges to beacons have a scale and offset, s |d| + o, with the shared priors
  // (calibration_priors.hpp); off: (1, 0). The ranges between robots have their own, held at
  // (1, 0) unless estimate_robot_range_calibration: between robots alone a range scale trades with
  // the robots' odometry distance scales (the team drawn larger about its starts explains both),
  // so it is barely observable - on a synthetic team with no beacon, estimating it took the team
  // from 3.76 m to 6.45 m against dead reckoning's 4.18.
  bool estimate_range_calibration = true;
  bool estimate_robot_range_calibration = false;
  double range_scale_prior_sigma = kRangeScalePriorSigma;
  double range_offset_prior_sigma_m = kRangeOffsetPriorSigma_m;
  int max_iterations = 200;
  // Every solve stops at a relative cost change of 1e-6 (Ceres' default). On MR.CLAM 6 the last
  // solve went on for 111 iterations to 1e-10 (16.1 s of CPU in roam-run) and 26 to 1e-6 (7.4 s):
  // the team's mean error moved by 2e-5 m. Exact data still converge to the gradient and
  // parameter tolerances (the cost falls by orders of magnitude an iteration).
  double function_tolerance = 1e-6;
  double gradient_tolerance = 1e-12;
  double parameter_tolerance = 1e-10;
};

// Where a robot's start pose came from.
struct TeamStart {
  enum class Source { kGiven, kFound, kNotFound };
  Source source = Source::kGiven;
  // The last registration tried (none: status kTooFew with 0 ranges). kFound: its start is the
  // solve's initial guess.
  estimation::StartRegistration registration;
};

struct TeamNoiseFactors {
  double odometry_translation = 1.0;
  double odometry_heading = 1.0;
  double robot_range = 1.0;
  double beacon = 1.0;   // ranges to beacons
  double bearing = 1.0;  // bearings to beacons (a sighting's line-of-sight sigma across its range)
};

struct TeamSummary {
  double initial_cost = 0.0;  // of the first solve, from dead reckoning
  double final_cost = 0.0;    // of the last solve
  int iterations = 0;         // over every solve
  int solves = 0;
  double time_s = 0.0;        // Ceres' wall time over every solve (single thread: its CPU time)
  bool usable = false;
  bool converged = false;     // the last solve stopped on a tolerance
  int poses = 0;
  int robot_ranges_used = 0, robot_ranges_downweighted = 0;
  int beacon_ranges_used = 0, beacon_ranges_downweighted = 0;
  int bearings_used = 0, bearings_downweighted = 0;
  TeamNoiseFactors noise;     // at the last solve
  std::string report;         // one line per solve
};

struct TeamResult {
  std::vector<Path> paths;  // per robot, one pose per odometry time (start included), robot set
  Map beacons;              // the survey, as held, then the beacons placed from their ranges
  std::array<double, 2> robot_range_calibration{1.0, 0.0};   // scale, offset_m
  std::array<double, 2> beacon_range_calibration{1.0, 0.0};  // scale, offset_m
  std::vector<estimation::OdometryCalibration> odometry_calibration;  // per robot
  std::vector<TeamStart> starts;   // per robot
  TeamSummary summary;
  std::vector<std::string> notes;  // what was set aside and why
};

// Throws std::invalid_argument on bad input (an index out of range, a non-finite value, time
// going backwards).
TeamResult solveTeam(const TeamInput& input, const TeamSolveOptions& options = {});

}  // namespace spectral_batch
}  // namespace roam
