// roam-plot on a team's result log (ResultLog::isTeam: a GROUND_TRUTH_<R> per robot R).
//
// One colour per robot (seriesColour in the order of the team's robots), one line style per
// estimator (solid, dashed, dotted, dash-dot, then again): each robot's ground truth is a wide pale
// band in its colour, each estimator's path for it a thin line in the same colour and the
// estimator's style. The legend names the robots by colour and the estimators by style, with the
// team's mean position error (roam-eval's unaligned team figure, over every robot's matched poses).
//
// PREFIX-paths.svg: one panel per estimator (every robot in each) on one shared window, or all in
// one overlay. PREFIX-error.svg: one curve per robot and estimator (the robot's error against its
// own ground truth, roam-eval's matching), on one time axis from the team's first ground truth.
// The team's dead reckoning is not integrated: a team log's odometry baseline is its
// deadreckoning estimator, when it ran one.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "figure_options.hpp"
#include "path_score.hpp"
#include "result_log.hpp"

namespace roam {
namespace plot {

struct RobotSeries {
  std::string robot;
  std::string colour;                    // the robot's
  Path path;                             // what roam-eval scores for the robot (empty: none published)
  std::vector<MatchedPosition> matched;  // against the robot's ground truth
};

struct TeamSeries {
  std::string name;              // the estimator
  std::string dash;              // its stroke-dasharray ("" solid)
  std::optional<Map> map;        // the team's last MAP_<NAME>
  double mean_error_m = kNaN;    // roam-eval's unaligned team mean
  std::vector<RobotSeries> robots;  // in the order of the team's robots
};

// The line style of the i-th estimator: "" (solid), dashed, dotted, dash-dot, then again.
std::string teamDash(size_t index);
// "solid", "dashed", "dotted", "dash-dot" for teamDash(index).
const char* teamDashName(size_t index);

// Every estimator of the team log in order of appearance, or those of `only` (names or channel
// suffixes) in that order; an unknown one throws std::runtime_error naming those there are.
std::vector<TeamSeries> collectTeamSeries(const ResultLog& log, const std::vector<std::string>& only);

std::string teamPathsFigureSvg(const ResultLog& log, const std::vector<TeamSeries>& series,
                               const FigureOptions& options);
std::string teamErrorFigureSvg(const ResultLog& log, const std::vector<TeamSeries>& series,
                               const FigureOptions& options);

}  // namespace plot
}  // namespace roam
