// The EKF's history of steps and the re-runs from it (model in ekf_slam.hpp):
// - each step keeps the snapshot a re-run may start from (runSnapshotted, rerunMayStartAt): step
//   0, a pending beacon's first buffered sighting, the starvation trial's step;
// - rollbackAndInsert: a beacon solved by multilateration enters at the snapshot before its first
//   buffered range with a weak prior, and every step since is re-run (replayFrom);
// - rerunWithCalibration: anchor = start_pose, the whole run re-filtered once from the start with
//   the calibration means re-centred on the estimate, every beacon initialised afresh where a
//   heading-rate bias was found (reinitialiseFromStart);
// - prune: the history is kept only while a beacon is pending, a trial runs or the calibrated
//   re-run may still come (bounded by init_window_s).
#include <algorithm>
#include <cmath>
#include <deque>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "ekf_slam.hpp"

namespace roam {
namespace ekf {

void EkfSlam::runSnapshotted(Step* step, bool live, bool rerun_start) {
  // The step with the snapshot a re-run from it restores, kept only where one may start
  // (rerunMayStartAt; always for the re-run's own first step). A step without ranges buffers no
  // sighting and starts no trial, so the state and covariance are not even copied for it.
  step->before = rerun_start || step->index == 0 || !step->ranges.empty() ? filter_ : EkfFilter{};
  step->before_utime = state_utime_;
  step->path_size = path_.size();
  step->before_adaptation = adapt_;
  runStep(*step, live);
  if (!rerun_start && !rerunMayStartAt(step->index)) step->before = EkfFilter{};
}

bool EkfSlam::rerunMayStartAt(int64_t step_index) const {
  // A re-run starts from one step's snapshot and rewrites those after it: step 0 (the calibrated
  // re-run and the early window's), a pending beacon's first buffered sighting (its
  // initialisation; the first moves on to later sightings as the oldest expire), or the
  // starvation trial's step. Any other step's snapshot is never read, so it is not kept: a
  // 50 Hz run with 64 beacons pending for minutes kept a state and covariance (~0.3 MB) per step.
  return step_index == 0 || step_index == last_sighting_step_ || (trial_.active && trial_.step == step_index);
}

size_t EkfSlam::historySnapshots() const {
  return static_cast<size_t>(std::count_if(history_.begin(), history_.end(),
                                           [](const Step& step) { return step.before.mean().size() > 0; }));
}

void EkfSlam::rollbackAndInsert(int id, const MultilaterationResult& solve, std::vector<Sighting> used) {
  const int64_t first_step = pending_.at(id).front().step;
  const int64_t offset = first_step - history_.front().index;
  if (offset < 0 || offset >= static_cast<int64_t>(history_.size()))
    throw std::logic_error("ekf: the history does not hold the first sighting of beacon " + std::to_string(id));
  initialisations_.push_back({id, state_utime_, 0, static_cast<int>(pending_.at(id).size()), solve, std::move(used)});
  // The buffered ranges the batch solve left out (the consensus' or the trimming's outliers) are
  // not re-applied: the beacon enters with a weak prior
  // (init_prior_inflation), so right after it every range passes the gate, and NLOS ranges
  // re-applied there moved a beacon initialised 0.12 m from the truth to 3.4 m (seed 305).
  std::set<int64_t> kept;
  for (const Sighting& sighting : initialisations_.back().sightings) kept.insert(sighting.utime);
  for (const Sighting& sighting : pending_.at(id))
    if (!kept.count(sighting.utime) && excluded_ranges_.insert({id, sighting.utime}).second) ++excluded_ranges_total_;
  pending_.erase(id);
  if (auto counted = pending_live_ranges_.find(id); counted != pending_live_ranges_.end()) {
    for (int64_t i = 0; i < counted->second; ++i) acceptRange();
    pending_live_ranges_.erase(counted);
  }
  auto entry = history_.begin() + offset;
  entry->inserts.push_back({id, solve.world_m, config_.init_prior_inflation * solve.cov_m2});
  initialisations_.back().first_utime = entry->before_utime;
  // The first beacon of a start_pose run: the range bias is still at its prior in the snapshot;
  // re-centre it on the batch estimate (width unchanged) so the re-run linearises s |m - p| + b
  // about a consistent (beacon, bias) pair rather than about the beacon and scale 1.
  if (entry->before.beacons().empty()) {
    entry->before.recentreBias(solve.scale, solve.offset_m);
    // And the heading-rate bias on the solve's estimate of it (0 unless solved for).
    if (solve.heading_rate_bias_rad_s != 0.0)
      entry->before.recentreCalibration(entry->before.odometryScale(),
                                        entry->before.headingRateBias() + solve.heading_rate_bias_rad_s);
  }
  replayFrom(offset, first_step);
  ++replays_;
  map_dirty_ = true;
}

void EkfSlam::replayFrom(int64_t offset, int64_t first_step) {
  if (!trial_rerun_) abandonRecoveryTrial();
  forgetLostBeacons();
  // The applied ranges of the re-run steps are collected again on the re-run poses.
  const int64_t replayed = history_[offset].index;
  for (auto& [id, applied] : applied_sightings_)
    applied.erase(std::remove_if(applied.begin(), applied.end(), [&](const Sighting& sg) { return sg.step >= replayed; }),
                  applied.end());
  // Sightings from the re-run steps are collected again with the re-run poses.
  for (auto it = pending_.begin(); it != pending_.end();) {
    auto& buffer = it->second;
    buffer.erase(std::remove_if(buffer.begin(), buffer.end(),
                                [&](const Sighting& s) { return s.step >= first_step; }),
                 buffer.end());
    it = buffer.empty() ? pending_.erase(it) : std::next(it);
  }
  auto entry = history_.begin() + offset;
  filter_ = entry->before;
  state_utime_ = entry->before_utime;
  truncatePath(entry->path_size);
  last_sighting_step_ = -1;  // the re-run's own sightings mark the snapshots it keeps
  for (auto it = entry; it != history_.end(); ++it) runSnapshotted(&*it, false, it == entry);
}

void EkfSlam::rerunWithCalibration(bool pending_may_not_wait) {
  // anchor = start_pose: the map's orientation is set when the first beacons enter, while the
  // heading-rate bias is still at its prior (the heading's sigma is then b_sigma * t), and the
  // EKF cannot rotate it afterwards. So the history is kept from the start until the bias is
  // known to calib_rerun_fraction of its prior sigma; then the whole run is re-filtered once
  // from the start with the calibration means re-centred on the estimate (widths unchanged),
  // linearising about the right heading. Given up (history freed) after init_window_s.
  if (!calib_rerun_pending_ || bias_undecided_) return;
  const int c = filter_.calibrationIndex();
  const double sigma_b = std::sqrt(filter_.covariance()(c + 1, c + 1));
  // Live, it waits for every pending beacon (so the map it re-solves is whole); at the end of input,
  // or once the history it needs is about to be freed (init_window_s), a beacon still pending
  // (seen over too narrow an arc, say) no longer holds it back: the re-run is made without it
  // rather than not at all (a 50 Hz run with a beacon outside the area, 20 seeds: the eleven
  // runs it held back 1.92 -> 0.86 m mean).
  if (filter_.beacons().empty() || (!pending_.empty() && !pending_may_not_wait) ||
      sigma_b > config_.calib_rerun_fraction * kHeadingRateBiasPriorSigma_rad_s)
    return;
  calib_rerun_pending_ = false;
  if (history_.empty() || history_.front().index != 0) return;
  history_.front().before.recentreCalibration(filter_.odometryScale(), filter_.headingRateBias());
  // The bias is known observable by now: the re-run estimates it from the first step.
  if (bias_release_step_ > 0) bias_release_step_ = history_.front().index;
  history_.front().before.recentreBias(filter_.scale(), filter_.offset());  // as for the first beacon
  // Where the calibration found a heading-rate bias (b beyond the gate of its own sigma, chi2 1
  // dof at gate_probability), the first pass built its frame without it: every beacon is
  // initialised afresh on the re-centred path (reinitialiseFromStart). Where it found none, the
  // first pass's frame is not turned by one, and its beacons are kept (their insertions re-run):
  // fresh initialisations with 30 % NLOS land differently from the first pass's, better or worse
  // by chance (nlos seeds 401-410, no gyro bias: 0.74 -> 0.87 m mean when every re-run
  // re-initialised).
  const double bias_z2 = std::pow(filter_.headingRateBias(), 2) / std::max(1e-30, sigma_b * sigma_b);
  if (bias_z2 > gate_range_chi2_) {
    // The fresh re-run releases b (from its first step) within the gate of the first pass's
    // posterior, not with its prior: its first beacon alone fixes the frame for tens of seconds,
    // and with b as free as its prior (0.01 rad/s) single ranges to that beacon swing b and the
    // heading (nlosw seed 408: the re-run's path curled 9 m off between 26 and 45 s, where the
    // first pass's was 2-6 m off), so the next beacons were solved from curled poses, 7.6 m off.
    rerun_bias_var_ = gate_range_chi2_ * sigma_b * sigma_b;
    reinitialiseFromStart();
    ++fresh_reruns_;
  } else {
    replayFrom(0, 0);
    ++replays_;
  }
  ++calibration_reruns_;
  map_dirty_ = true;
}

void EkfSlam::reinitialiseFromStart() {
  // The re-run initialises every beacon afresh, from sightings taken on the re-run's own poses.
  // Re-running with the first pass's beacon insertions (mean and weak prior) kept the first
  // pass's frame: its first ~10 s dead-reckon with b held at 0 (checkBiasObservable) and its
  // first beacons were solved from that curled path, so its map is rotated by ~b t (0.01 rad/s:
  // 1-3 degrees, of one sign on 9 of 10 seeds), and the re-run's ranges, linearised about
  // those beacons, pulled b from its re-centred 0.0094 to 0.0003 rad/s within 14 s and rotated
  // the re-run the same way (drift8 seeds 301-310: -2.95 ... +0.71 degrees about the start; with
  // -0.01 rad/s the signs flip). Even with the insertions' priors made uninformative the
  // linearisation points kept it (mean 0.59 -> 0.68 m). Re-solved from the re-centred path,
  // the beacons enter in the frame the calibration gives; the rotation left is of either sign
  // and of the size the batch solution's (spectral_batch) is: the start heading's and the early
  // odometry's.
  abandonRecoveryTrial();
  forgetLostBeacons();
  applied_sightings_.clear();  // the re-run collects them again on its own poses
  std::deque<Step> old = std::move(history_);
  history_.clear();
  filter_ = old.front().before;
  state_utime_ = old.front().before_utime;
  last_sighting_step_ = -1;
  truncatePath(old.front().path_size);
  next_step_ = old.front().index;
  // A beacon still pending (a re-run at the end of input or as its history expires) is buffered
  // again from the re-run's own poses; its live range count (pending_live_ranges_) stays.
  pending_.clear();
  touched_.clear();
  first_pass_excluded_ = std::move(excluded_ranges_);  // the first pass's verdicts, for the solves
  excluded_ranges_.clear();
  last_solve_.clear();
  last_trim_size_.clear();
  init_status_.clear();
  for (Step& previous : old) {
    Step step;
    step.index = next_step_++;
    step.odometry = previous.odometry;
    step.ranges = std::move(previous.ranges);
    step.standstill = previous.standstill;
    advance(std::move(step), false);
  }
  ++replays_;
}

bool EkfSlam::rerunHistoryExpiring() const {
  return !history_.empty() && history_.front().index == 0 &&
         history_.front().before_utime < state_utime_ - static_cast<int64_t>(config_.init_window_s * 1e6);
}

void EkfSlam::prune() {
  if (calib_rerun_pending_) {
    if (!rerunHistoryExpiring()) return;
    calib_rerun_pending_ = false;  // the bias was not learnt within the window: no re-run
  }
  // Sightings older than init_window_s are dropped (bounding the history kept for re-runs).
  const int64_t oldest_utime = state_utime_ - static_cast<int64_t>(config_.init_window_s * 1e6);
  for (auto it = pending_.begin(); it != pending_.end();) {
    auto& buffer = it->second;
    buffer.erase(std::remove_if(buffer.begin(), buffer.end(),
                                [&](const Sighting& s) { return s.utime < oldest_utime; }),
                 buffer.end());
    it = buffer.empty() ? pending_.erase(it) : std::next(it);
  }
  if (pending_.empty() && !trial_.active) {
    history_.clear();
    if (!calib_rerun_pending_) excluded_ranges_.clear();  // no re-run can reach them
    return;
  }
  int64_t earliest = next_step_;
  for (const auto& [id, buffer] : pending_) earliest = std::min(earliest, buffer.front().step);
  if (trial_.active) earliest = std::min(earliest, trial_.step);  // the trial's re-run starts there
  while (!history_.empty() && history_.front().index < earliest) history_.pop_front();
}

}  // namespace ekf
}  // namespace roam
