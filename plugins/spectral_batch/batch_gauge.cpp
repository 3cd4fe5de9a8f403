// The rotation gauge of anchor = start_pose (model in spectral_batch_slam.hpp): rotation about
// pose 0 changes no residual when no beacon is fixed, so the solve leaves it to a choice.
// - alignRotationToOdometry (gauge = window, the default): the rotation that best aligns the
//   solved positions over the first gauge_align_m of travel onto the calibrated dead reckoning
//   from the start pose (roam/estimation/rotation_about_start.hpp);
// - pinStartHeading (gauge = pinned): pose 0 turned onto the start heading and held there;
// - rotateAboutStart: the rigid turn of poses and beacons about pose 0 both apply.
#include <array>
#include <cmath>
#include <utility>
#include <vector>

#include "initial_guess.hpp"
#include "roam/estimation/rotation_about_start.hpp"
#include "spectral_batch_slam.hpp"

namespace roam {
namespace spectral_batch {

void SpectralBatchSlam::alignRotationToOdometry(spectral_batch::State* state) {
  // Rotation about pose 0 leaves every residual unchanged (no beacon is fixed): the gauge. It is
  // set as the spectral core sets it: the rotation that best aligns (least squares) the solved
  // positions over the first gauge_align_m of travel to the calibrated dead reckoning from the
  // start pose. Calibrated: with the gyro bias removed, the first metres of odometry are better
  // than one start heading, and far better than a spectral seed fitted to biased odometry.
  const std::vector<std::array<double, 3>>& poses = state->poses;
  const estimation::OdometryCalibration calibration{state->odometry_calibration[0], state->odometry_calibration[1]};
  const std::vector<std::array<double, 3>> dr = spectral_batch::deadReckon(start_pose_, odometry_, dt_s_, calibration);
  std::vector<std::array<double, 2>> solved_m, reference_m;
  std::vector<double> step_m;
  for (size_t k = 0; k < poses.size(); ++k) {
    solved_m.push_back({poses[k][0], poses[k][1]});
    reference_m.push_back({dr[k][0], dr[k][1]});
    if (k > 0) step_m.push_back(std::hypot(odometry_[k - 1].forward_m, odometry_[k - 1].lateral_m));
  }
  const estimation::StartRotation fit =
      estimation::fitRotationAboutStart(solved_m, reference_m, step_m, config_.gauge_align_m);
  if (fit.travelled_m < 0.5 * config_.gauge_align_m || !fit.defined) return;
  rotateAboutStart(state, fit.angle_rad);
}

void SpectralBatchSlam::rotateAboutStart(spectral_batch::State* state, double angle_rad) {
  std::vector<std::array<double, 3>>& poses = state->poses;
  const double c = std::cos(angle_rad), s = std::sin(angle_rad);
  const double ox = poses[0][0], oy = poses[0][1];
  auto rotate = [&](double* x, double* y) {
    const double rx = *x - ox, ry = *y - oy;
    *x = ox + c * rx - s * ry;
    *y = oy + s * rx + c * ry;
  };
  for (auto& pose : poses) {
    rotate(&pose[0], &pose[1]);
    pose[2] += angle_rad;
  }
  for (auto& beacon : state->beacons) rotate(&beacon[0], &beacon[1]);
  setDiagnostic("gauge_rotation_rad", angle_rad);
}

void SpectralBatchSlam::pinStartHeading(Candidate* candidate) {
  spectral_batch::Problem& problem = candidate->problem;
  spectral_batch::State& state = candidate->state;
  if (state.poses.empty()) return;
  // Rotation about pose 0 changes no residual (no beacon fixed): holding the start heading only
  // picks the gauge, so the cost is the same and one warm solve settles it.
  if (problem.fix_first_heading) return;
  rotateAboutStart(&state, wrapAngle(start_pose_[2] - state.poses[0][2]));
  problem.fix_first_heading = true;
  spectral_batch::State trial_state = state;
  spectral_batch::Summary trial = spectral_batch::solve(config_, problem, &trial_state);
  if (!trial.usable) return;
  trial.iterations += candidate->summary.iterations;
  state = std::move(trial_state);
  candidate->summary = trial;
}

}  // namespace spectral_batch
}  // namespace roam
