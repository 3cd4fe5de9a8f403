// Online spectral SLAM (Boots & Gordon 2013, Sec. 3.4 "Online Spectral SLAM").
//
// Each time the input passes the end of an interpolation window, that window is fitted; poses
// before the start of the next window are then final (no later window covers them), their
// columns of Y are added to a rank-k incremental SVD (Brand 2006), the metric upgrade is redone
// on the current factors, and their poses are returned. Poses with no complete column (ranging
// gaps) are bridged as in the batch solve.
//
// Self-check before publishing (the batch one, on what has been seen): nothing is published
// until the upgrade is possible and, on the data so far, the windows fit their ranges
// (max_local_residual_sigma) and the solution explains them (max_residual_ratio). Until then the
// final poses are held (holdReason() says why) and go out with the first solution that passes.
// A check that fails later holds again; poses already published stay published.
#pragma once

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "incremental_svd.hpp"
#include "range_interpolation.hpp"
#include "spectral_config.hpp"
#include "spectral_solver.hpp"

namespace roam::spectral {

class OnlineSpectral {
 public:
  explicit OnlineSpectral(const SpectralConfig& config);

  // False for a beacon first seen after the beacon rows were fixed (the first window closed).
  bool acceptsBeacon(int id, const SpectralProblem& problem) const;
  // Processes the windows the path has passed; returns the newly final poses, oldest first.
  std::vector<Pose> advance(const SpectralProblem& problem);
  // End of input: the poses not yet published, taken from the batch solution.
  std::vector<Pose> flush(const SpectralProblem& problem, const SpectralSolution& batch);

  // The trajectory of the final poses from the current incremental factors (for tests).
  Path currentTrajectory(const SpectralProblem& problem) const;
  // The path published so far (pose 0 = the start pose).
  const Path& published() const { return published_; }
  // Why final poses are being held ("" while publishing).
  const std::string& holdReason() const { return hold_reason_; }

 private:
  std::vector<Pose> publishUpTo(const SpectralProblem& problem, int end_pose);

  SpectralConfig config_;
  std::unique_ptr<RangeInterpolator> interpolator_;
  IncrementalSvd svd_;
  int next_window_ = 0;
  int final_end_ = 1;  // poses [0, final_end_) are final
  std::vector<int> column_poses_;  // poses with a complete column, in order
  Eigen::MatrixXd columns_;        // their columns of Y (grown in blocks)
  Path published_;
  std::string hold_reason_ = "spectral online: no window closed yet";
};

}  // namespace roam::spectral
