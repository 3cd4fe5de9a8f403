// The score table of roam-eval: per run (result log), per estimator, the spectral paper's
// Figure 3 rows — full path, last / best / worst 10 % — as mean error and RMSE, then max
// error, beacon error and CPU time. Runs are columns (one log: one column).
// A team log (result_log.hpp) gets its own table: one row per estimator with the team's mean /
// RMSE unaligned and aligned by one rigid fit (team_score.hpp), then each robot's figure.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "path_score.hpp"
#include "result_log.hpp"
#include "team_score.hpp"

namespace roam {

// The dead-reckoning baseline roam-eval integrates itself from the log's INITIAL_POSE and
// ODOMETRY; it appears as an estimator of this name.
constexpr const char* kOdometryRowName = "odometry";

// A path that covers less than this fraction of the ground-truth poses (an estimator that gave
// up early, or published one pose) is shown with its coverage and its errors in parentheses:
// its error over the part it covers is not comparable with a whole run's.
constexpr double kMinRankedCoverage = 0.9;

struct EstimatorScore {
  std::string estimator;
  std::string scored;          // "trajectory" | "poses" | "odometry" (what was scored)
  PathScore score;
  double coverage = 0.0;       // matched ground-truth poses / all ground-truth poses
  bool ranked() const { return coverage >= kMinRankedCoverage; }
  std::optional<double> cpu_s;
  std::string state;           // the last STATUS_ state, "" if none
  std::optional<TeamScore> team;  // team run: the team's and each robot's figures (`score` unused)
};

struct RunScores {
  std::string run;             // label: the log's file name without .lcmlog
  std::string log;
  long events = 0;
  long skipped = 0;
  size_t ground_truth = 0;     // team run: over all robots
  std::vector<EstimatorScore> estimators;
  std::vector<std::string> robots;  // team run: the robots; empty for a single robot's log
  bool aligned = false;             // --aligned (team run: the per-robot figures)
  bool isTeam() const { return !robots.empty(); }
};

RunScores scoreRun(const ResultLog& log, const std::string& run, bool aligned, bool with_odometry);

enum class TableFormat { kText, kMarkdown, kCsv, kJson };
enum class TableMetric { kMean, kRmse, kBoth };

// text / markdown: rows estimator x segment, columns run x metric, then max, beacons, CPU and
// coverage (errors of a row below kMinRankedCoverage in parentheses). csv: one row per run and
// estimator with every figure (metric ignored). json: the same as nested objects.
// Team runs: text / markdown print a titled table per team run after the single runs' table,
// one row per estimator: team mean / RMSE, aligned mean / RMSE, each robot's mean (RMSE with
// --metric rmse; "no path" where it published none), beacons, CPU, coverage. csv: when any run is
// a team, three columns are appended (robot, team_aligned_mean_m, team_aligned_rmse_m) and a team
// run has a row robot "team" per estimator (full_* = the team unaligned) and one per robot
// (scored "none" without a path). json: a team run has "robots" and each estimator "team" and
// "robots".
std::string formatScores(const std::vector<RunScores>& runs, TableFormat format, TableMetric metric);

}  // namespace roam
