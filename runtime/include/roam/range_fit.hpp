// How well a path explains the ranges taken along it: the statistic of the SDK's self-check
// (roam/self_check.hpp), the same for every estimator.
//
// Model: a range r_k to beacon j taken at time t_k is scale |m_j - p(t_k)| + offset + e_k, e_k
// Laplace (heavy tailed: NLOS and clutter cost in proportion to their size, not its square).
// p(t) is the path interpolated linearly in time. The range scale and offset (roam's one range
// calibration, roam/calibration_priors.hpp) are those that best explain every range within three
// sigmas of their priors: a ranging system 7 % long or 0.3 m late costs a path nothing, and half
// the ranges NLOS cannot be explained away by a scale near 0 and an offset near their median. A
// surveyed beacon m_j is where the survey puts it (the survey and the path share the log's one
// frame): a path in the wrong place or turned costs there. Any other is placed where it best
// explains its own ranges from this path: with no survey, a path and any rigid motion of it score
// the same. All by least absolute deviations; the score is the mean |e_k| over the ranges counted,
// in metres. A beacon with fewer than three ranges in the window is not counted (two ranges fit a
// 2-D point exactly from any path); ranges outside the path's time span are not counted. Bearings
// are not scored.
//
// Ranges between robots (robotRangeFit): a range r_k from robot a to robot b at t_k is
// scale |p_b(t_k) - p_a(t_k)| + offset + e_k, both positions interpolated as above: the other
// robot is a beacon held where its path puts it at that time. The same scale and offset, fitted
// within the same priors (a radio on each robot is the same kind of radio), the same Laplace
// residuals and score.
//
// This is a scorer, not a beacon initialisation: both paths compared get the same freedom, and it
// is in the SDK because the SDK needs no maths library; the estimators' one initialisation is
// roam/estimation's multilaterate().
#pragma once

#include <cstdint>
#include <vector>

#include "roam/types.hpp"

namespace roam {

struct RangeRecord {
  int64_t utime = 0;
  int beacon_id = 0;
  double range_m = 0.0;
};

struct RangeFit {
  double mean_abs_residual_m = 0.0;  // over `ranges` counted; 0 if none
  int64_t ranges = 0;
  double scale = 1.0, offset_m = 0.0;  // the range calibration fitted with it
  std::vector<double> residuals_m;     // each range's |residual|, in the order of the ranges given
};

// The ranges of `ranges` within [begin_utime, end_utime] whose beacon has at least three there.
std::vector<RangeRecord> rangesToScore(const std::vector<RangeRecord>& ranges, int64_t begin_utime,
                                       int64_t end_utime);

// The fit of `path` (ordered by time) to `ranges` (all within its time span), the beacons of
// `surveyed` held where it puts them; the range scale and offset fitted with the free beacons if
// `fit_calibration`, else held at 1 and 0.
RangeFit rangeFit(const Path& path, const std::vector<RangeRecord>& ranges, const Map& surveyed = {},
                  bool fit_calibration = false);

// A range between two robots of a team: taken by `robot` to `other_robot` (indices of the team).
struct RobotRangeRecord {
  int64_t utime = 0;
  int robot = 0;
  int other_robot = 0;
  double range_m = 0.0;
};

// The fit of a team's `paths` (indexed by robot, each ordered by time) to ranges between its
// robots (each within both robots' time spans); the range scale and offset fitted if
// `fit_calibration`, else held at 1 and 0.
RangeFit robotRangeFit(const std::vector<Path>& paths, const std::vector<RobotRangeRecord>& ranges,
                       bool fit_calibration = false);

}  // namespace roam
