// The score table of roam-eval: per run (result log), per estimator, the spectral paper's
// Figure 3 rows — full path, last / best / worst 10 % — as mean error and RMSE, then max
// error, beacon error and CPU time. Runs are columns (one log: one column).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "path_score.hpp"
#include "result_log.hpp"

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
};

struct RunScores {
  std::string run;             // label: the log's file name without .lcmlog
  std::string log;
  long events = 0;
  long skipped = 0;
  size_t ground_truth = 0;
  std::vector<EstimatorScore> estimators;
};

RunScores scoreRun(const ResultLog& log, const std::string& run, bool aligned, bool with_odometry);

enum class TableFormat { kText, kMarkdown, kCsv, kJson };
enum class TableMetric { kMean, kRmse, kBoth };

// text / markdown: rows estimator x segment, columns run x metric, then max, beacons, CPU and
// coverage (errors of a row below kMinRankedCoverage in parentheses). csv: one row per run and
// estimator with every figure (metric ignored). json: the same as nested objects.
std::string formatScores(const std::vector<RunScores>& runs, TableFormat format, TableMetric metric);

}  // namespace roam
