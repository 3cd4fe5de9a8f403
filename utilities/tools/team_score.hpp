// Scoring a team's paths: each robot's path against its own ground truth by scorePath (the same
// per-path figures as a single robot's), and the team's figures over all robots' matched poses
// together — unaligned, and aligned by one rigid 2-D motion (rotation + translation, no scale)
// fitted to all robots' matches at once, as CORA reports a team. Errors in metres.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "path_score.hpp"
#include "result_log.hpp"

namespace roam {

struct RobotScore {
  std::string robot;
  std::string scored;          // "trajectory" | "poses" | "" when the estimator published no path for it
  PathScore score;             // scorePath against the robot's ground truth (aligned alone if asked)
  size_t ground_truth = 0;     // the robot's ground-truth poses
  bool published() const { return !scored.empty(); }
  double coverage() const;     // matched / ground truth (0 without ground truth)
};

struct TeamScore {
  size_t matched = 0;          // matched poses over all robots
  size_t ground_truth = 0;     // ground-truth poses over all robots
  ErrorStats unaligned, aligned;  // over every matched pose of every robot
  double unaligned_max_m = kNaN, aligned_max_m = kNaN;
  double beacon_error_m = kNaN, aligned_beacon_error_m = kNaN;  // the team's map, as is / by the team fit
  std::optional<Rigid2D> alignment;  // the one team fit (when any pose matched)
  std::vector<RobotScore> robots;    // in the order of the team's robots
  double coverage() const;
  size_t robotsWithoutPath() const;
};

// `aligned_robots` is roam-eval's --aligned for the per-robot figures; the team's figures are
// reported both ways regardless.
TeamScore scoreTeam(const EstimatorOutputs& estimator, const std::map<std::string, Path>& team_ground_truth,
                    bool aligned_robots, const std::optional<Map>& true_map);

}  // namespace roam
