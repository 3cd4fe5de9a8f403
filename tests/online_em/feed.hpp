// The online EM tests' helpers: the shared feeder (tests/common/feed.hpp, roam-run's order) and
// path and map scores.
#pragma once

#include <cmath>
#include <vector>

#include "../common/feed.hpp"
#include "roam/estimation/motion_model.hpp"

namespace roam {
namespace online_em_test {

using roam::test::feed;

// Mean position error of `path` against `truth`, matched by utime (poses without a match skipped).
inline double meanError(const Path& path, const Path& truth, double* rmse = nullptr, double* last10 = nullptr) {
  size_t j = 0;
  std::vector<double> errors;
  for (const Pose& p : path) {
    while (j < truth.size() && truth[j].utime < p.utime) ++j;
    if (j == truth.size()) break;
    if (truth[j].utime != p.utime) continue;
    errors.push_back(std::hypot(p.x_m - truth[j].x_m, p.y_m - truth[j].y_m));
  }
  double sum = 0.0, sum2 = 0.0, tail = 0.0;
  const size_t tail_start = errors.size() - errors.size() / 10;
  for (size_t k = 0; k < errors.size(); ++k) {
    sum += errors[k];
    sum2 += errors[k] * errors[k];
    if (k >= tail_start) tail += errors[k];
  }
  if (rmse) *rmse = std::sqrt(sum2 / errors.size());
  if (last10) *last10 = tail / static_cast<double>(errors.size() - tail_start);
  return sum / errors.size();
}

// Mean distance of the estimated beacons to the true ones (by id; missing ones count as NaN).
inline double mapError(const Map& estimate, const Map& truth) {
  double sum = 0.0;
  for (const Beacon& t : truth) {
    double e = std::nan("");
    for (const Beacon& b : estimate)
      if (b.id == t.id) e = std::hypot(b.x_m - t.x_m, b.y_m - t.y_m);
    sum += e;
  }
  return sum / truth.size();
}

// Mean error of the run's own odometry composed from the start pose (dead reckoning).
inline double deadReckoningError(const Dataset& data) {
  Path path;
  Eigen::Vector3d pose(data.start.x_m, data.start.y_m, data.start.heading_rad);
  int64_t utime = data.start.utime;
  Pose p = data.start;
  path.push_back(p);
  for (const Odometry& odometry : data.odometry) {
    const double dt_s = 1e-6 * static_cast<double>(odometry.utime - utime);
    pose = estimation::step(pose, estimation::calibratedIncrement(odometry, dt_s, estimation::OdometryCalibration{}));
    utime = odometry.utime;
    p.utime = utime;
    p.x_m = pose.x();
    p.y_m = pose.y();
    path.push_back(p);
  }
  return meanError(path, data.ground_truth);
}

}  // namespace online_em_test
}  // namespace roam
