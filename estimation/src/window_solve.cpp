#include "roam/estimation/window_solve.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>
#include <Eigen/Geometry>

namespace roam {
namespace estimation {

namespace {

Eigen::Vector2d perp(const Eigen::Vector2d& v) { return Eigen::Vector2d(-v.y(), v.x()); }

}  // namespace

WindowSolution solveWindow(const WindowProblem& problem) {
  WindowSolution out;
  const int m = static_cast<int>(problem.path.size()) - 1;  // steps
  const int num_landmarks = static_cast<int>(problem.landmarks_m.size());
  if (m < 1 || num_landmarks == 0 || problem.ranges.empty() || !problem.weight ||
      static_cast<int>(problem.heading_variance_rad2.size()) != m)
    return out;
  // Blocks: step j belongs to block floor(t_j / block_s), numbered in order of appearance.
  std::vector<int> block(m);
  std::vector<int> block_first;  // first step of each block
  std::vector<double> block_variance;
  long last_raw = 0;
  for (int j = 0; j < m; ++j) {
    const long raw = static_cast<long>(std::floor(problem.time_s[j] / problem.block_s));
    if (j == 0 || raw != last_raw) {
      block_first.push_back(j);
      block_variance.push_back(0.0);
    }
    last_raw = raw;
    block[j] = static_cast<int>(block_first.size()) - 1;
    block_variance.back() += problem.heading_variance_rad2[j];
  }
  const int num_blocks = static_cast<int>(block_first.size());
  out.heading_blocks = num_blocks;
  const bool with_range_scale = problem.range_scale_prior_sigma > 0.0;
  const int i_block = 2 * num_landmarks, i_range_scale = i_block + num_blocks;
  const int num = i_range_scale + (with_range_scale ? 1 : 0);
  double rs = problem.range_scale;

  std::vector<Eigen::Vector2d> landmarks = problem.landmarks_m;
  Eigen::VectorXd c = Eigen::VectorXd::Zero(num_blocks);
  std::vector<Eigen::Vector2d> q(m + 1);
  std::vector<double> turn(m);
  auto buildPath = [&] {
    q[0] = problem.path[0].head<2>();
    double cumulative = 0.0;
    for (int j = 0; j < m; ++j) {
      if (block_first[block[j]] == j) cumulative += c[block[j]];
      turn[j] = cumulative;
      const Eigen::Vector2d d = problem.path[j + 1].head<2>() - problem.path[j].head<2>();
      q[j + 1] = q[j] + Eigen::Rotation2Dd(turn[j]) * d;
    }
  };
  buildPath();
  Eigen::VectorXd row(num);
  Eigen::MatrixXd h;
  double log_posterior = 0.0;
  for (int iteration = 0; iteration <= problem.iterations; ++iteration) {
    log_posterior = 0.0;
    h = Eigen::MatrixXd::Zero(num, num);
    Eigen::VectorXd g = Eigen::VectorXd::Zero(num);
    for (const WindowRange& r : problem.ranges) {
      const int j = r.step;
      const double f = r.fraction;
      const Eigen::Vector2d x = (1.0 - f) * q[j] + f * q[j + 1];
      const Eigen::Vector2d delta = landmarks[r.landmark] - x;
      const double distance = delta.norm();
      if (!(distance > 1e-6)) continue;
      const Eigen::Vector2d u = delta / distance;
      const double e = r.range_m - (rs * distance + problem.range_offset_m);
      double log_likelihood = 0.0;
      const double w = problem.weight(r, e, &log_likelihood);
      log_posterior += log_likelihood;
      if (!(w > 0.0)) continue;
      // d(prediction)/dx = -rs u; dx/d(param) from the path's Jacobians.
      row.setZero();
      row.segment<2>(2 * r.landmark) = rs * u;
      const Eigen::Vector2d dx = -rs * u;
      for (int k = 0; k <= block[j]; ++k) {
        const int s = block_first[k];
        Eigen::Vector2d dq = Eigen::Vector2d::Zero();
        if (j > s) dq += (1.0 - f) * perp(q[j] - q[s]);
        if (j + 1 > s) dq += f * perp(q[j + 1] - q[s]);
        row[i_block + k] = dx.dot(dq);
      }
      if (with_range_scale) row[i_range_scale] = distance;
      h.selfadjointView<Eigen::Lower>().rankUpdate(row, w);
      g += w * e * row;
    }
    h.triangularView<Eigen::StrictlyUpper>() = h.transpose();
    // Priors as pseudo-observations; a landmark without inlier ranges stays where it is.
    for (int k = 0; k < 2 * num_landmarks; ++k) h(k, k) += 1e-9;
    for (int k = 0; k < num_blocks; ++k) {
      const double information = 1.0 / std::max(block_variance[k], 1e-12);
      h(i_block + k, i_block + k) += information;
      g[i_block + k] -= information * c[k];
      log_posterior -= 0.5 * information * c[k] * c[k];
    }
    if (with_range_scale) {
      const double information = 1.0 / (problem.range_scale_prior_sigma * problem.range_scale_prior_sigma);
      h(i_range_scale, i_range_scale) += information;
      g[i_range_scale] -= information * (rs - 1.0);
      log_posterior -= 0.5 * information * (rs - 1.0) * (rs - 1.0);
    }
    if (iteration == problem.iterations) break;  // the last pass only evaluates
    const Eigen::VectorXd step = h.ldlt().solve(g);
    if (!step.allFinite()) return out;
    for (int i = 0; i < num_landmarks; ++i) landmarks[i] += step.segment<2>(2 * i);
    c += step.segment(i_block, num_blocks);
    if (with_range_scale) rs += step[i_range_scale];
    buildPath();
  }
  {
    Eigen::VectorXd ones = Eigen::VectorXd::Zero(num);
    ones.segment(i_block, num_blocks).setOnes();
    out.end_turn_sigma_rad = std::sqrt(std::max(0.0, ones.dot(h.ldlt().solve(ones))));
  }
  out.path.resize(m + 1);
  out.path[0] = problem.path[0];
  for (int j = 0; j < m; ++j) {
    out.path[j + 1].head<2>() = q[j + 1];
    out.path[j + 1].z() = problem.path[j + 1].z() + turn[j];
  }
  out.landmarks_m = landmarks;
  out.log_posterior = log_posterior;
  out.range_scale = rs;
  out.solved = true;
  return out;
}

WindowProblem withPathHeld(WindowProblem problem) {
  for (double& v : problem.heading_variance_rad2) v = 1e-16;
  return problem;
}

}  // namespace estimation
}  // namespace roam
