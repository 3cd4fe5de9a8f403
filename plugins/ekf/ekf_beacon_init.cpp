// The EKF's beacon initialisation (anchor = start_pose, and beacons not surveyed): a beacon enters
// the state once the sightings buffered for it (range, the pose it was taken from, that pose's
// variance and its sensitivity to the heading-rate bias) fix it by robust multilateration
// (estimation::multilaterate: beacon, range scale and offset under their priors):
//   consensus solve -> trimmed solve over every sighting -> the plain (bias-free) solve where the
//   ranges do not ask for a bias -> each range judged against the solve of the others (deleted
//   residual, gate_probability; masking guarded) -> the range bias inside its prior's gate.
// A ready beacon is inserted by rolling the filter back to its first sighting (ekf_history.cpp,
// rollbackAndInsert). Units: metres, radians, seconds.
#include "ekf_slam.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "ekf_joint_bias.hpp"
#include "roam/estimation/multilateration.hpp"

namespace roam {
namespace ekf {

void EkfSlam::initialiseReadyBeacons() {
  // Each pass inserts at most one beacon (which re-runs the history), so this terminates.
  bool inserted = true;
  while (inserted) {
    inserted = false;
    const std::set<int> candidates = touched_;
    touched_.clear();
    const JointBiasResult joint = jointHeadingBias();
    if (joint.misfit) ++joint_bias_misfits_;
    for (int id : candidates) {
      auto it = pending_.find(id);
      if (it == pending_.end()) continue;
      RangeBiasPrior bias = rangeBiasPrior();
      // Before the first beacon the path is dead reckoning, curled by the gyro bias the filter
      // cannot see yet (0.005 rad/s: 9 m after a minute at 1 m/s): the solve estimates that
      // bias error with the beacon, from the filter's bias prior (the first beacon only: later
      // sightings' poses already carry the ranges' information on the bias).
      if (filter_.beacons().empty() && filter_.withCalibration() && biasEstimated(next_step_ - 1)) {
        const int b = filter_.calibrationIndex() + 1;
        bias.heading_rate_bias_sigma_rad_s = std::sqrt(filter_.covariance()(b, b));
      }
      // Several pending beacons pin the curl far better than one (jointHeadingBias): the
      // sightings are uncurled by the joint estimate, and this solve estimates what is left of
      // db within the joint's sigma.
      std::vector<Sighting> corrected;
      const std::vector<Sighting>* buffer = &it->second;
      double db_joint = 0.0;
      if (bias.heading_rate_bias_sigma_rad_s > 0.0 && joint.ok &&
          joint.db_sigma_rad_s < 0.5 * bias.heading_rate_bias_sigma_rad_s) {
        db_joint = joint.db_rad_s;
        bias.heading_rate_bias_sigma_rad_s = joint.db_sigma_rad_s;
        corrected = it->second;
        for (Sighting& sg : corrected) {
          sg.x_m += sg.dx_db * db_joint;
          sg.y_m += sg.dy_db * db_joint;
        }
        buffer = &corrected;
      }
      // On the fresh re-run (reinitialiseFromStart) the ranges that the first pass's solve of
      // this beacon left out stay out: whether a range is NLOS does not depend on the poses'
      // calibration, and the first pass judged it against more sightings (nlosw 301: the re-run
      // solved beacon 2 from 16 sightings with the first pass's excluded NLOS range at the end of
      // its arc, its deleted residual 3.2 sigma, just inside the gate, and placed it 5.2 m off).
      std::vector<Sighting> judged;
      if (!first_pass_excluded_.empty()) {
        for (const Sighting& sg : *buffer)
          if (!first_pass_excluded_.count({id, sg.utime})) judged.push_back(sg);
        buffer = &judged;
      }
      // The consensus' sightings first (as before); if their solve fails or explains its
      // outliers by the range bias, the trimmed solve over all sightings (trimmedSolve).
      std::vector<Sighting> used = consensusSightings(*buffer, bias);
      RangeBiasPrior plain_bias = bias;
      plain_bias.heading_rate_bias_sigma_rad_s = 0.0;
      MultilaterationResult solve = estimation::multilaterate(used, plain_bias, init_config_);
      RangeBiasPrior solved_with = plain_bias;
      const bool first_ok = solve.status == MultilaterationResult::Status::kReady && biasConsistent(solve, bias);
      // The trimmed solve costs up to 6 solves over every sighting: with a full buffer (200) it
      // is re-tried once the buffer has grown by a sixteenth since the last try (a run that
      // initialises no beacon: 11.9 s of CPU against 2.1 s before, re-trying at every range).
      const size_t buffered = it->second.size();
      auto& last_try = last_trim_size_[id];
      const bool trim = !first_ok && (buffered < last_try || buffered >= last_try + std::max<size_t>(1, buffered / 16));
      if (trim) {
        last_try = buffered;
        solve = trimmedSolve(*buffer, bias, &used);
        solved_with = bias;
      }
      if (trim && bias.heading_rate_bias_sigma_rad_s > 0.0) {
        // The bias error is kept only where the ranges ask for it: if the same sightings fit as
        // well without it (chi2 within the 1-dof gate), the plain solve is used. Plaza's dead-
        // reckoned path drifts as a random walk, which a constant bias does not model.
        const MultilaterationResult plain = estimation::multilaterate(used, plain_bias, init_config_);
        if (plain.status != MultilaterationResult::Status::kTooFew && plain.status != MultilaterationResult::Status::kShortBaseline &&
            plain.status != MultilaterationResult::Status::kNoSolution && plain.chi2 - solve.chi2 <= gate_range_chi2_) {
          solve = plain;
          solved_with = plain_bias;
        }
      }
      // A ready solve must not rest on one range (round 7): each range is judged against the
      // solve of the others, and dropped (the rest re-solved) where they do not predict it
      // (dropDeletedOutliers). With 30 % NLOS a beacon seen over a narrow arc was placed by the
      // one NLOS range at the arc's end, which the solve fitted within its noise model (nlos
      // 301: 5.3 m off, the map turned 5.5 degrees); without it the arc is too narrow, and the
      // beacon waits.
      if (solve.status == MultilaterationResult::Status::kReady && biasConsistent(solve, bias))
        solve = dropDeletedOutliers(solve, solved_with, &used);
      solve.heading_rate_bias_rad_s += db_joint;
      if (solve.status == MultilaterationResult::Status::kReady && !biasConsistent(solve, bias))
        solve.status = MultilaterationResult::Status::kPoorlyConstrained;
      // Stable: the previous solve of this beacon (one range less) lies within the gate of this
      // one's covariance. A solve that jumps with one new range is held by a few of its ranges
      // (nlosw seed 306: 2.6 m in one range, sigma 0.9 m, then 8.6 m from the truth).
      const auto previous = last_solve_.find(id);
      const bool stable = previous != last_solve_.end() && previous->second.status != MultilaterationResult::Status::kTooFew &&
                          (previous->second.world_m - solve.world_m).dot(solve.cov_m2.ldlt().solve(previous->second.world_m - solve.world_m)) <=
                              gate_range_bearing_chi2_;
      if (solve.status != MultilaterationResult::Status::kTooFew && solve.status != MultilaterationResult::Status::kShortBaseline &&
          solve.status != MultilaterationResult::Status::kNoSolution)
        last_solve_[id] = solve;
      if (solve.status == MultilaterationResult::Status::kReady && !stable) solve.status = MultilaterationResult::Status::kPoorlyConstrained;
      init_status_[id] = solve.status;
      if (solve.status == MultilaterationResult::Status::kReady) {
        rollbackAndInsert(id, solve, std::move(used));
        inserted = true;
        break;
      }
    }
  }
  touched_.clear();
}

void EkfSlam::noteLostBeacon(int id, Sighting sighting) {
  // A beacon placed from the ranges can be placed wrong (a mirror half-resolved at the end of a
  // straight, a frame the first pass could not see yet); its ranges are then gated for the rest of
  // the run, and nothing moves it, since only applied ranges do (a racetrack run with a drifting
  // gyro, seed 302: one beacon 7.7 m off, 232 of its ranges gated, 13 % of the input; 60 m lanes,
  // seeds 310, 312, 316: 9-12 %). Its gated ranges are sightings like a pending beacon's: once
  // lost_beacon_gated_ranges of them come in a row, they are solved alone by the initialisation's
  // rules (consensus, trimming, the deleted-residual check, the range bias within its prior's
  // gate, the ready checks: no mirror, angle, sigma). Where they place the beacon outside the
  // gate (2 dof) of the filter's estimate and of the previous such solve, and the new place
  // explains more of the beacon's recent ranges than the old, it is moved there at the next step
  // with the initialisation's weak prior, its old state dropped (the smoother carries the
  // removal). Outliers do not agree on a point; a stretch of NLOS long by one excess can, and is
  // out-voted by the ranges applied before it.
  std::vector<Sighting>& run = lost_[id];
  run.push_back(sighting);
  if (static_cast<int>(run.size()) > config_.init_max_ranges) run.erase(run.begin());
  if (static_cast<int>(run.size()) < config_.lost_beacon_gated_ranges) return;
  // As for a pending beacon's trimmed solve: re-tried once the run has grown by a sixteenth.
  size_t& last_try = lost_last_try_[id];
  if (run.size() >= last_try && run.size() < last_try + std::max<size_t>(1, run.size() / 16)) return;
  last_try = run.size();
  const RangeBiasPrior bias = rangeBiasPrior();
  std::vector<Sighting> used = consensusSightings(run, bias);
  MultilaterationResult solve = estimation::multilaterate(used, bias, init_config_);
  if (solve.status != MultilaterationResult::Status::kReady || !biasConsistent(solve, bias)) solve = trimmedSolve(run, bias, &used);
  if (solve.status == MultilaterationResult::Status::kReady && biasConsistent(solve, bias)) solve = dropDeletedOutliers(solve, bias, &used);
  if (solve.status != MultilaterationResult::Status::kReady || !biasConsistent(solve, bias)) return;
  auto previous = lost_last_solve_.find(id);
  const bool stable = previous != lost_last_solve_.end() &&
                      (previous->second.world_m - solve.world_m).dot(solve.cov_m2.ldlt().solve(previous->second.world_m - solve.world_m)) <=
                          gate_range_bearing_chi2_;
  lost_last_solve_[id] = solve;
  const int m = filter_.beaconIndex(id);
  const Eigen::Vector2d moved_m = solve.world_m - filter_.mean().segment<2>(m);
  const Eigen::Matrix2d cov_m2 = solve.cov_m2 + filter_.covariance().block<2, 2>(m, m);
  if (!stable || moved_m.dot(cov_m2.ldlt().solve(moved_m)) <= gate_range_bearing_chi2_) return;
  // And where it explains more of the beacon's recent ranges, applied and gated, than the
  // estimate does (each within the gate of its sigma and its pose's spread): a stretch of NLOS
  // after hundreds of applied ranges fits a shifted point (one excess per stretch) and is out-
  // voted by them; a mirror image or a beacon placed wrong early was applied few ranges, or ones
  // its true place explains as well (a straight lane's, seen from either side).
  auto explained = [&](const Eigen::Vector2d& beacon_m) {
    int count = 0;
    auto fits = [&](const Sighting& sg) {
      const double predicted_m = bias.scale * std::hypot(beacon_m.x() - sg.x_m, beacon_m.y() - sg.y_m) + bias.offset_m;
      const double r = sg.range_m - predicted_m;
      return r * r <= gate_range_chi2_ * (sg.sigma_m * sg.sigma_m + sg.position_var_m2);
    };
    for (const Sighting& sg : applied_sightings_[id]) count += fits(sg) ? 1 : 0;
    for (const Sighting& sg : run) count += fits(sg) ? 1 : 0;
    return count;
  };
  if (explained(solve.world_m) <= explained(filter_.mean().segment<2>(m))) return;
  moves_.push_back({id, solve.world_m, config_.init_prior_inflation * solve.cov_m2});
  lost_.erase(id);
  lost_last_solve_.erase(id);
  lost_last_try_.erase(id);
  applied_sightings_.erase(id);
  ++beacons_moved_;
}

void EkfSlam::forgetLostBeacons() {
  lost_.clear();
  lost_last_solve_.clear();
  lost_last_try_.clear();
  moves_.clear();
}

RangeBiasPrior EkfSlam::rangeBiasPrior() const {
  // The filter's range scale and offset, with their current uncertainty when they are states.
  RangeBiasPrior bias;
  bias.scale = filter_.scale();
  bias.offset_m = filter_.offset();
  if (filter_.withBias()) {
    bias.scale_sigma = std::sqrt(filter_.covariance()(EkfFilter::kScale, EkfFilter::kScale));
    bias.offset_sigma_m = std::sqrt(filter_.covariance()(EkfFilter::kOffset, EkfFilter::kOffset));
  }
  return bias;
}

JointBiasResult EkfSlam::jointHeadingBias() const {
  // Before the first beacon only, with b a live state: the heading-rate bias error of the
  // dead-reckoned path from every pending beacon whose own solve found a position (not a mirror,
  // not a narrow angle), its ranges re-selected by residual (ekf_joint_bias.hpp).
  JointBiasResult none;
  if (!filter_.beacons().empty() || !filter_.withCalibration() || !biasEstimated(next_step_ - 1) || pending_.size() < 2)
    return none;
  RangeBiasPrior bias = rangeBiasPrior();
  const int b = filter_.calibrationIndex() + 1;
  bias.heading_rate_bias_sigma_rad_s = std::sqrt(filter_.covariance()(b, b));
  std::map<int, MultilaterationResult> start;
  for (const auto& [id, solve] : last_solve_)
    if (pending_.count(id) && (solve.status == MultilaterationResult::Status::kPoorlyConstrained ||
                               solve.status == MultilaterationResult::Status::kReady))
      start[id] = solve;
  if (start.size() < 2) return none;
  JointBiasResult joint = solveJointHeadingBias(pending_, start, bias, std::sqrt(gate_range_chi2_), config_.init_min_ranges);
  // As for one beacon: outliers explained by the range bias (scale 1.47, offset 6 m on nlosw
  // seed 306, db the wrong sign) fail the prior's gate.
  MultilaterationResult as_solve;
  as_solve.scale = joint.scale;
  as_solve.offset_m = joint.offset_m;
  if (joint.ok && !biasConsistent(as_solve, bias)) joint.ok = false;
  // Nor is a joint solve whose kept ranges do not fit its own model (chi2 beyond the
  // gate_probability quantile of its degrees of freedom): it has kept outliers, and its db is
  // explaining them. With NLOS in stretches (one excess held for ~20 s) the residual trim keeps a
  // whole stretch, since its ranges agree with each other, and a curl of the dead-reckoned path
  // fits it (nlos30-episodes seed 1008, clean odometry: db 0.0076 +- 0.0018 rad/s at chi2 82.5
  // for 36 dof; the first beacon entered 9.2 m off and the run ended 9.2 m off, dead reckoning
  // 1.8 m). A curl that is there fits within its noise model: a drifting gyro's runs keep theirs.
  if (joint.ok && joint.chi2 > chiSquareQuantileWilsonHilferty(joint.dof, config_.gate_probability)) {
    joint.ok = false;
    joint.misfit = true;
  }
  return joint;
}

std::vector<Sighting> EkfSlam::consensusSightings(const std::vector<Sighting>& sightings,
                                                  const RangeBiasPrior& bias) const {
  // Non-line-of-sight ranges (30 % of them, 2-40 m long) leave the batch solve's chi2 far above
  // its noise model, so its widened sigma never passes init_max_sigma_m and the beacon is never
  // initialised. The sightings that agree on one point (estimation::multilaterateConsensus,
  // tolerance: the gate times each range's sigma with its pose's and the offset's spread) are
  // solved instead; the others are re-applied through the gate once the beacon is in.
  // The range scale is one unknown shared by every range of the beacon, not noise per range: it
  // is tried as hypotheses across its prior (the filter's scale +-1 and +-2 sigma), each range's
  // tolerance carrying only the grid's own spread (sigma / sqrt(12) of the range); the hypothesis
  // with the most agreeing ranges wins (ties: the one nearer the prior; once every range agrees,
  // no other is tried). Widening every range by the scale's full prior instead (10 % of a 50 m
  // NLOS range is 5 m, and an NLOS range is the long one) let most outliers agree: with half the
  // ranges NLOS no beacon ever entered.
  if (static_cast<int>(sightings.size()) < config_.init_min_ranges) return sightings;
  std::vector<std::array<double, 2>> positions;
  std::vector<double> tolerances;  // the same for every hypothesis
  const double gate = std::sqrt(gate_range_chi2_);
  const double grid_sigma_per_m = bias.scale_sigma / std::sqrt(12.0);
  for (const Sighting& s : sightings) {
    positions.push_back({s.x_m, s.y_m});
    const double var = s.sigma_m * s.sigma_m + s.position_var_m2 + std::pow(grid_sigma_per_m * s.range_m, 2) +
                       bias.offset_sigma_m * bias.offset_sigma_m;
    tolerances.push_back(gate * std::sqrt(var));
  }
  const std::array<double, 5> steps = {0.0, -1.0, 1.0, -2.0, 2.0};
  const int hypotheses = bias.scale_sigma > 0.0 ? static_cast<int>(steps.size()) : 1;
  estimation::ConsensusMultilateration best;
  for (int h = 0; h < hypotheses && best.inliers < static_cast<int>(sightings.size()); ++h) {
    const double scale = bias.scale + steps[h] * bias.scale_sigma;
    if (scale <= 0.0) continue;
    std::vector<double> ranges;
    for (const Sighting& s : sightings) ranges.push_back((s.range_m - bias.offset_m) / scale);
    estimation::ConsensusMultilateration consensus;
    if (estimation::multilaterateConsensus(positions, ranges, tolerances, &consensus) && consensus.inliers > best.inliers)
      best = std::move(consensus);
  }
  if (best.inliers < config_.init_min_ranges || best.inliers == static_cast<int>(sightings.size())) return sightings;
  std::vector<Sighting> agreeing;
  for (size_t i = 0; i < sightings.size(); ++i)
    if (best.inlier[i]) agreeing.push_back(sightings[i]);
  return agreeing;
}

MultilaterationResult EkfSlam::trimmedSolve(const std::vector<Sighting>& sightings, const RangeBiasPrior& bias,
                                           std::vector<Sighting>* used) const {
  // The consensus' tolerance carries the range bias' prior spread (10 % of a 20 m range is 2 m)
  // and the poses' absolute variance (metres after minutes of dead reckoning), so with 30 % NLOS
  // ranges (2-40 m long) about a sixth of what it keeps are outliers; the solve then explains
  // them with the scale (1.1-1.3) and fails as poorly constrained (chi2 10-40 x its range count)
  // or, later, lands metres off. Once solved, the bias is estimated and the common part of the
  // pose error (a shift of the whole path) moves the beacon, not the residuals; so the sightings
  // are re-selected by their residual against the solution, with a robust scale (1.4826 x the
  // median absolute residual, at least each range's sigma): |r| <= gate x that. Re-solved until
  // the selection repeats (at most kTrimIterations times). Used when the consensus' own solve
  // fails or its range bias leaves the prior's gate; Plaza 1 from the start pose (whose
  // consensus solves pass) moved 0.34 -> 0.57 m when every solve was trimmed.
  MultilaterationResult solve = estimation::multilaterate(*used, bias, init_config_);
  const double gate = std::sqrt(gate_range_chi2_);
  for (int iteration = 0; iteration < kTrimIterations; ++iteration) {
    if (solve.status == MultilaterationResult::Status::kTooFew || solve.status == MultilaterationResult::Status::kShortBaseline ||
        solve.status == MultilaterationResult::Status::kNoSolution)
      break;
    std::vector<double> residual_m(sightings.size()), magnitude_m(sightings.size());
    for (size_t i = 0; i < sightings.size(); ++i) {
      const Sighting& sg = sightings[i];
      const double db = solve.heading_rate_bias_rad_s;
      residual_m[i] = sg.range_m -
                      solve.scale * std::hypot(solve.world_m.x() - sg.x_m - sg.dx_db * db, solve.world_m.y() - sg.y_m - sg.dy_db * db) -
                      solve.offset_m;
      magnitude_m[i] = std::abs(residual_m[i]);
    }
    std::nth_element(magnitude_m.begin(), magnitude_m.begin() + magnitude_m.size() / 2, magnitude_m.end());
    const double robust_sigma_m = 1.4826 * magnitude_m[magnitude_m.size() / 2];
    std::vector<Sighting> selected;
    for (size_t i = 0; i < sightings.size(); ++i)
      if (std::abs(residual_m[i]) <= gate * std::max(robust_sigma_m, sightings[i].sigma_m)) selected.push_back(sightings[i]);
    if (static_cast<int>(selected.size()) < config_.init_min_ranges) break;
    bool same = selected.size() == used->size();
    for (size_t i = 0; same && i < selected.size(); ++i) same = selected[i].utime == (*used)[i].utime;
    if (same) break;
    *used = std::move(selected);
    solve = estimation::multilaterate(*used, bias, init_config_);
  }
  return solve;
}

size_t EkfSlam::mostInformative(const MultilaterationResult& solve, const std::vector<Sighting>& used,
                                const RangeBiasPrior& bias) const {
  // The sighting that informs the solve's weakest direction most: the solve's information
  // (beacon, range scale, offset; linearised at the solution, the bias prior added), and the
  // drop in the beacon's variance along its weakest axis when one sighting is taken out.
  const size_t n = used.size();
  std::vector<Eigen::Vector4d> rows(n);
  Eigen::Matrix4d information = Eigen::Matrix4d::Zero();
  information(2, 2) = bias.estimated() ? 1.0 / (bias.scale_sigma * bias.scale_sigma) : 1e12;
  information(3, 3) = bias.estimated() ? 1.0 / (bias.offset_sigma_m * bias.offset_sigma_m) : 1e12;
  const double db = solve.heading_rate_bias_rad_s;
  for (size_t i = 0; i < n; ++i) {
    const Sighting& sg = used[i];
    const Eigen::Vector2d line(solve.world_m.x() - sg.x_m - sg.dx_db * db, solve.world_m.y() - sg.y_m - sg.dy_db * db);
    const double distance_m = std::max(1e-9, line.norm());
    const double sigma_m = std::sqrt(sg.sigma_m * sg.sigma_m + solve.scale * solve.scale * sg.position_var_m2);
    rows[i] << solve.scale * line.x() / distance_m, solve.scale * line.y() / distance_m, distance_m, 1.0;
    rows[i] /= sigma_m;
    information += rows[i] * rows[i].transpose();
  }
  const Eigen::Matrix4d cov = information.inverse();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(cov.topLeftCorner<2, 2>());
  Eigen::Vector4d weakest = Eigen::Vector4d::Zero();
  weakest.head<2>() = eig.eigenvectors().col(1);
  const Eigen::Vector4d gain = cov * weakest;
  size_t best = n;
  double best_loss = -1.0;
  for (size_t i = 0; i < n; ++i) {
    // Taking row i out raises the variance along `weakest` by (row . gain)^2 / (1 - row' cov row).
    const double loss = std::pow(rows[i].dot(gain), 2) / std::max(1e-12, 1.0 - rows[i].dot(cov * rows[i]));
    if (loss > best_loss) {
      best_loss = loss;
      best = i;
    }
  }
  return best;
}

double EkfSlam::deletedResidualZ2(const std::vector<Sighting>& used, size_t i, size_t also_out, const RangeBiasPrior& bias) const {
  // Sighting i's range against the solve of the others (also_out left out too; used.size() for
  // none): its squared residual over the variance of that prediction (range noise, pose, the
  // others' beacon covariance along the line of sight). 0 where the others have no solution.
  std::vector<Sighting> others;
  others.reserve(used.size());
  for (size_t j = 0; j < used.size(); ++j)
    if (j != i && j != also_out) others.push_back(used[j]);
  const MultilaterationResult loo = estimation::multilaterate(others, bias, init_config_);
  if (loo.status == MultilaterationResult::Status::kTooFew || loo.status == MultilaterationResult::Status::kShortBaseline ||
      loo.status == MultilaterationResult::Status::kNoSolution)
    return 0.0;
  const Sighting& sg = used[i];
  const double db = loo.heading_rate_bias_rad_s;
  const Eigen::Vector2d line(sg.x_m + sg.dx_db * db - loo.world_m.x(), sg.y_m + sg.dy_db * db - loo.world_m.y());
  const double distance_m = line.norm();
  const Eigen::Vector2d u = line / std::max(1e-9, distance_m);
  const double residual_m = sg.range_m - loo.scale * distance_m - loo.offset_m;
  const double var = sg.sigma_m * sg.sigma_m + loo.scale * loo.scale * (sg.position_var_m2 + u.dot(loo.cov_m2 * u));
  return residual_m * residual_m / var;
}

MultilaterationResult EkfSlam::dropDeletedOutliers(MultilaterationResult solve, const RangeBiasPrior& bias,
                                                  std::vector<Sighting>* used) const {
  // Each range is judged against the solve of the others (its deleted residual): a range that
  // they do not predict within the gate is dropped (the worst first) and the rest re-solved,
  // until every range is predicted (at most kTrimIterations rounds). Two outliers at the same
  // end of a narrow arc vouch for each other (masking: nlos 301 had two NLOS ranges, 4.1 and
  // 3.6 m long, 80 degrees round from the others); so each range is also judged with the
  // sighting that informs the solve's weakest direction most left out as well.
  for (int round = 0; round < kTrimIterations; ++round) {
    if (static_cast<int>(used->size()) <= config_.init_min_ranges) break;
    const size_t lever = mostInformative(solve, *used, bias);
    double worst_z2 = gate_range_chi2_;
    size_t worst = used->size();
    for (size_t i = 0; i < used->size(); ++i) {
      double z2 = deletedResidualZ2(*used, i, used->size(), bias);
      if (i != lever) z2 = std::max(z2, deletedResidualZ2(*used, i, lever, bias));
      if (z2 > worst_z2) {
        worst_z2 = z2;
        worst = i;
      }
    }
    if (worst == used->size()) break;
    used->erase(used->begin() + static_cast<std::ptrdiff_t>(worst));
    solve = estimation::multilaterate(*used, bias, init_config_);
  }
  return solve;
}

bool EkfSlam::biasConsistent(const MultilaterationResult& solve, const RangeBiasPrior& bias) const {
  // The solve's range bias must lie inside its prior's gate (chi2, 2 dof, gate_probability).
  // Outliers that the consensus let in are explained by moving the bias: NLOS 30 %, seed 302,
  // initialised its first beacon with scale 1.31 and offset 5.6 m (11 sigma of the 0.5 m prior)
  // 11 m from the truth, and every beacon after it 40-65 m off (the run 38 m).
  if (!bias.estimated()) return true;
  const double chi2 = std::pow((solve.scale - bias.scale) / bias.scale_sigma, 2) +
                      std::pow((solve.offset_m - bias.offset_m) / bias.offset_sigma_m, 2);
  return chi2 <= gate_range_bearing_chi2_;
}

}  // namespace ekf
}  // namespace roam
