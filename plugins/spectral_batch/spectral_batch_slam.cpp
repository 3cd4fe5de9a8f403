#include "spectral_batch_slam.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <iostream>
#include <set>
#include <sstream>
#include <stdexcept>
#include <ctime>

#include "initial_guess.hpp"
#include "roam/estimation/multilateration.hpp"
#include "spectral_seed.hpp"

namespace roam {
namespace spectral_batch {
namespace {

// Odometry noise-scale search: up to 32 times the configured noise (2 % per metre -> 64 %).
constexpr double kMaxOdometryNoiseScale = 32.0;

// Thread CPU seconds (verbose: where a final solve's time goes).
double threadCpu_s() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

Pose toPose(int64_t utime, const std::array<double, 3>& pose) {
  Pose out;
  out.utime = utime;
  out.x_m = pose[0];
  out.y_m = pose[1];
  out.heading_rad = wrapAngle(pose[2]);
  return out;
}

}  // namespace

SpectralBatchSlam::SpectralBatchSlam(const SpectralBatchConfig& config) : config_(config) {
  checkConfig(config_, addSpectralBatchOptions);
  if (config_.init == SpectralBatchConfig::Init::kSpectral) spectral_ = spectral_batch::makeSpectralSeed(config_);
}

SpectralBatchSlam::~SpectralBatchSlam() = default;

void SpectralBatchSlam::start(const Pose& start_pose) {
  started_ = true;
  pose_utime_.assign(1, start_pose.utime);
  start_pose_ = {start_pose.x_m, start_pose.y_m, start_pose.heading_rad};
  current_pose_ = start_pose_;
  last_solve_utime_ = start_pose.utime;
  setState(EstimatorState::kTracking);
  emitPose(toPose(start_pose.utime, current_pose_));
}

void SpectralBatchSlam::setTeam(const std::vector<std::string>& robots) {
  team_ = std::make_unique<TeamBatch>(config_, robots);
  spectral_.reset();  // a one-robot seed; the team is seeded by each robot's dead reckoning
  if (config_.anchor == SpectralBatchConfig::Anchor::kBeacons)
    note("anchor = beacons in a team run: the team solve holds every robot's start pose (INITIAL_POSE_<robot>) "
         "and uses the surveyed beacons' ranges; see anchor");
  setState(EstimatorState::kTracking);
}

void SpectralBatchSlam::setInitialPose(const Pose& start_pose) {
  if (team_) return team_->setInitialPose(start_pose);
  if (started_) return;  // the start is fixed once odometry has begun
  start(start_pose);
  have_initial_pose_ = true;
  if (spectral_) spectral_->setInitialPose(start_pose);
}

void SpectralBatchSlam::setBeacons(const Map& surveyed) {
  if (team_) return team_->setBeacons(surveyed);
  surveyed_ = surveyed;
  if (spectral_) spectral_->setBeacons(surveyed);
}

void SpectralBatchSlam::addOdometry(const Odometry& odometry) {
  if (team_) return team_->addOdometry(odometry) ? acceptOdometry() : rejectOdometry("time went backwards");
  if (!started_) {
    // No INITIAL_POSE: start at the origin, at this step's time (as deadreckoning does).
    Pose origin;
    origin.utime = odometry.utime;
    start(origin);
  }
  if (odometry.utime < pose_utime_.back()) return rejectOdometry("time went backwards");
  odometry_.push_back(odometry);
  dt_s_.push_back(1e-6 * static_cast<double>(odometry.utime - pose_utime_.back()));
  pose_utime_.push_back(odometry.utime);
  acceptOdometry();
  if (spectral_) spectral_->addOdometry(odometry);

  current_pose_ = spectral_batch::propagate(current_pose_, odometry, dt_s_.back(), odometryCalibration());
  emitPose(toPose(odometry.utime, current_pose_));

  if (config_.resolve_interval_s > 0.0 &&
      static_cast<double>(odometry.utime - last_solve_utime_) >= config_.resolve_interval_s * 1e6)
    solveNow(false);
}

void SpectralBatchSlam::addRange(const Range& range) {
  if (!(range.range_m > 0.0)) return rejectRange("range not positive");
  if (team_) return team_->addRange(range) ? acceptRange() : rejectRange("time went backwards");
  ranges_.push_back(range);
  acceptRange();
  if (spectral_) spectral_->addRange(range);
}

void SpectralBatchSlam::finish() {
  if (team_) return finishTeam();
  if (config_.anchor == SpectralBatchConfig::Anchor::kBeacons && surveyed_.empty()) noteNoSurvey();
  if (started_) {
    if (spectral_) {
      try {
        spectral_->finish();
      } catch (const std::exception& error) {
        // The batch solve goes on from dead reckoning; the reason is on stderr with verbose.
        if (config_.verbose) std::cerr << "spectral_batch: spectral seed failed: " << error.what() << "\n";
        spectral_.reset();
      }
    }
    solveNow(true);
  }
  setState(EstimatorState::kFinished);
}

std::vector<std::array<double, 3>> SpectralBatchSlam::initialPoses(bool final) {
  const size_t num_poses = pose_utime_.size();
  // The final solve re-seeds from the spectral solution over all data unless the warm-start
  // chain already began from one (live mode solves before the spectral batch has a path).
  const bool reseed = final && spectral_ && !seeded_by_spectral_;
  if (!solved_poses_.empty() && !reseed) {
    // Warm start: the previous solution, extended by odometry from its last pose.
    std::vector<std::array<double, 3>> poses = solved_poses_;
    while (poses.size() < num_poses) {
      const size_t k = poses.size() - 1;
      poses.push_back(spectral_batch::propagate(poses.back(), odometry_[k], dt_s_[k], odometryCalibration()));
    }
    return poses;
  }
  if (spectral_) {
    Path path;
    bool have = false;
    try {
      have = spectral_->trajectory(true, &path);
    } catch (const std::exception& error) {
      if (config_.verbose) std::cerr << "spectral_batch: spectral seed failed: " << error.what() << "\n";
    }
    if (have && path.size() == num_poses) {
      std::vector<std::array<double, 3>> poses;
      poses.reserve(num_poses);
      for (const Pose& pose : path) poses.push_back({pose.x_m, pose.y_m, pose.heading_rad});
      if (config_.seed_heading_align_m > 0.0) {
        spectral_batch::headingsFromOdometryAlignment(odometry_, 0.5 * config_.seed_heading_align_m, &poses);
      } else {
        // Unwrap the headings so each odometry residual starts from its small increment.
        for (size_t k = 1; k < poses.size(); ++k)
          poses[k][2] = poses[k - 1][2] + wrapAngle(poses[k][2] - poses[k - 1][2]);
      }
      if (config_.anchor == SpectralBatchConfig::Anchor::kStartPose) {
        // Gauge: the solve fixes pose 0, and INITIAL_POSE defines it. The spectral path sits in
        // the start-pose frame only up to its alignment over the first align_m of travel (its
        // pose 0 is typically decimetres off, its heading there poorly determined while the robot
        // stands still), so fixing the seed's own pose 0 would pin the whole solution to that
        // error (a wrong pose-0 heading rotates everything about it). Translate the seed onto the
        // start position (the rotation of the frame, fitted over align_m, is kept) and give pose 0
        // the start heading; the odometry residuals reconcile the first steps.
        const double dx_m = start_pose_[0] - poses[0][0], dy_m = start_pose_[1] - poses[0][1];
        for (auto& pose : poses) {
          pose[0] += dx_m;
          pose[1] += dy_m;
        }
        poses[0][2] += wrapAngle(start_pose_[2] - poses[0][2]);
        shifted_seed_m_ = {dx_m, dy_m};
      }
      seeded_by_spectral_ = true;
      return poses;
    }
    if (config_.verbose && final)
      std::cerr << "spectral_batch: no spectral path of " << num_poses << " poses (got "
                << path.size() << "); seeding from dead reckoning\n";
  }
  if (!solved_poses_.empty()) {
    // No spectral path after all: keep the warm start.
    std::vector<std::array<double, 3>> poses = solved_poses_;
    while (poses.size() < num_poses) {
      const size_t k = poses.size() - 1;
      poses.push_back(spectral_batch::propagate(poses.back(), odometry_[k], dt_s_[k], odometryCalibration()));
    }
    return poses;
  }
  return spectral_batch::deadReckon(start_pose_, odometry_, dt_s_, odometryCalibration());
}

std::vector<SpectralBatchSlam::Tie> SpectralBatchSlam::tieRanges(bool final) const {
  // Tie every range to the pose chain (see the header): pose k and alpha along step k.
  std::vector<Tie> tied;
  tied.reserve(ranges_.size());
  for (const Range& range : ranges_) {
    const auto after = std::upper_bound(pose_utime_.begin(), pose_utime_.end(), range.utime);
    if (after == pose_utime_.begin()) {
      tied.push_back({0, 0.0, &range});
      continue;
    }
    const int k = static_cast<int>(after - pose_utime_.begin()) - 1;
    if (after == pose_utime_.end()) {
      if (final || range.utime == pose_utime_.back()) tied.push_back({k, 0.0, &range});
      continue;  // live: waits for the step that contains it
    }
    const double step_us = static_cast<double>(pose_utime_[k + 1] - pose_utime_[k]);
    const double alpha = step_us > 0.0 ? static_cast<double>(range.utime - pose_utime_[k]) / step_us : 0.0;
    tied.push_back({k, alpha, &range});
  }
  return tied;
}

double SpectralBatchSlam::rangeSigma(const Range& range) const {
  return range.sigma_m > 0.0 ? range.sigma_m : config_.range_sigma_m;
}

SpectralBatchSlam::Candidate SpectralBatchSlam::solveFrom(std::vector<std::array<double, 3>> poses,
                                                          const Map* seed_map, bool use_previous,
                                                          bool fix_first_heading,
                                                          const std::vector<Tie>& tied,
                                                          bool evaluate_only,
                                                          double odometry_noise_factor,
                                                          const std::array<double, 2>& odometry_calibration) const {
  auto positionAt = [&poses](const Tie& t) -> std::array<double, 2> {
    const auto& a = poses[t.pose];
    if (t.alpha == 0.0) return {a[0], a[1]};
    const auto& b = poses[t.pose + 1];
    return {a[0] + t.alpha * (b[0] - a[0]), a[1] + t.alpha * (b[1] - a[1])};
  };

  // Beacon blocks: surveyed and fixed (anchor = beacons), the seed's map, the previous solve, or
  // robust multilateration from the guessed path, in that order of preference.
  std::set<int> ids;
  for (const Tie& t : tied) ids.insert(t.range->beacon_id);
  Candidate out;
  spectral_batch::Problem& problem = out.problem;
  spectral_batch::State& state = out.state;
  for (int id : ids) {
    std::array<double, 2> beacon{0.0, 0.0};
    bool have = false;
    bool fixed = false;
    if (config_.anchor == SpectralBatchConfig::Anchor::kBeacons) {
      for (const Beacon& b : surveyed_) {
        if (b.id == id) {
          beacon = {b.x_m, b.y_m};
          have = fixed = true;
        }
      }
    }
    if (!have && seed_map) {
      for (const Beacon& b : *seed_map) {
        if (b.id == id && std::isfinite(b.x_m) && std::isfinite(b.y_m)) {
          beacon = {b.x_m + shifted_seed_m_[0], b.y_m + shifted_seed_m_[1]};
          have = true;
        }
      }
    }
    if (!have && use_previous && solved_beacons_.count(id)) {
      beacon = solved_beacons_.at(id);
      have = true;
    }
    if (!have) {
      std::vector<std::array<double, 2>> positions_m;
      std::vector<double> ranges_m;
      double sigma_m = 0.0;
      for (const Tie& t : tied) {
        if (t.range->beacon_id != id) continue;
        positions_m.push_back(positionAt(t));
        ranges_m.push_back(t.range->range_m);
        sigma_m += rangeSigma(*t.range);
      }
      if (!positions_m.empty()) sigma_m /= static_cast<double>(positions_m.size());
      // The path is a guess: its error adds to the range noise (odometry drift of metres).
      estimation::RobustMultilateration robust;
      have = estimation::multilaterateRobust(positions_m, ranges_m, std::max(sigma_m, 1.0), &robust);
      if (have) beacon = robust.beacon_m;
    }
    if (!have) continue;  // not yet observable: its ranges wait for a later solve
    out.index_of[id] = static_cast<int>(state.beacons.size());
    state.beacons.push_back(beacon);
    state.beacon_offsets_m.push_back(use_previous && beacon_offsets_m_.count(id) ? beacon_offsets_m_.at(id) : 0.0);
    problem.beacon_fixed.push_back(fixed);
  }
  for (const Tie& t : tied) {
    const auto found = out.index_of.find(t.range->beacon_id);
    if (found == out.index_of.end()) continue;
    spectral_batch::RangeObservation observation;
    observation.pose = t.pose;
    observation.alpha = t.alpha;
    observation.beacon = found->second;
    observation.range_m = t.range->range_m;
    observation.sigma_m = rangeSigma(*t.range);
    problem.ranges.push_back(observation);
  }
  problem.odometry = odometry_;
  problem.dt_s = dt_s_;
  problem.fix_first_pose = config_.anchor == SpectralBatchConfig::Anchor::kStartPose;
  problem.fix_first_heading = fix_first_heading;
  if (have_initial_pose_ && config_.anchor == SpectralBatchConfig::Anchor::kBeacons && config_.start_pose_sigma_m > 0.0) {
    problem.start_prior_pose = start_pose_;
    problem.start_prior_sigma = {config_.start_pose_sigma_m, config_.start_pose_sigma_m,
                                 config_.start_heading_sigma_rad};
  }
  state.poses = std::move(poses);
  state.odometry_calibration = odometry_calibration;
  if (use_previous) {
    state.calibration = calibration_;
    state.odometry_calibration = odometry_calibration_;
  }
  problem.odometry_sigma_factor = odometry_noise_factor;
  problem.heading_as_stated = heading_as_stated_;
  if (heading_as_stated_) state.odometry_calibration[1] = 0.0;
  problem.from_seed = true;
  out.summary = spectral_batch::solve(config_, problem, &state, evaluate_only);
  problem.from_seed = false;  // the trials below and the candidate's later solves are warm
  // The odometry noise scale k by maximum likelihood (profile over k): every odometry sigma times
  // k adds n log k to the negative log-likelihood (n odometry residuals) and divides their squares
  // by k^2. k = 1, 2, 4, ... is tried, each solve warm-started from the last, while the
  // likelihood improves; the configured (or reported) noise is the floor, never narrowed. A log's
  // stated noise is often its generator's setting (GOATS: 2 cm per edge for odometry good to a
  // metre), and odometry held 10 times too stiff makes good ranges look like outliers.
  if (!evaluate_only && config_.estimate_noise_scale && out.summary.usable && problem.odometry_sigma_factor == 1.0) {
    const double n = 3.0 * static_cast<double>(problem.odometry.size());
    double best_nll = out.summary.final_cost;
    for (double k = 2.0; k <= kMaxOdometryNoiseScale; k *= 2.0) {
      // Doubling k divides the odometry part of the cost by 4 and leaves the rest (ranges,
      // priors; all >= 0), so no state costs less than a quarter of the current minimum C:
      // nll(2k) >= C / 4 + n log(2k). When n log 2 >= 3 C / 4 the trial cannot improve the
      // likelihood and its solve is skipped (Plaza-sized runs: most of a solve's time).
      if (n * std::log(2.0) >= 0.75 * out.summary.final_cost) break;
      spectral_batch::Problem trial_problem = problem;
      spectral_batch::State trial_state = state;
      trial_problem.odometry_sigma_factor = k;
      spectral_batch::Summary trial = spectral_batch::solve(config_, trial_problem, &trial_state);
      const double nll = trial.final_cost + n * std::log(k);
      if (!trial.usable || !(nll < best_nll)) break;
      best_nll = nll;
      trial.iterations += out.summary.iterations;
      problem = std::move(trial_problem);
      state = std::move(trial_state);
      out.summary = trial;
    }
  }
  return out;
}

double SpectralBatchSlam::costWithNoise(const Candidate& candidate, double odometry_noise_factor) const {
  spectral_batch::Problem problem = candidate.problem;
  spectral_batch::State state = candidate.state;
  problem.odometry_sigma_factor = odometry_noise_factor;
  return spectral_batch::solve(config_, problem, &state, true).final_cost;
}

bool SpectralBatchSlam::inDoubt(const Candidate& first) const {
  if (config_.dead_reckoning_seed == SpectralBatchConfig::DeadReckoningSeed::kAlways || !first.summary.usable) return true;
  const double num_ranges = static_cast<double>(first.problem.ranges.size());
  const double odometry_cost_max = 0.5 * num_ranges;
  const double inliers_min = config_.doubt_inlier_fraction * num_ranges;
  const bool doubt = first.summary.odometry_cost > odometry_cost_max ||
                     static_cast<double>(first.summary.range_inliers) < inliers_min;
  if (config_.verbose)
    std::cerr << "spectral_batch: the first solve's odometry cost " << first.summary.odometry_cost << " (in doubt above "
              << odometry_cost_max << "), inliers " << first.summary.range_inliers << " of " << first.problem.ranges.size()
              << (doubt ? ": in doubt, the dead-reckoning seed is solved too\n"
                        : ": not in doubt, the dead-reckoning seed is not solved (dead_reckoning_seed = always)\n");
  return doubt;
}

void SpectralBatchSlam::solveNow(bool final) {
  const size_t num_poses = pose_utime_.size();
  std::vector<std::array<double, 3>> poses = initialPoses(final);
  Map spectral_map;
  const bool fresh_seed = seeded_by_spectral_ && !spectral_map_taken_;
  const bool seeded_by_spectral = fresh_seed && spectral_->takeMap(&spectral_map);
  if (fresh_seed) spectral_map_taken_ = true;
  const std::vector<Tie> tied = tieRanges(final);

  // A spectral seed already carries the frame's rotation, fitted by the spectral core to the start
  // pose and the first align_m of odometry (least squares over ~50 m, insensitive to the heading
  // at a standing start). Pinning the single pose-0 heading instead lets early odometry heading
  // errors (a 2 % turn error is degrees) rotate the whole solution about the start: on Plaza 1
  // the pinned optimum is rotated ~6 deg, metres at the far end. So with a spectral seed only the
  // start position is fixed and the rotation gauge stays where the seed put it.
  // Final solve: the dead-reckoning seed with the heading-rate bias that best explains the
  // ranges (a scan): a gyro drift of 0.3 deg/s curls a 30-minute path into circles no local
  // solve unwinds. Without a spectral seed or a previous solve it is the only seed, solved once;
  // with one, it is solved too where the first solve is in doubt (dead_reckoning_seed) and the
  // lower robust cost, under the same (wider) noise scales, is kept (a seed dragged by outliers
  // loses).
  double bias_rad_s = 0.0;
  std::ostringstream times;  // verbose: thread CPU per part of the solve
  double mark_s = threadCpu_s();
  auto lap = [&](const char* what) {
    const double now_s = threadCpu_s();
    times << " " << what << " " << now_s - mark_s << " s";
    mark_s = now_s;
  };
  decideHeadingAsStated(final);
  if (final) {
    bias_rad_s = config_.estimate_odometry_calibration && !heading_as_stated_ ? scanHeadingRateBias(tied) : 0.0;
    lap("scan");
    setDiagnostic("heading_rate_bias_scan_rad_s", bias_rad_s);
  }
  const std::array<double, 2> scanned_calibration{1.0, bias_rad_s};
  const bool dead_reckoning_only = final && !seeded_by_spectral_ && solved_poses_.empty();
  if (dead_reckoning_only)
    poses = spectral_batch::deadReckon(start_pose_, odometry_, dt_s_, estimation::OdometryCalibration{1.0, bias_rad_s});
  Candidate best = solveFrom(std::move(poses), seeded_by_spectral ? &spectral_map : nullptr,
                             !seeded_by_spectral, !seeded_by_spectral_, tied, false, odometry_noise_factor_,
                             dead_reckoning_only ? scanned_calibration : odometry_calibration_);
  lap("first solve");
  bool from_spectral = seeded_by_spectral_;
  double factor = best.problem.odometry_sigma_factor;
  Candidate alone;  // final: dead reckoning with its multilaterated beacons, evaluated
  if (final) {
    // The odometry-alone hypothesis: dead reckoning, beacons multilaterated (robustly) from it.
    const std::vector<std::array<double, 3>> dr = spectral_batch::deadReckon(start_pose_, odometry_, dt_s_);
    const bool compare = !dead_reckoning_only && (from_spectral || bias_rad_s != 0.0) && inDoubt(best);
    setDiagnostic("dead_reckoning_seed_solved", compare ? 1.0 : 0.0);
    if (compare) {
      const std::vector<std::array<double, 3>> dr_biased =
          spectral_batch::deadReckon(start_pose_, odometry_, dt_s_, estimation::OdometryCalibration{1.0, bias_rad_s});
      Candidate from_dr = solveFrom(dr_biased, nullptr, false, true, tied, false, odometry_noise_factor_, scanned_calibration);
      lap("dead-reckoning solve");
      if (from_dr.summary.usable) {
        const double common = std::max(factor, from_dr.problem.odometry_sigma_factor);
        const double cost_spectral = best.summary.usable ? costWithNoise(best, common) : HUGE_VAL;
        const double cost_dr = costWithNoise(from_dr, common);
        if (config_.verbose)
          std::cerr << "spectral_batch: robust cost from the spectral seed " << cost_spectral
                    << ", from dead reckoning " << cost_dr << " (odometry noise scale " << common << ")\n";
        if (cost_dr < cost_spectral) {
          best = std::move(from_dr);
          from_spectral = false;
        }
      }
      factor = best.problem.odometry_sigma_factor;
    }
    lap("comparison");
    alone = solveFrom(dr, nullptr, false, true, tied, true, factor, {1.0, 0.0});
    odometry_alone_cost_ = alone.summary.final_cost;
    best_cost_ = costWithNoise(best, factor);
    lap("odometry alone");
    setDiagnostic("odometry_alone_cost", odometry_alone_cost_);
  }
  const spectral_batch::Summary checked = best.summary;  // the trust checks below judge this solve
  if (final && config_.anchor == SpectralBatchConfig::Anchor::kStartPose && best.summary.usable) {
    // With the heading as stated the rotation is the start heading carried along the odometry's
    // heading chain (the solve's own, pose 0 held): a window fit to dead-reckoned positions would
    // add their lateral wander (GOATS: ~1 m per 5 m step) to it.
    if (config_.gauge == SpectralBatchConfig::Gauge::kWindow && config_.gauge_align_m > 0.0 && !heading_as_stated_)
      alignRotationToOdometry(&best.state);
    else if (config_.gauge == SpectralBatchConfig::Gauge::kPinned)
      pinStartHeading(&best);
  }
  lap("gauge");
  if (config_.verbose) std::cerr << "spectral_batch: thread CPU:" << times.str() << "\n";
  odometry_noise_factor_ = factor;
  setDiagnostic("odometry_noise_scale", factor);
  setDiagnostic("init_spectral", from_spectral ? 1.0 : 0.0);
  summary_ = best.summary;
  const spectral_batch::Problem& problem = best.problem;
  spectral_batch::State& state = best.state;
  ++solves_;
  if (config_.verbose) {
    std::cerr << "spectral_batch: solve " << solves_ << " over " << num_poses << " poses, "
              << problem.ranges.size() << " ranges, " << state.beacons.size() << " beacons: "
              << summary_.iterations << " iterations, cost " << summary_.initial_cost << " -> "
              << summary_.final_cost << " (odometry " << summary_.odometry_cost << ", ranges "
              << summary_.range_cost << ", " << summary_.range_inliers << " inliers), " << summary_.time_s
              << " s, range scale " << state.calibration[0] << ", offset " << state.calibration[1]
              << " m, distance scale " << state.odometry_calibration[0] << ", heading-rate bias "
              << state.odometry_calibration[1] << " rad/s, odometry noise scale "
              << best.problem.odometry_sigma_factor << "\n"
              << summary_.report;
  }
  setDiagnostic("solves", solves_);
  setDiagnostic("solver_iterations", summary_.iterations);
  setDiagnostic("solver_stages", summary_.stages);
  setDiagnostic("solver_final_scale_kept", summary_.anneal_check_kept);
  setDiagnostic("solver_converged", summary_.converged ? 1.0 : 0.0);
  setDiagnostic("solver_initial_cost", summary_.initial_cost);
  setDiagnostic("solver_final_cost", summary_.final_cost);
  setDiagnostic("solver_odometry_cost", summary_.odometry_cost);
  setDiagnostic("solver_range_cost", summary_.range_cost);
  setDiagnostic("solver_time_s", summary_.time_s);
  setDiagnostic("ranges_used", static_cast<double>(problem.ranges.size()));
  setDiagnostic("ranges_inliers", static_cast<double>(summary_.range_inliers));
  if (!summary_.usable) {
    setState(EstimatorState::kFailed);
    throw std::runtime_error("spectral_batch: the Ceres solve failed: " + summary_.report);
  }
  if (final && best_cost_ > odometry_alone_cost_ * (1.0 + 1e-9) + 1e-9) {
    // Ranges and odometry together explain the data worse than odometry alone: a wrong basin.
    std::ostringstream why;
    why << "spectral_batch: the solve ended at robust cost " << best_cost_
        << ", above odometry alone (" << odometry_alone_cost_
        << "): no solution (check range_sigma_m, the odometry noise keys and loss)";
    return refuse(std::move(alone), why.str());
  }
  const bool any_beacon_fixed =
      std::find(problem.beacon_fixed.begin(), problem.beacon_fixed.end(), true) != problem.beacon_fixed.end();
  const double inlier_fraction =
      problem.ranges.empty() ? 1.0 : static_cast<double>(checked.range_inliers) / static_cast<double>(problem.ranges.size());
  setDiagnostic("ranges_inlier_fraction", inlier_fraction);
  if (final && !any_beacon_fixed && inlier_fraction < config_.min_inlier_fraction) {
    // Beacons fitted to the same ranges, most of which the solution calls outliers: below the
    // robust loss's breakdown point a wrong basin explaining another minority fits as well.
    std::ostringstream why;
    why << "spectral_batch: the solve explains only " << checked.range_inliers << " of "
        << problem.ranges.size() << " ranges as inliers, under min_inlier_fraction "
        << config_.min_inlier_fraction
        << " with no surveyed beacon: no solution (survey the beacons with anchor = beacons, or check "
           "range_sigma_m and loss)";
    return refuse(std::move(alone), why.str());
  }
  if (!summary_.converged && config_.verbose)
    std::cerr << "spectral_batch: the last stage stopped at max_iterations (" << config_.max_iterations
              << ") before converging\n";

  solved_poses_ = std::move(state.poses);
  for (const auto& [id, index] : best.index_of) {
    solved_beacons_[id] = state.beacons[index];
    beacon_offsets_m_[id] = state.beacon_offsets_m[index];
    if (config_.estimate_beacon_offsets)
      setDiagnostic("beacon_offset_m_" + std::to_string(id), state.beacon_offsets_m[index]);
  }
  calibration_ = state.calibration;
  odometry_calibration_ = state.odometry_calibration;
  setDiagnostic("range_scale", calibration_[0]);
  setDiagnostic("range_offset_m", calibration_[1]);
  setDiagnostic("odometry_distance_scale", odometry_calibration_[0]);
  setDiagnostic("heading_rate_bias_rad_s", odometry_calibration_[1]);
  current_pose_ = solved_poses_.back();
  last_solve_utime_ = pose_utime_.back();
  new_solution_ = true;
  emitMap(map());
}

void SpectralBatchSlam::refuse(Candidate alone, const std::string& why) {
  if (!config_.fallback_deadreckoning) {
    setState(EstimatorState::kFailed);
    throw std::runtime_error(why);
  }
  // The data do not fix the solution (see the checks in solveNow), but the odometry alone is
  // still an answer with a known error growth: dead reckoning from the start pose, uncalibrated
  // (nothing the ranges say is trusted), with the beacons multilaterated from it. Published as
  // the solution with the reason on stderr and in STATUS (dead_reckoning_fallback = 1).
  std::cerr << why << "; publishing dead reckoning instead (fallback_deadreckoning = true)\n";
  setDiagnostic("dead_reckoning_fallback", 1.0);
  solved_poses_ = std::move(alone.state.poses);
  solved_beacons_.clear();
  beacon_offsets_m_.clear();
  for (const auto& [id, index] : alone.index_of) solved_beacons_[id] = alone.state.beacons[index];
  calibration_ = {1.0, 0.0};
  odometry_calibration_ = {1.0, 0.0};
  setDiagnostic("range_scale", 1.0);
  setDiagnostic("range_offset_m", 0.0);
  setDiagnostic("odometry_distance_scale", 1.0);
  setDiagnostic("heading_rate_bias_rad_s", 0.0);
  current_pose_ = solved_poses_.back();
  last_solve_utime_ = pose_utime_.back();
  new_solution_ = true;
  emitMap(map());
}

Map SpectralBatchSlam::map() const {
  Map out;
  for (const auto& [id, xy] : solved_beacons_) {
    Beacon beacon;
    beacon.id = id;
    beacon.x_m = xy[0];
    beacon.y_m = xy[1];
    out.push_back(beacon);
  }
  return out;
}

Path SpectralBatchSlam::currentPath() const {
  Path path;
  path.reserve(pose_utime_.size());
  std::array<double, 3> pose = solved_poses_.empty() ? start_pose_ : solved_poses_[0];
  for (size_t k = 0; k < pose_utime_.size(); ++k) {
    if (k > 0)
      pose = k < solved_poses_.size() ? solved_poses_[k]
                                      : spectral_batch::propagate(pose, odometry_[k - 1], dt_s_[k - 1], odometryCalibration());
    path.push_back(toPose(pose_utime_[k], pose));
  }
  return path;
}

void SpectralBatchSlam::finishTeam() {
  team_->finish();
  const TeamSummary& summary = team_->result().summary;
  setDiagnostic("team_cost", summary.final_cost);
  setDiagnostic("team_iterations", summary.iterations);
  setDiagnostic("team_solves", summary.solves);
  setDiagnostic("team_converged", summary.converged ? 1.0 : 0.0);
  setDiagnostic("team_solve_s", summary.time_s);
  setDiagnostic("robot_ranges_used", summary.robot_ranges_used);
  setDiagnostic("robot_ranges_downweighted", summary.robot_ranges_downweighted);
  setDiagnostic("beacon_ranges_used", summary.beacon_ranges_used);
  setDiagnostic("bearings_used", summary.bearings_used);
  setDiagnostic("noise_odometry_translation", summary.noise.odometry_translation);
  setDiagnostic("noise_odometry_heading", summary.noise.odometry_heading);
  setDiagnostic("noise_robot_range", summary.noise.robot_range);
  setDiagnostic("noise_beacon", summary.noise.beacon);
  setDiagnostic("noise_bearing", summary.noise.bearing);
  for (const std::string& text : team_->notes()) note(text);
  emitMap(team_->result().beacons);
  setState(summary.usable ? EstimatorState::kFinished : EstimatorState::kFailed);
  if (!summary.usable) throw std::runtime_error("the team solve's answer is not usable (Ceres: " + summary.report + ")");
  new_solution_ = true;
}

bool SpectralBatchSlam::trajectory(bool force, Path* path) {
  if (team_) {
    if (!force && !new_solution_) return false;
    *path = team_->paths();
    new_solution_ = false;
    return !path->empty();
  }
  if (!started_) return false;
  if (!force && !new_solution_) return false;
  *path = currentPath();
  new_solution_ = false;
  return true;
}

}  // namespace spectral_batch
}  // namespace roam
