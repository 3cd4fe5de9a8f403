#include "team_solve.hpp"

#include <ceres/ceres.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "batch_redundancy.hpp"
#include "batch_residuals.hpp"
#include "team_starts.hpp"
#include "roam/estimation/multilateration.hpp"

namespace roam {
namespace spectral_batch {
namespace {

// Robust loss. Huber at 2 whitened sigmas: the noise factors are learned from these same
// residuals, so the loss must leave the inliers' spread alone - Huber's weight is 1 within its
// scale, and at 2 sigmas only 4.6 % of Gaussian inliers are down-weighted (its efficiency on
// Gaussian data is 99 %, against 95 % at the textbook 1.345), while a range off by 10 sigmas
// still counts 5x less than under least squares. Its cost is convex: no stage of annealing is
// needed from a dead-reckoning start.
//
// Noise factors: each round scales a group's factor by sqrt(squares / redundancy). A factor is
// kept within [kMinNoiseFactor, kMaxNoiseFactor] of the stated sigmas: exact data (squares 0)
// would otherwise drive a sigma to zero and the next solve's whitening to infinity.
constexpr double kMinNoiseFactor = 1e-3;
constexpr double kMaxNoiseFactor = 1e3;
// A group whose redundancy is below this is not observed well enough to learn its noise from.
constexpr double kMinRedundancy = 1.0;

template <typename T>
T wrapped(const T& angle_rad) {
  using std::atan2;
  using std::cos;
  using std::sin;
  return atan2(sin(angle_rad), cos(angle_rad));
}

// A range between robot i, a fraction alpha_i along its step (a_i, b_i), and robot j likewise.
struct RobotRangeResidual {
  RobotRangeResidual(double range_m, double sigma_m, double alpha_i, double alpha_j)
      : range_m(range_m), sigma_m(sigma_m), alpha_i(alpha_i), alpha_j(alpha_j) {}
  template <typename T>
  bool operator()(const T* a_i, const T* b_i, const T* a_j, const T* b_j, const T* calibration, T* residual) const {
    const T x_i = a_i[0] + alpha_i * (b_i[0] - a_i[0]), y_i = a_i[1] + alpha_i * (b_i[1] - a_i[1]);
    const T other[2] = {a_j[0] + alpha_j * (b_j[0] - a_j[0]), a_j[1] + alpha_j * (b_j[1] - a_j[1])};
    const T no_offset[1] = {T(0.0)};
    residual[0] = whitenedRangeError(x_i, y_i, other, calibration, no_offset, range_m, sigma_m);
    return true;
  }
  static ceres::CostFunction* create(double range_m, double sigma_m, double alpha_i, double alpha_j) {
    return new ceres::AutoDiffCostFunction<RobotRangeResidual, 1, 3, 3, 3, 3, 2>(
        new RobotRangeResidual(range_m, sigma_m, alpha_i, alpha_j));
  }
  double range_m, sigma_m, alpha_i, alpha_j;
};

// A range to a beacon, alpha along the step (a, b), through the beacon ranges' calibration.
struct BeaconRangeResidual {
  BeaconRangeResidual(double range_m, double sigma_m, double alpha) : range_m(range_m), sigma_m(sigma_m), alpha(alpha) {}
  template <typename T>
  bool operator()(const T* a, const T* b, const T* beacon, const T* calibration, T* residual) const {
    const T x_m = a[0] + alpha * (b[0] - a[0]), y_m = a[1] + alpha * (b[1] - a[1]);
    const T no_offset[1] = {T(0.0)};
    residual[0] = whitenedRangeError(x_m, y_m, beacon, calibration, no_offset, range_m, sigma_m);
    return true;
  }
  static ceres::CostFunction* create(double range_m, double sigma_m, double alpha) {
    return new ceres::AutoDiffCostFunction<BeaconRangeResidual, 1, 3, 3, 2, 2>(
        new BeaconRangeResidual(range_m, sigma_m, alpha));
  }
  double range_m, sigma_m, alpha;
};

// The beacon's bearing in the robot frame (CCW), wrapped, whitened; the heading interpolated along
// the step's wrapped turn.
struct BearingResidual {
  BearingResidual(double bearing_rad, double sigma_rad, double alpha)
      : bearing_rad(bearing_rad), sigma_rad(sigma_rad), alpha(alpha) {}
  template <typename T>
  bool operator()(const T* a, const T* b, const T* beacon, T* residual) const {
    using std::atan2;
    const T x_m = a[0] + alpha * (b[0] - a[0]), y_m = a[1] + alpha * (b[1] - a[1]);
    const T heading_rad = a[2] + alpha * wrapped(T(b[2] - a[2]));
    residual[0] = wrapped(T(atan2(beacon[1] - y_m, beacon[0] - x_m) - heading_rad - bearing_rad)) / sigma_rad;
    return true;
  }
  static ceres::CostFunction* create(double bearing_rad, double sigma_rad, double alpha) {
    return new ceres::AutoDiffCostFunction<BearingResidual, 1, 3, 3, 2>(
        new BearingResidual(bearing_rad, sigma_rad, alpha));
  }
  double bearing_rad, sigma_rad, alpha;
};

struct RobotRangeObservation {
  int robot_i = 0, robot_j = 0;
  StepLocation at_i, at_j;
  double range_m = 0.0, sigma_m = 0.0;
};

struct BeaconObservation {
  int robot = 0;
  StepLocation at;
  int beacon = 0;  // index into the beacon blocks
  double range_m = 0.0, sigma_m = 0.0;
  bool has_bearing = false;
  double bearing_rad = 0.0;
};

bool finite(double x) { return std::isfinite(x); }

void fail(const std::string& what) { throw std::invalid_argument("solveTeam: " + what); }

void checkRange(const Range& range, const std::string& where) {
  if (!finite(range.range_m) || range.range_m < 0.0) fail(where + ": range_m not a finite distance");
  if (!finite(range.sigma_m)) fail(where + ": sigma_m not finite");
  if (range.has_bearing && !finite(range.bearing_rad)) fail(where + ": bearing_rad not finite");
}

void validate(const TeamInput& input) {
  const int num_robots = static_cast<int>(input.robots.size());
  if (num_robots == 0) fail("no robots");
  for (int r = 0; r < num_robots; ++r) {
    const TeamRobot& robot = input.robots[r];
    const std::string name = "robot " + std::to_string(r);
    if (!finite(robot.start.x_m) || !finite(robot.start.y_m) || !finite(robot.start.heading_rad))
      fail(name + ": start pose not finite");
    int64_t previous = robot.start.utime;
    for (size_t k = 0; k < robot.odometry.size(); ++k) {
      const Odometry& o = robot.odometry[k];
      if (!finite(o.forward_m) || !finite(o.lateral_m) || !finite(o.delta_heading_rad))
        fail(name + ": odometry step " + std::to_string(k) + " not finite");
      if (o.utime <= previous) fail(name + ": odometry step " + std::to_string(k) + " does not end after the one before");
      previous = o.utime;
    }
    for (size_t i = 0; i < robot.beacon_ranges.size(); ++i) {
      if (robot.beacon_ranges[i].toRobot())
        fail(name + ": beacon range " + std::to_string(i) + " names a robot (robot ranges go in robot_ranges)");
      checkRange(robot.beacon_ranges[i], name + ": beacon range " + std::to_string(i));
    }
  }
  for (size_t i = 0; i < input.robot_ranges.size(); ++i) {
    const Range& range = input.robot_ranges[i];
    const std::string name = "robot range " + std::to_string(i);
    if (range.robot < 0 || range.robot >= num_robots || range.other_robot < 0 || range.other_robot >= num_robots)
      fail(name + ": robot " + std::to_string(range.robot) + " to " + std::to_string(range.other_robot) +
           " is not a pair of the team's " + std::to_string(num_robots) + " robots");
    if (range.robot == range.other_robot) fail(name + ": a robot ranged to itself");
    checkRange(range, name);
  }
  std::map<int, int> ids;
  for (const Beacon& beacon : input.beacons) {
    if (!finite(beacon.x_m) || !finite(beacon.y_m)) fail("beacon " + std::to_string(beacon.id) + " not finite");
    if (!ids.emplace(beacon.id, 0).second) fail("beacon " + std::to_string(beacon.id) + " surveyed twice");
  }
}

// The range calibration blocks: one for the ranges between robots, one for those to beacons.
constexpr int kRobotRanges = 0, kBeaconRanges = 1;

// Everything one solve's Ceres problem points into, and the residual blocks by group.
struct Blocks {
  std::vector<ceres::ResidualBlockId> odometry, robot_ranges, beacon_ranges, bearings;
};

std::unique_ptr<ceres::Problem> buildProblem(const TeamInput& input, const TeamSolveOptions& options,
                                             const std::vector<std::vector<double>>& dt_s,
                                             const std::vector<RobotRangeObservation>& robot_ranges,
                                             const std::vector<BeaconObservation>& beacon_observations,
                                             const TeamNoiseFactors& factors, ceres::LossFunction* loss,
                                             std::vector<std::vector<std::array<double, 3>>>* poses,
                                             std::vector<std::array<double, 2>>* calibration,
                                             std::vector<std::array<double, 2>>* beacons,
                                             const std::vector<bool>& beacon_surveyed,
                                             std::array<std::array<double, 2>, 2>* range_calibration,
                                             const std::vector<TeamStart>& starts, Blocks* blocks) {
  ceres::Problem::Options problem_options;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  auto problem = std::make_unique<ceres::Problem>(problem_options);
  *blocks = Blocks{};
  for (size_t r = 0; r < input.robots.size(); ++r) {
    const std::vector<Odometry>& odometry = input.robots[r].odometry;
    std::vector<std::array<double, 3>>& path = (*poses)[r];
    problem->AddParameterBlock(path[0].data(), 3);
    // The anchor: a start given (or not found: that robot keeps its own frame) is held.
    if (starts[r].source != TeamStart::Source::kFound) problem->SetParameterBlockConstant(path[0].data());
    if (odometry.empty()) continue;
    double* odometry_calibration = (*calibration)[r].data();
    for (size_t k = 0; k < odometry.size(); ++k) {
      const Odometry& o = odometry[k];
      // Whitening: Sigma^-1 = L L^T with L = chol(Sigma^-1); the residual is L^T e. L^T is upper
      // triangular: its heading row holds the heading alone.
      const Eigen::Matrix3d information =
          (options.increment_covariance ? options.increment_covariance(o, dt_s[r][k])
                                        : estimation::incrementCovariance(o, dt_s[r][k], options.motion_noise))
              .inverse();
      Eigen::Matrix3d sqrt_information = Eigen::LLT<Eigen::Matrix3d>(information).matrixU();
      sqrt_information.topRows<2>() /= factors.odometry_translation;
      sqrt_information.row(2) /= factors.odometry_heading;
      blocks->odometry.push_back(problem->AddResidualBlock(
          OdometryResidual::create(Eigen::Vector3d(o.forward_m, o.lateral_m, o.delta_heading_rad), dt_s[r][k],
                                   sqrt_information),
          nullptr, path[k].data(), path[k + 1].data(), odometry_calibration));
    }
    if (!options.estimate_odometry_calibration) {
      problem->SetParameterBlockConstant(odometry_calibration);
    } else {
      const bool scale_prior = options.distance_scale_prior_sigma > 0.0;
      const bool bias_prior = options.heading_rate_bias_prior_sigma_rad_s > 0.0;
      // A prior of sigma 1e6 is none: (s - 1) / 1e6 bends the cost by 1e-12 at the most.
      if (scale_prior || bias_prior)
        problem->AddResidualBlock(
            OdometryCalibrationPrior::create(scale_prior ? options.distance_scale_prior_sigma : 1e6,
                                             bias_prior ? options.heading_rate_bias_prior_sigma_rad_s : 1e6),
            nullptr, odometry_calibration);
    }
  }
  // The range calibration of each kind of range (between robots, to beacons): scale and offset,
  // with the shared priors, or held at (1, 0).
  const auto addCalibration = [&](std::array<double, 2>* calibration, bool estimate) {
    problem->AddParameterBlock(calibration->data(), 2);
    if (!estimate) {
      problem->SetParameterBlockConstant(calibration->data());
      return;
    }
    if (options.range_scale_prior_sigma > 0.0)
      problem->AddResidualBlock(CalibrationPrior::create(0, 1.0, options.range_scale_prior_sigma), nullptr, calibration->data());
    if (options.range_offset_prior_sigma_m > 0.0)
      problem->AddResidualBlock(CalibrationPrior::create(1, 0.0, options.range_offset_prior_sigma_m), nullptr,
                                calibration->data());
  };
  if (!robot_ranges.empty())
    addCalibration(&(*range_calibration)[kRobotRanges], options.estimate_range_calibration && options.estimate_robot_range_calibration);
  if (!beacon_observations.empty()) addCalibration(&(*range_calibration)[kBeaconRanges], options.estimate_range_calibration);
  for (const RobotRangeObservation& o : robot_ranges) {
    auto& path_i = (*poses)[o.robot_i];
    auto& path_j = (*poses)[o.robot_j];
    blocks->robot_ranges.push_back(problem->AddResidualBlock(
        RobotRangeResidual::create(o.range_m, o.sigma_m * factors.robot_range, o.at_i.alpha, o.at_j.alpha), loss,
        path_i[o.at_i.step].data(), path_i[o.at_i.step + 1].data(), path_j[o.at_j.step].data(),
        path_j[o.at_j.step + 1].data(), (*range_calibration)[kRobotRanges].data()));
  }
  for (const BeaconObservation& o : beacon_observations) {
    auto& path = (*poses)[o.robot];
    double* beacon = (*beacons)[o.beacon].data();
    const double sigma_m = o.sigma_m * factors.beacon;
    blocks->beacon_ranges.push_back(problem->AddResidualBlock(
        BeaconRangeResidual::create(o.range_m, sigma_m, o.at.alpha), loss, path[o.at.step].data(),
        path[o.at.step + 1].data(), beacon, (*range_calibration)[kBeaconRanges].data()));
    if (o.has_bearing)
      blocks->bearings.push_back(problem->AddResidualBlock(
          BearingResidual::create(o.bearing_rad, factors.bearing * o.sigma_m / std::max(o.range_m, o.sigma_m), o.at.alpha),
          loss,
          path[o.at.step].data(), path[o.at.step + 1].data(), beacon));
    if (beacon_surveyed[static_cast<size_t>(o.beacon)]) problem->SetParameterBlockConstant(beacon);
  }
  return problem;
}

// Ranges (or bearings) whose whitened residual is beyond the loss's scale.
int downweighted(ceres::Problem& problem, const std::vector<ceres::ResidualBlockId>& ids, double scale) {
  int count = 0;
  for (ceres::ResidualBlockId id : ids) {
    double cost = 0.0, residual = 0.0;
    problem.EvaluateResidualBlock(id, false, &cost, &residual, nullptr);
    if (std::abs(residual) > scale) ++count;
  }
  return count;
}

// Beacons the survey lacks, placed from their ranges at the dead-reckoned positions they were
// taken from (the initial guess): the consensus of the range circles (up to half of the ranges
// may be wrong), tolerance 3 sigma each. A beacon is placed where it has kMinRangesToPlace ranges
// whose positions spread kMinSpreadToPlace_m off a line (the multilateration's own defaults: a
// narrower spread has a mirror image that fits as well); the solve then refines it with the rest.
constexpr int kMinRangesToPlace = 6;
constexpr double kMinSpreadToPlace_m = 3.0;

std::map<int, std::array<double, 2>> placeUnsurveyedBeacons(const TeamInput& input, const TeamSolveOptions& options,
                                                            const std::vector<std::vector<int64_t>>& times,
                                                            const std::vector<std::vector<std::array<double, 3>>>& poses,
                                                            const std::map<int, int>& surveyed,
                                                            const std::vector<TeamStart>& starts,
                                                            std::vector<std::string>* notes) {
  struct Sightings {
    std::vector<std::array<double, 2>> positions_m;
    std::vector<double> ranges_m, tolerance_m;
  };
  std::map<int, Sightings> by_beacon;
  for (size_t r = 0; r < input.robots.size(); ++r) {
    if (starts[r].source == TeamStart::Source::kNotFound) continue;  // in its own frame
    for (const Range& range : input.robots[r].beacon_ranges) {
      StepLocation at;
      if (surveyed.count(range.beacon_id) || !locate(times[r], range.utime, &at)) continue;
      const auto& a = poses[r][static_cast<size_t>(at.step)];
      const auto& b = poses[r][static_cast<size_t>(at.step) + 1];
      Sightings& s = by_beacon[range.beacon_id];
      s.positions_m.push_back({a[0] + at.alpha * (b[0] - a[0]), a[1] + at.alpha * (b[1] - a[1])});
      s.ranges_m.push_back(range.range_m);
      s.tolerance_m.push_back(3.0 * (range.sigma_m > 0.0 ? range.sigma_m : options.range_sigma_m));
    }
  }
  std::map<int, std::array<double, 2>> placed;
  for (const auto& [id, s] : by_beacon) {
    estimation::ConsensusMultilateration consensus;
    if (static_cast<int>(s.ranges_m.size()) >= kMinRangesToPlace &&
        estimation::positionSpread(s.positions_m) >= kMinSpreadToPlace_m &&
        estimation::multilaterateConsensus(s.positions_m, s.ranges_m, s.tolerance_m, &consensus)) {
      placed[id] = consensus.point_m;
    } else {
      notes->push_back("beacon " + std::to_string(id) + " is not surveyed and its " + std::to_string(s.ranges_m.size()) +
                       " range(s) do not place it (fewer than " + std::to_string(kMinRangesToPlace) +
                       ", or taken from too near a line): they are set aside");
    }
  }
  if (!placed.empty())
    notes->push_back(std::to_string(placed.size()) + " beacon(s) not in the survey placed from their ranges");
  return placed;
}

}  // namespace

TeamResult solveTeam(const TeamInput& input, const TeamSolveOptions& options) {
  validate(input);
  if (!(options.huber_scale > 0.0)) fail("huber_scale must be > 0");
  if (!(options.range_sigma_m > 0.0)) fail("range_sigma_m must be > 0");
  const int num_robots = static_cast<int>(input.robots.size());
  TeamResult result;

  // Pose times, step durations, and the initial guess: each robot's dead reckoning from its start.
  std::vector<std::vector<int64_t>> times(num_robots);
  std::vector<std::vector<double>> dt_s(num_robots);
  std::vector<std::vector<std::array<double, 3>>> poses(num_robots);
  std::vector<std::array<double, 2>> calibration(num_robots, {1.0, 0.0});
  // The anchor: the starts known; with none and no beacon surveyed, robot 0's start as given.
  std::vector<bool> start_known(static_cast<size_t>(num_robots));
  for (int r = 0; r < num_robots; ++r) start_known[r] = input.robots[r].start_known;
  if (std::none_of(start_known.begin(), start_known.end(), [](bool known) { return known; }) && input.beacons.empty()) {
    start_known[0] = true;
    result.notes.push_back("no robot's start is known and no beacon is surveyed: robot 0's start fixes the team's frame");
  }
  for (int r = 0; r < num_robots; ++r) {
    const TeamRobot& robot = input.robots[r];
    times[r].push_back(robot.start.utime);
    Eigen::Vector3d pose(robot.start.x_m, robot.start.y_m, robot.start.heading_rad);
    if (!start_known[r]) pose.setZero();  // its own frame until it is placed
    poses[r].push_back({pose[0], pose[1], pose[2]});
    for (const Odometry& o : robot.odometry) {
      dt_s[r].push_back(1e-6 * static_cast<double>(o.utime - times[r].back()));
      times[r].push_back(o.utime);
      pose = estimation::step(pose, estimation::calibratedIncrement(o, dt_s[r].back()));
      poses[r].push_back({pose[0], pose[1], pose[2]});
    }
    result.summary.poses += static_cast<int>(poses[r].size());
  }
  result.starts = findUnknownStarts(input, options, times, dt_s, start_known, &poses);
  // A robot not placed keeps its own frame: its ranges are set aside.
  const auto notPlaced = [&](int r) { return result.starts[static_cast<size_t>(r)].source == TeamStart::Source::kNotFound; };

  // Observations on the pose chains; what cannot be placed is set aside with a note.
  std::vector<RobotRangeObservation> robot_ranges;
  int outside_span = 0;
  for (const Range& range : input.robot_ranges) {
    RobotRangeObservation o;
    o.robot_i = range.robot;
    o.robot_j = range.other_robot;
    if (notPlaced(o.robot_i) || notPlaced(o.robot_j)) continue;
    if (!locate(times[o.robot_i], range.utime, &o.at_i) || !locate(times[o.robot_j], range.utime, &o.at_j)) {
      ++outside_span;
      continue;
    }
    o.range_m = range.range_m;
    o.sigma_m = range.sigma_m > 0.0 ? range.sigma_m : options.range_sigma_m;
    robot_ranges.push_back(o);
  }
  if (outside_span > 0)
    result.notes.push_back(std::to_string(outside_span) +
                           " robot range(s) set aside: taken outside a robot's odometry span");

  std::map<int, int> beacon_index;
  std::vector<std::array<double, 2>> beacons;
  std::vector<bool> beacon_surveyed;
  for (const Beacon& beacon : input.beacons) {
    beacon_index[beacon.id] = static_cast<int>(beacons.size());
    beacons.push_back({beacon.x_m, beacon.y_m});
    beacon_surveyed.push_back(true);
  }
  std::vector<int> placed_ids;
  if (options.use_beacon_ranges && options.place_unsurveyed_beacons) {
    const auto placed = placeUnsurveyedBeacons(input, options, times, poses, beacon_index, result.starts, &result.notes);
    for (const auto& [id, position] : placed) {
      beacon_index[id] = static_cast<int>(beacons.size());
      beacons.push_back(position);
      beacon_surveyed.push_back(false);
      placed_ids.push_back(id);
    }
  }
  std::vector<BeaconObservation> beacon_observations;
  int unsurveyed = 0, beacon_outside_span = 0, beacon_total = 0;
  for (int r = 0; r < num_robots; ++r) {
    if (notPlaced(r)) continue;
    for (const Range& range : input.robots[r].beacon_ranges) {
      ++beacon_total;
      if (!options.use_beacon_ranges) continue;
      BeaconObservation o;
      o.robot = r;
      const auto found = beacon_index.find(range.beacon_id);
      if (found == beacon_index.end()) {
        ++unsurveyed;
        continue;
      }
      if (!locate(times[r], range.utime, &o.at)) {
        ++beacon_outside_span;
        continue;
      }
      o.beacon = found->second;
      o.range_m = range.range_m;
      o.sigma_m = range.sigma_m > 0.0 ? range.sigma_m : options.range_sigma_m;
      o.has_bearing = range.has_bearing;
      o.bearing_rad = range.bearing_rad;
      beacon_observations.push_back(o);
    }
  }
  if (!options.use_beacon_ranges && beacon_total > 0)
    result.notes.push_back(std::to_string(beacon_total) + " beacon range(s) set aside: use_beacon_ranges off");
  if (unsurveyed > 0)
    result.notes.push_back(std::to_string(unsurveyed) +
                           " beacon range(s) set aside: their beacon is not surveyed and its ranges could not place it");
  if (beacon_outside_span > 0)
    result.notes.push_back(std::to_string(beacon_outside_span) +
                           " beacon range(s) set aside: taken outside their robot's odometry span");

  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  solver_options.max_num_iterations = options.max_iterations;
  solver_options.function_tolerance = options.function_tolerance;
  solver_options.gradient_tolerance = options.gradient_tolerance;
  solver_options.parameter_tolerance = options.parameter_tolerance;
  solver_options.num_threads = 1;
  solver_options.logging_type = ceres::SILENT;
  // Powell's dogleg: on MR.CLAM 6's robot ranges Levenberg-Marquardt had not converged after 200
  // iterations (31 s); the dogleg converges in ~100, re-using one factorisation when it shrinks
  // its region after a rejected step.
  solver_options.trust_region_strategy_type = ceres::DOGLEG;
  std::string error;
  if (!solver_options.IsValid(&error)) fail("Ceres options: " + error);

  ceres::HuberLoss loss(options.huber_scale);
  std::array<std::array<double, 2>, 2> range_calibration{{{1.0, 0.0}, {1.0, 0.0}}};
  TeamNoiseFactors factors;
  TeamSummary& summary = result.summary;
  for (int round = 0; round <= std::max(0, options.noise_rounds); ++round) {
    Blocks blocks;
    std::unique_ptr<ceres::Problem> problem =
        buildProblem(input, options, dt_s, robot_ranges, beacon_observations, factors, &loss, &poses, &calibration,
                     &beacons, beacon_surveyed, &range_calibration, result.starts, &blocks);
    ceres::Solver::Summary solve;
    ceres::Solve(solver_options, problem.get(), &solve);
    if (round == 0) summary.initial_cost = solve.initial_cost;
    summary.final_cost = solve.final_cost;
    summary.iterations += solve.num_successful_steps + solve.num_unsuccessful_steps;
    summary.time_s += solve.total_time_in_seconds;
    ++summary.solves;
    summary.usable = solve.IsSolutionUsable();
    summary.converged = solve.termination_type == ceres::CONVERGENCE;
    summary.noise = factors;
    std::ostringstream line;
    line << "factors odometry " << factors.odometry_translation << " / heading " << factors.odometry_heading
         << ", robot range " << factors.robot_range << ", beacon " << factors.beacon << ", bearing " << factors.bearing << ": " << solve.BriefReport();
    summary.report += line.str() + "\n";
    summary.robot_ranges_used = static_cast<int>(blocks.robot_ranges.size());
    summary.beacon_ranges_used = static_cast<int>(blocks.beacon_ranges.size());
    summary.bearings_used = static_cast<int>(blocks.bearings.size());
    summary.robot_ranges_downweighted = downweighted(*problem, blocks.robot_ranges, options.huber_scale);
    summary.beacon_ranges_downweighted = downweighted(*problem, blocks.beacon_ranges, options.huber_scale);
    summary.bearings_downweighted = downweighted(*problem, blocks.bearings, options.huber_scale);
    if (!summary.usable || round == options.noise_rounds) break;

    // Variance components: each group's factor times sqrt(squares / redundancy).
    RedundancyGroups groups;
    groups.block_sets = {blocks.odometry, blocks.robot_ranges, blocks.beacon_ranges, blocks.bearings};
    groups.group_of_row = {{0, 0, 1}, {2}, {3}, {4}};
    groups.num_groups = 5;
    const Redundancy redundancy = redundancyNumbers(*problem, groups);
    if (!redundancy.ok) {
      result.notes.push_back("noise factors not learned: the redundancy numbers failed");
      break;
    }
    auto scaled = [&](double factor, int group) {
      if (!(redundancy.redundancy[group] > kMinRedundancy)) return factor;  // not observed: keep it
      return std::clamp(factor * std::sqrt(redundancy.squares[group] / redundancy.redundancy[group]), kMinNoiseFactor,
                        kMaxNoiseFactor);
    };
    factors.odometry_translation = scaled(factors.odometry_translation, 0);
    factors.odometry_heading = scaled(factors.odometry_heading, 1);
    factors.robot_range = scaled(factors.robot_range, 2);
    factors.beacon = scaled(factors.beacon, 3);
    factors.bearing = scaled(factors.bearing, 4);
  }

  for (int r = 0; r < num_robots; ++r) {
    Path path;
    for (size_t k = 0; k < poses[r].size(); ++k) {
      Pose pose;
      pose.utime = times[r][k];
      pose.x_m = poses[r][k][0];
      pose.y_m = poses[r][k][1];
      pose.heading_rad = wrapAngle(poses[r][k][2]);
      pose.robot = r;
      path.push_back(pose);
    }
    result.paths.push_back(std::move(path));
    result.odometry_calibration.push_back({calibration[r][0], calibration[r][1]});
  }
  result.beacons = input.beacons;
  for (size_t i = 0; i < placed_ids.size(); ++i) {
    Beacon beacon;
    beacon.id = placed_ids[i];
    const auto& position = beacons[static_cast<size_t>(beacon_index.at(beacon.id))];
    beacon.x_m = position[0];
    beacon.y_m = position[1];
    result.beacons.push_back(beacon);
  }
  result.robot_range_calibration = range_calibration[kRobotRanges];
  result.beacon_range_calibration = range_calibration[kBeaconRanges];
  return result;
}

}  // namespace spectral_batch
}  // namespace roam
