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

std::string anchorNote(const std::string& anchor, const Map& surveyed, const std::vector<RangeRecord>& ranges) {
  if (anchor != "beacons" || surveyed.empty()) return "";
  std::set<int> ranged;
  for (const auto& r : ranges) ranged.insert(r.beacon_id);
  double mx = 0, my = 0;
  std::vector<const Beacon*> used;
  for (const Beacon& b : surveyed)
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
  else return "";
  return std::string(SelfCheck::kAnchorNote) + ", but " + free_part +
         " (at least three, not on one line, fix it); anchor = start_pose uses the start pose";
}

std::string SelfCheck::key(const char* figure) const {
  return member_.empty() ? std::string(figure) : TeamSelfCheck::memberKey(figure, member_);
}

void SelfCheck::decide(int64_t ranges_accepted, const Path& path) {
  if (decided_) return;
  decided_ = true;
  if (const std::string note = anchorNote(anchor_, surveyed_, ranges_); !note.empty()) diagnostics_.emplace_back(note, 1.0);
  if (!have_start_) return;
  if (ranges_accepted == 0) {
    use_dead_reckoning_ = no_range_ = true;
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
  diagnostics_.emplace_back(key(kRangesScored), static_cast<double>(of_path.ranges));
  diagnostics_.emplace_back(key(kPathFit), of_path.mean_abs_residual_m);
  diagnostics_.emplace_back(key(kDeadReckoningFit), of_dead_reckoning.mean_abs_residual_m);
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
    diagnostics_.emplace_back(key(kPathSurveyFit), path_on_survey.mean_abs_residual_m);
    diagnostics_.emplace_back(key(kDeadReckoningSurveyFit), dead_reckoning_on_survey.mean_abs_residual_m);
    if (why.empty() && worse(path_on_survey, dead_reckoning_on_survey))
      why = metres(path_on_survey.mean_abs_residual_m) + " against " +
            metres(dead_reckoning_on_survey.mean_abs_residual_m) + " with the surveyed beacons";
  }
  if (why.empty()) return;
  why_ = "mean |range residual| " + why + ", over " + std::to_string(of_path.ranges) + " ranges";
  if (!member_.empty()) return;  // the team decides
  use_dead_reckoning_ = true;
  diagnostics_.emplace_back(std::string(kWorseNote) + " than dead reckoning does (" + why_ +
                                "): the path published is dead reckoning from the start pose",
                            1.0);
}

bool SelfCheck::apply(const Estimator& estimator, Path* path) {
  if (!finished_) return false;
  decide(estimator.rangesAccepted(), *path);
  if (!use_dead_reckoning_ || samePath(*path, dead_reckoned_)) return false;
  *path = dead_reckoned_;
  if (no_range_) replaced_ = true;
  return true;
}

std::string TeamSelfCheck::memberKey(const char* figure, const std::string& robot) {
  const std::string text = figure;
  const std::string prefix = "self-check";
  if (text.rfind(prefix, 0) != 0) return text + " (" + robot + ")";
  return prefix + " (" + robot + ")" + text.substr(prefix.size());
}

void TeamSelfCheck::team(const std::vector<std::string>& robots) {
  robots_ = robots;
  members_.assign(robots.size(), SelfCheck());
  for (size_t r = 0; r < robots.size(); ++r) members_[r].member(robots[r]);
  usable_ranges_.assign(robots.size(), 0);
  replace_.assign(robots.size(), false);
}

void TeamSelfCheck::surveyed(const Map& beacons) {
  surveyed_ = beacons;
  for (SelfCheck& member : members_) member.surveyed(beacons);
}

void TeamSelfCheck::startPose(const Pose& start) {
  if (start.robot < 0 || static_cast<size_t>(start.robot) >= members_.size()) return;
  members_[static_cast<size_t>(start.robot)].startPose(start);
}

void TeamSelfCheck::odometry(const Odometry& step, bool accepted) {
  if (step.robot < 0 || static_cast<size_t>(step.robot) >= members_.size()) return;
  members_[static_cast<size_t>(step.robot)].odometry(step, accepted);
}

void TeamSelfCheck::range(const Range& range, bool rejected) {
  const auto size = static_cast<int>(members_.size());
  if (range.robot < 0 || range.robot >= size || range.other_robot >= size) return;
  if (!rejected) ++usable_ranges_[static_cast<size_t>(range.robot)];
  if (range.toRobot()) {
    if (!rejected) ++usable_ranges_[static_cast<size_t>(range.other_robot)];
    robot_ranges_.push_back(RobotRangeRecord{range.utime, range.robot, range.other_robot, range.range_m});
    return;
  }
  members_[static_cast<size_t>(range.robot)].range(range);
  beacon_ranges_.push_back(RangeRecord{range.utime, range.beacon_id, range.range_m});
}

