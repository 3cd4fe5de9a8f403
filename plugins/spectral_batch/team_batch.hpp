// spectral_batch's team mode: the inputs of a team run gathered per robot, and at the end of
// input one solve of the whole team (team_solve.hpp: every robot's poses and odometry calibration,
// the ranges between robots and to surveyed beacons, the noise learned from the data).
//
// Anchor: the robots' start poses that came (INITIAL_POSE_<robot>), held. A robot whose start
// never came is placed from its ranges (team_starts.hpp) and solved, or, where its ranges cannot
// place it, left in its own frame; a note says which, and why. The spectral seed is a one-robot
// method and is not used: the team is seeded by each robot's dead reckoning.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "batch_config.hpp"
#include "roam/types.hpp"
#include "team_solve.hpp"

namespace roam {
namespace spectral_batch {

class TeamBatch {
 public:
  TeamBatch(const SpectralBatchConfig& config, const std::vector<std::string>& robots);

  void setInitialPose(const Pose& start);
  void setBeacons(const Map& surveyed) { input_.beacons = surveyed; }
  // False if the step goes back in its robot's time (rejected: the caller counts it).
  bool addOdometry(const Odometry& odometry);
  // False if the range goes back in time on its robot (rejected).
  bool addRange(const Range& range);
  // Solves the team (std::invalid_argument on input the solve cannot take).
  void finish();

  bool solved() const { return result_.has_value(); }
  const TeamResult& result() const { return *result_; }
  // Every robot's path, robot by robot (Pose::robot set), solved or (before finish) dead reckoned.
  Path paths() const;
  // Notes for the end of the run: starts that never came, the solve's own notes.
  std::vector<std::string> notes() const;

 private:
  SpectralBatchConfig config_;
  std::vector<std::string> robots_;
  TeamInput input_;
  std::vector<bool> have_start_;
  std::optional<TeamResult> result_;
};

}  // namespace spectral_batch
}  // namespace roam
