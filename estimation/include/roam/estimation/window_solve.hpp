// The early window solved jointly (anchor = start_pose): the path from the start and the map
// that its ranges place, instead of the map multilaterated from the dead-reckoned mean path as
// if that path were known.
//
// Model (the filter's own, restricted to the window; MAP by iteratively reweighted Gauss-Newton):
// the nominal path p_0 .. p_m (the filter's mean poses; p_0 = the known start pose) is off by a
// heading error that grows as the odometry's heading random walk (a heading-rate bias is the
// filter's, already in the nominal path):
//   q_0 = p_0,  q_{j+1} = q_j + R(D_j) (p_{j+1} - p_j),  D_j = C_{k(j)},
//   C_k = c_0 + ... + c_k (piecewise constant over blocks of block_s seconds, k(j) the block of
//   step j), c_k ~ N(0, sum of the block's per-step heading variances: the random walk's
//   increment over the block). (The distance scale is left out: from the start pose it is a
//   gauge with the range scale, fixed only by their priors.)
// A range r to landmark i, taken a fraction f into step j, reads
//   r = rs |m_i - x| + off + delta,  x = q_j + f (q_{j+1} - q_j),
// with the range scale rs an unknown too (prior N(1, sigma_rs^2), the filter's: UWB ranges run a
// few % long, and with rs held the window bends its path to fit them),
// delta the filter's mixture: each iteration weighs a range by its posterior inlier probability
// over the inlier variance (weight(), the EM of the mixture with the indicators marginalised).
// Jacobians (exact for this parametrisation): dq_j/dc_k = J (q_j - q_{s_k}) for j > s_k (the path
// after the block's first pose turns about it), J = [[0, -1], [1, 0]]. The start pose fixes the gauge.
#pragma once

#include <functional>
#include <vector>

#include <Eigen/Core>

namespace roam {
namespace estimation {

struct WindowRange {
  int landmark = 0;     // index into the solve's landmarks
  int step = 0;         // between path pose step and step + 1
  double fraction = 1.0;
  double range_m = 0.0;
  double sigma_m = 0.0;  // the range's noise (its own, or range_sigma_m)
};

struct WindowProblem {
  std::vector<Eigen::Vector3d> path;  // nominal poses (x, y, heading), path[0] = the start pose
  std::vector<double> time_s;         // time of each pose since the start
  std::vector<WindowRange> ranges;
  std::vector<Eigen::Vector2d> landmarks_m;  // initial positions
  double range_scale = 1.0, range_offset_m = 0.0;
  // > 0: the range scale is an unknown with prior N(1, sigma^2), starting at range_scale.
  double range_scale_prior_sigma = 0.0;
  std::vector<double> heading_variance_rad2;  // per step: the heading walk's increment variance
  double block_s = 5.0;
  int iterations = 10;
  // (1 - P(outlier)) / inlier variance of range r with residual e_m (range minus prediction);
  // *log_likelihood = its mixture log-likelihood.
  std::function<double(const WindowRange&, double e_m, double* log_likelihood)> weight;
};

struct WindowSolution {
  std::vector<Eigen::Vector3d> path;  // corrected poses
  std::vector<Eigen::Vector2d> landmarks_m;
  double range_scale = 1.0;
  double end_turn_sigma_rad = 0.0;  // posterior sigma of the heading correction at the end
  double log_posterior = 0.0;       // at the solution: ranges' mixture log-likelihood + log priors
  int heading_blocks = 0;           // the heading random walk's blocks (one unknown each)
  bool solved = false;
};

WindowSolution solveWindow(const WindowProblem& problem);

// The same problem with the path held at its nominal poses (heading walk pinned; the
// landmarks and the range scale still free): the null hypothesis of the likelihood-ratio test
// that decides whether a window's ranges refute its dead-reckoned path (twice the gain in
// log_posterior of the free solve over this one).
WindowProblem withPathHeld(WindowProblem problem);

}  // namespace estimation
}  // namespace roam
