// Scoring a path against ground truth: the numbers of the spectral paper's Figure 3.
//
// Matching: every ground-truth pose whose time lies inside the estimate's time span
// [first, last] is matched to the estimate's position interpolated linearly between the two
// estimate poses that bracket its time (an estimate pose at exactly that time is used as is).
// The estimate is first put in time order (stable); of poses with equal time the last counts.
// Errors are Euclidean position errors (m). Ten segments: the matched rows in time order cut
// into 10 equal consecutive chunks, chunk c = rows [floor(c n / 10), floor((c+1) n / 10));
// last 10 % = chunk 9; best / worst 10 % = the non-empty chunk with the lowest / highest mean
// error (its RMSE is reported alongside). Aligned: the estimate (and its map) are first moved
// by the rigid 2-D motion (rotation + translation, no scale) that best fits the matched
// estimate positions to ground truth in least squares.
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "roam/types.hpp"

namespace roam {

struct MatchedPosition {
  int64_t utime = 0;
  double estimate_x_m = 0.0, estimate_y_m = 0.0;
  double truth_x_m = 0.0, truth_y_m = 0.0;
  double error_m() const;
};

std::vector<MatchedPosition> matchToGroundTruth(const Path& estimate, const Path& ground_truth);

// truth ≈ R(angle) * estimate + translation
struct Rigid2D {
  double angle_rad = 0.0;
  double tx_m = 0.0, ty_m = 0.0;
  void apply(double* x_m, double* y_m) const;
};
Rigid2D fitRigid2D(const std::vector<MatchedPosition>& matched);
// One motion fitted to several paths' matches together (a team's robots): the least-squares fit
// over all their positions as one set.
Rigid2D fitRigid2D(const std::vector<std::vector<MatchedPosition>>& paths);

struct ErrorStats {
  size_t count = 0;
  double mean_m = kNaN;
  double rmse_m = kNaN;
};
ErrorStats errorStats(const std::vector<double>& errors_m, size_t begin, size_t end);

// Mean distance (m) of estimated to true beacons matched by id, the estimate moved by `fit` if
// given; NaN when no id matches. *compared (if given) = the number matched.
double beaconError(const Map& estimated_map, const Map& true_map, const std::optional<Rigid2D>& fit,
                   size_t* compared = nullptr);

struct PathScore {
  size_t matched = 0;
  ErrorStats full, last10, best10, worst10;
  double max_m = kNaN;
  double beacon_error_m = kNaN;  // mean distance of estimated to true beacons, by id
  size_t beacons_compared = 0;
  std::optional<Rigid2D> alignment;  // when aligned
};

PathScore scorePath(const Path& estimate, const Path& ground_truth, bool aligned,
                    const std::optional<Map>& estimated_map = std::nullopt,
                    const std::optional<Map>& true_map = std::nullopt);

}  // namespace roam
