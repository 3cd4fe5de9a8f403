#include "roam/self_check.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>

#include "roam/se2.hpp"

namespace roam {

void SelfCheck::startPose(const Pose& start) {
  if (have_start_ || odometry_before_start_) return;
  have_start_ = true;
  Pose pose = start;
  pose.covariance.fill(kNaN);
  dead_reckoned_.assign(1, pose);
}

void SelfCheck::odometry(const Odometry& step, bool accepted) {
  if (!have_start_) {
    odometry_before_start_ = true;
    return;
  }
  if (!accepted) return;
  const Pose& last = dead_reckoned_.back();
  const double pose[3] = {last.x_m, last.y_m, last.heading_rad};
  const double increment[3] = {step.forward_m, step.lateral_m, step.delta_heading_rad};
  double next[3];
  composeIncrement(pose, increment, next);
  Pose out;
  out.utime = step.utime;
  out.x_m = next[0];
  out.y_m = next[1];
  out.heading_rad = wrapAngle(next[2]);
  dead_reckoned_.push_back(out);
}

void SelfCheck::range(const Range& range) {
  ranges_.push_back(RangeRecord{range.utime, range.beacon_id, range.range_m});
}

namespace {

bool samePath(const Path& a, const Path& b) {
  bool same = a.size() == b.size();
  for (size_t k = 0; same && k < a.size(); ++k)
    same = std::abs(a[k].x_m - b[k].x_m) <= 1e-9 && std::abs(a[k].y_m - b[k].y_m) <= 1e-9;
  return same;
}

std::string metres(double value_m) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.3g m", value_m);
  return text;
}

}  // namespace

bool worseBeyondChance(const std::vector<double>& path_m, const std::vector<double>& dead_reckoning_m) {
  const size_t n = std::min(path_m.size(), dead_reckoning_m.size());
  if (n == 0) return false;
  const size_t batches = std::min<size_t>(kSelfCheckBatches, n);
  const size_t per_batch = n / batches;  // the last few ranges (n % batches) are left out
  std::vector<double> means(batches, 0.0);
  double mean = 0.0, scale = 0.0;
  for (size_t i = 0; i < batches; ++i) {
    for (size_t k = i * per_batch; k < (i + 1) * per_batch; ++k) {
      means[i] += path_m[k] - dead_reckoning_m[k];
      scale += dead_reckoning_m[k];
    }
    means[i] /= static_cast<double>(per_batch);
    mean += means[i];
  }
  mean /= static_cast<double>(batches);
  scale /= static_cast<double>(batches * per_batch);
  double variance = 0.0;
  for (double m : means) variance += (m - mean) * (m - mean);
  const double standard_error = batches > 1 ? std::sqrt(variance / static_cast<double>(batches - 1) / batches) : 0.0;
  // Beyond rounding too: a path equal to dead reckoning but for the last bits is not worse.
  return mean > kSelfCheckStandardErrors * standard_error && mean > 1e-9 * scale + 1e-12;
}

void SelfCheck::checkAnchor() {
  if (anchor_ != "beacons" || surveyed_.empty()) return;
  std::set<int> ranged;
  for (const auto& r : ranges_) ranged.insert(r.beacon_id);
  double mx = 0, my = 0;
  std::vector<const Beacon*> used;
  for (const Beacon& b : surveyed_)
    if (ranged.count(b.id)) {
      used.push_back(&b);
      mx += b.x_m;
      my += b.y_m;
    }
  const size_t n = used.size();
  if (n > 0) {
    mx /= static_cast<double>(n);
    my /= static_cast<double>(n);
  }
  double sxx = 0, sxy = 0, syy = 0;
  for (const Beacon* b : used) {
    sxx += (b->x_m - mx) * (b->x_m - mx);
    sxy += (b->x_m - mx) * (b->y_m - my);
    syy += (b->y_m - my) * (b->y_m - my);
  }
  // On one line: the smaller spread is under 1e-3 of the larger (1 mm across 1 m).
  const bool on_a_line = sxx * syy - sxy * sxy <= 1e-6 * (sxx + syy) * (sxx + syy);
  std::string free_part;
  if (n == 0) free_part = "no surveyed beacon was ranged: the frame is not fixed";
  else if (n == 1) free_part = "one surveyed beacon was ranged: the frame's rotation about it is free";
  else if (on_a_line) free_part = std::to_string(n) + " surveyed beacons ranged, all on one line: the frame's reflection across it is free";
  else return;
  diagnostics_.emplace_back(std::string(kAnchorNote) + ", but " + free_part +
                                " (at least three, not on one line, fix it); anchor = start_pose uses the start pose",
                            1.0);
}

