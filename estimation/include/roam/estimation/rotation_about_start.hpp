// The rotation gauge of anchor = start_pose.
//
// With no beacon surveyed, turning a solved path and its map about the first pose changes no range
// residual; the start pose fixes the position, and the rotation is taken from the odometry. It is
// the rotation about the first pose that best aligns (least squares) the solved displacements
// p_k = x_k - x_0 onto the reference's d_k = r_k - r_0 (dead reckoning from the start pose) over
// the first window_m of travel; in 2-D the minimiser of sum_k |R(a) p_k - d_k|^2 is closed form:
//   a = atan2(sum_k p_k x d_k, sum_k p_k . d_k).
// About the start, not about the stretch's centroid: dead reckoning from the start pose is exact at
// the start, and the direction of a displacement from it carries the heading error averaged along
// the way. Used by spectral (gauge_about_start) and spectral_batch (gauge = window).
#pragma once

#include <array>
#include <vector>

namespace roam {
namespace estimation {

struct StartRotation {
  double angle_rad = 0.0;    // turn the solved path (and map) by this about its first pose
  double travelled_m = 0.0;  // travel the fit covered: window_m and one step, or the whole run
  bool defined = false;      // false: no displacement in the window (no travel)
};

// solved_m and reference_m: positions (m) of the same poses; step_m[k]: travel from pose k to
// k + 1 (m), what measures the window. Poses k = 1.. enter while the travel before them is at most
// window_m. Sizes must agree (step_m one shorter); throws std::invalid_argument otherwise.
StartRotation fitRotationAboutStart(const std::vector<std::array<double, 2>>& solved_m,
                                    const std::vector<std::array<double, 2>>& reference_m,
                                    const std::vector<double>& step_m, double window_m);

}  // namespace estimation
}  // namespace roam