void TeamSelfCheck::decide(const Estimator& estimator, const Path& path) {
  decided_ = true;
  const size_t n = members_.size();
  if (const std::string note = anchorNote(anchor_, surveyed_, beacon_ranges_); !note.empty())
    diagnostics_.emplace_back(note, 1.0);
  // Each robot's poses, in time order.
  std::vector<Path> paths(n);
  for (const Pose& pose : path)
    if (pose.robot >= 0 && static_cast<size_t>(pose.robot) < n) paths[static_cast<size_t>(pose.robot)].push_back(pose);
  for (Path& p : paths)
    std::stable_sort(p.begin(), p.end(), [](const Pose& a, const Pose& b) { return a.utime < b.utime; });
  std::string why;
  for (size_t r = 0; r < n; ++r) {
    SelfCheck& member = members_[r];
    member.decide(estimator.rangesAccepted() == 0 ? 0 : usable_ranges_[r], paths[r]);
    diagnostics_.insert(diagnostics_.end(), member.diagnostics().begin(), member.diagnostics().end());
    if (member.usedNoRange()) {
      replace_[r] = true;
      diagnostics_.emplace_back(std::string(kNoRangeNote) + " from " + robots_[r] + "'s start pose (robot " + robots_[r] + ")", 1.0);
    }
    if (member.worse()) why += (why.empty() ? "" : "; ") + robots_[r] + ", ranges to beacons: " + member.why();
  }
  // The ranges between robots, where both robots have a path and dead reckoning at the range's time.
  std::vector<Path> dead_reckoning(n);
  for (size_t r = 0; r < n; ++r)
    if (members_[r].hasDeadReckoning() && members_[r].deadReckoning().size() >= 2 && !paths[r].empty())
      dead_reckoning[r] = members_[r].deadReckoning();
  auto within = [&](size_t r, int64_t utime) {
    const Path& p = paths[r];
    const Path& d = dead_reckoning[r];
    return !d.empty() && utime >= std::max(p.front().utime, d.front().utime) &&
           utime <= std::min(p.back().utime, d.back().utime);
  };
  std::vector<RobotRangeRecord> window;
  for (const RobotRangeRecord& r : robot_ranges_)
    if (within(static_cast<size_t>(r.robot), r.utime) && within(static_cast<size_t>(r.other_robot), r.utime))
      window.push_back(r);
  // At most kSelfCheckMaxRanges, every k-th in time order, as for one robot.
  const size_t stride = (window.size() + kSelfCheckMaxRanges - 1) / kSelfCheckMaxRanges;
  if (stride > 1) {
    std::vector<RobotRangeRecord> thinned;
    for (size_t k = 0; k < window.size(); k += stride) thinned.push_back(window[k]);
    window.swap(thinned);
  }
  if (window.size() >= kMinRobotRanges) {
    const RangeFit of_paths = robotRangeFit(paths, window, true);
    const RangeFit of_dead_reckoning = robotRangeFit(dead_reckoning, window, true);
    diagnostics_.emplace_back(kRobotRangesScored, static_cast<double>(of_paths.ranges));
    diagnostics_.emplace_back(kRobotPathFit, of_paths.mean_abs_residual_m);
    diagnostics_.emplace_back(kRobotDeadReckoningFit, of_dead_reckoning.mean_abs_residual_m);
    if (worseBeyondChance(of_paths.residuals_m, of_dead_reckoning.residuals_m))
      why += (why.empty() ? "" : "; ") + std::string("ranges between robots: mean |range residual| ") +
             metres(of_paths.mean_abs_residual_m) + " against " + metres(of_dead_reckoning.mean_abs_residual_m) +
             ", over " + std::to_string(of_paths.ranges) + " ranges";
  }
  if (why.empty()) return;
  for (size_t r = 0; r < n; ++r) replace_[r] = true;
  diagnostics_.emplace_back(std::string(kTeamWorseNote) + " than dead reckoning does (" + why +
                                "): every robot's path published is its dead reckoning from its start pose",
                            1.0);
}

bool TeamSelfCheck::apply(const Estimator& estimator, Path* path) {
  if (!finished_) return false;
  if (!decided_) decide(estimator, *path);
  if (std::find(replace_.begin(), replace_.end(), true) == replace_.end()) return false;
  const size_t n = members_.size();
  std::vector<Path> paths(n);
  for (const Pose& pose : *path)
    if (pose.robot >= 0 && static_cast<size_t>(pose.robot) < n) paths[static_cast<size_t>(pose.robot)].push_back(pose);
  bool changed = false;
  for (size_t r = 0; r < n; ++r) {
    if (!replace_[r] || !members_[r].hasDeadReckoning()) continue;  // no start pose: no frame
    Path dead_reckoning = members_[r].deadReckoning();
    for (Pose& pose : dead_reckoning) pose.robot = static_cast<int>(r);
    if (samePath(paths[r], dead_reckoning)) continue;
    paths[r] = std::move(dead_reckoning);
    changed = true;
  }
  if (!changed) return false;
  path->clear();
  for (const Path& p : paths) path->insert(path->end(), p.begin(), p.end());
  return true;
}


}  // namespace roam
