// Spectral range-only SLAM (Boots & Gordon, "A Spectral Learning Approach to Range-Only SLAM",
// ICML 2013) as a roam::Estimator.
//
// Model: the half squared range from pose t to beacon n factors as
//   d_nt^2 / 2 = C_n . X_t,  C_n = [|m_n|^2/2, m_nx, m_ny, 1],  X_t = [1, -x_t, -y_t, |p_t|^2/2]
// (rank 4, Eq. 4-7), and with the range rate along the direction of travel u_t = (cos, sin)
//   (p_t - m_n) . u_t = [m_nx, m_ny, 1] . [-cos(theta_t), -sin(theta_t), p_t . u_t]
// (rank 7, Eq. 8-11, zero-step limit). Sparse ranges are interpolated in windows of dead
// reckoning (range_interpolation.hpp), Y is factored by a thin SVD (thin_svd.hpp), and the
// factors are upgraded to metric coordinates (metric_upgrade.hpp): see spectral_solver.hpp.
//
// Inputs: INITIAL_POSE (pose 0; the origin at the first odometry time if none), BEACONS (used by
// anchor = beacons), then odometry and ranges in time order. A range is placed on the
// dead-reckoned path at its own time (linear between poses). Poses: one per odometry step plus the
// start pose. mode = batch: every pose at finish(). mode = online: the path is solved by an
// incremental SVD (Brand 2006, incremental_svd.hpp) each time an interpolation window closes and
// the poses that no later window can change are emitted, so a pose comes out at most
// window_s (+ one stride) after its odometry; at finish() the batch solution is the trajectory.
//
// Frame: the solve runs in a local frame, world = local + origin(). The model squares positions
// (|m_n|^2/2 in C_n, |p_t|^2/2 in X_t), and at map-grid coordinates (UTM northings of 4.6e6 m)
// those squares cancel every digit of a metre: surveyed beacons read as collinear and the start
// pose's solve misfits by metres. origin() is fixed at the start pose or the first odometry or
// range, whichever comes first: near the start pose if given, else near the surveyed beacons'
// centroid (anchor = beacons), else at zero, snapped to a kOriginGrid_m grid, so a run within 500 m
// of its frame's origin is solved exactly as given. Without a start pose the path starts at the
// local frame's origin (the world origin, unless surveyed beacons far from it moved it). Inputs
// are moved into the local frame as they arrive; POSE, MAP, TRAJECTORY and solution() are in the
// world frame, problem() in the local one.
#pragma once

#include <map>
#include <memory>
#include <optional>

#include "range_interpolation.hpp"
#include "roam/estimator.hpp"
#include "spectral_config.hpp"
#include "spectral_solver.hpp"

namespace roam::spectral {

class OnlineSpectral;

class SpectralSlam : public Estimator {
 public:
  // Throws ConfigError naming the key if the config breaks a declared check.
  explicit SpectralSlam(const SpectralConfig& config);
  ~SpectralSlam() override;

  void setInitialPose(const Pose& start) override;
  void setBeacons(const Map& surveyed) override;
  void addOdometry(const Odometry& odometry) override;
  void addRange(const Range& range) override;
  // Runs the batch solve. Data too thin to solve (fewer than 4 beacons, ...) end the run without
  // a solution, counted as "data: <reason>" in the rejections; other errors throw.
  void finish() override;
  bool trajectory(bool force, Path* path) override;

  const SpectralConfig& config() const { return config_; }
  // The batch solution (after finish()).
  const std::optional<SpectralSolution>& solution() const { return solution_; }
  // The problem as collected so far (dead-reckoned path, ranges, beacons), in the local frame.
  const SpectralProblem& problem() const { return problem_; }
  // The local frame's origin in the world frame (zero until the run gives a position).
  const Eigen::Vector2d& origin() const { return origin_m_; }
  static constexpr double kOriginGrid_m = 1000.0;
  // mode = online: the incremental solver (nullptr in batch mode).
  const OnlineSpectral* online() const { return online_.get(); }

 private:
  int beaconRow(int id);
  void startPath(const Pose& start_local);
  // Fixes the local frame's origin, unless it is fixed already, near the start pose if given,
  // else near the surveyed beacons' centroid (anchor = beacons), else at zero.
  void fixOrigin(const std::optional<Eigen::Vector2d>& start_m);
  Pose toWorld(Pose local) const;
  std::optional<Eigen::Vector2d> surveyedLocal(int id) const;
  void noSolution(const std::string& reason);
  // mode = online, no solution at the end after poses went out live: the final TRAJECTORY is
  // empty, so what was published is withdrawn rather than scored as the answer.
  bool withdrawn_ = false;

  SpectralConfig config_;
  SpectralProblem problem_;
  Map surveyed_;  // as given (world frame)
  Eigen::Vector2d origin_m_ = Eigen::Vector2d::Zero();
  bool have_origin_ = false;
  bool have_start_ = false;
  std::optional<SpectralSolution> solution_;
  std::unique_ptr<OnlineSpectral> online_;
};

}  // namespace roam::spectral
