// What roam-plot draws of each estimator: the path roam-eval scores (the last TRAJECTORY_<NAME>,
// else the POSE_<NAME> sequence; "odometry" is the log's ODOMETRY integrated from INITIAL_POSE,
// as roam-eval's baseline row), the last MAP_<NAME>, and the position error against
// GROUND_TRUTH with roam-eval's matching (path_score.hpp: matchToGroundTruth).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "path_score.hpp"
#include "result_log.hpp"

namespace roam {
namespace plot {

struct Series {
  std::string name;
  std::string colour;
  bool dashed = false;        // the odometry baseline
  Path path;                  // what is scored
  std::optional<Map> map;     // the last MAP_ (none for odometry)
  std::vector<MatchedPosition> matched;
  double mean_error_m = kNaN; // roam-eval's full-path mean
};

// Every estimator of the log in order of appearance, the odometry row first when
// `with_odometry` and the log has INITIAL_POSE and ODOMETRY. `only` (names or channel suffixes,
// "odometry" included) keeps those, in that order; an unknown one throws std::runtime_error
// naming the estimators there are.
std::vector<Series> collectSeries(const ResultLog& log, const std::vector<std::string>& only, bool with_odometry);

// The colour of the i-th estimator (Okabe-Ito palette, readable by colour-blind people).
std::string seriesColour(size_t index);

}  // namespace plot
}  // namespace roam
