// Initial guesses of the batch problem that need no other estimator.
//
// Dead reckoning: from the start pose, each step through the shared motion model
// (estimation::step of the calibrated increment; the deadreckoning plugin's convention).
// Beacons are multilaterated by estimation/multilateration.hpp (robust, from the guessed path, so
// a beacon inherits the path's errors: a seed only).
#pragma once

#include <array>
#include <vector>

#include "roam/estimation/motion_model.hpp"
#include "roam/types.hpp"

namespace roam {
namespace spectral_batch {

// dt_s[k]: duration of step k (empty: 0, so the heading-rate bias does not act).
std::vector<std::array<double, 3>> deadReckon(const std::array<double, 3>& start_pose,
                                              const std::vector<Odometry>& odometry,
                                              const std::vector<double>& dt_s = {},
                                              const estimation::OdometryCalibration& calibration = {});

// One step of dead reckoning from pose.
std::array<double, 3> propagate(const std::array<double, 3>& pose, const Odometry& odometry, double dt_s = 0.0,
                                const estimation::OdometryCalibration& calibration = {});

// Headings of a seed path made consistent with odometry: heading_k = dead-reckoned heading_k +
// delta_k, where delta_k is the rotation that best aligns (least squares, centred) the
// dead-reckoned positions to the seed positions over the poses within half_window_m of travelled
// distance of pose k. A window in distance, not time, keeps the fit well posed while the robot
// stands still (where the seed's own headings are arbitrary); over a window of L metres, position
// noise sigma gives a rotation error of ~sigma / (L sqrt(n / 12)), and odometry heading drift
// inside it stays small. Poses whose window spans no motion keep the seed heading. Unwrapped.
void headingsFromOdometryAlignment(const std::vector<Odometry>& odometry, double half_window_m,
                                   std::vector<std::array<double, 3>>* poses);

}  // namespace spectral_batch
}  // namespace roam