void SelfCheck::decide(const Estimator& estimator, const Path& path) {
  decided_ = true;
  checkAnchor();
  if (!have_start_) return;
  if (estimator.rangesAccepted() == 0) {
    use_dead_reckoning_ = true;
    return;
  }
  if (path.empty() || dead_reckoned_.size() < 2) return;
  const int64_t begin = std::max(path.front().utime, dead_reckoned_.front().utime);
  const int64_t end = std::min(path.back().utime, dead_reckoned_.back().utime);
  // At most kSelfCheckMaxRanges scored, every k-th in time order (a run of a million ranges
  // costs the check what one of 20,000 does, and says the same).
  std::vector<RangeRecord> window;
  for (const RangeRecord& r : ranges_)
    if (r.utime >= begin && r.utime <= end) window.push_back(r);
  const size_t stride = (window.size() + kSelfCheckMaxRanges - 1) / kSelfCheckMaxRanges;
  if (stride > 1) {
    std::vector<RangeRecord> thinned;
    for (size_t k = 0; k < window.size(); k += stride) thinned.push_back(window[k]);
    window.swap(thinned);
  }
  const std::vector<RangeRecord> scored = rangesToScore(window, begin, end);
  if (scored.empty()) return;
  // The path's shape (beacons free), and where the survey has ranged beacons, the path against it.
  const RangeFit of_path = rangeFit(path, scored, {}, true);
  const RangeFit of_dead_reckoning = rangeFit(dead_reckoned_, scored, {}, true);
  diagnostics_.emplace_back(kRangesScored, static_cast<double>(of_path.ranges));
  diagnostics_.emplace_back(kPathFit, of_path.mean_abs_residual_m);
  diagnostics_.emplace_back(kDeadReckoningFit, of_dead_reckoning.mean_abs_residual_m);
  auto worse = [](const RangeFit& a, const RangeFit& b) { return worseBeyondChance(a.residuals_m, b.residuals_m); };
  std::string why;
  if (worse(of_path, of_dead_reckoning))
    why = metres(of_path.mean_abs_residual_m) + " against " + metres(of_dead_reckoning.mean_abs_residual_m);
  bool survey_ranged = false;
  for (const Beacon& b : surveyed_)
    for (const RangeRecord& r : scored) survey_ranged = survey_ranged || r.beacon_id == b.id;
  if (survey_ranged) {
    const RangeFit path_on_survey = rangeFit(path, scored, surveyed_, true);
    const RangeFit dead_reckoning_on_survey = rangeFit(dead_reckoned_, scored, surveyed_, true);
    diagnostics_.emplace_back(kPathSurveyFit, path_on_survey.mean_abs_residual_m);
    diagnostics_.emplace_back(kDeadReckoningSurveyFit, dead_reckoning_on_survey.mean_abs_residual_m);
    if (why.empty() && worse(path_on_survey, dead_reckoning_on_survey))
      why = metres(path_on_survey.mean_abs_residual_m) + " against " +
            metres(dead_reckoning_on_survey.mean_abs_residual_m) + " with the surveyed beacons";
  }
  if (!why.empty()) {
    use_dead_reckoning_ = true;
    diagnostics_.emplace_back(std::string(kWorseNote) + " than dead reckoning does (mean |range residual| " + why +
                                  ", over " + std::to_string(of_path.ranges) +
                                  " ranges): the path published is dead reckoning from the start pose",
                              1.0);
  }
}

bool SelfCheck::apply(const Estimator& estimator, Path* path) {
  if (!finished_) return false;
  if (!decided_) decide(estimator, *path);
  if (!use_dead_reckoning_ || samePath(*path, dead_reckoned_)) return false;
  *path = dead_reckoned_;
  if (estimator.rangesAccepted() == 0) replaced_ = true;
  return true;
}

}  // namespace roam
