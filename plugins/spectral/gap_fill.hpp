// Step 4 of the batch solve: poses the interpolation did not cover (radio silences, the run's
// ends) are filled from the calibrated odometry, held by the solved poses on both sides.
//
// Model. Inside a run of unsolved poses between solved poses a and b, the fill is the
// dead-reckoned segment, turned by a heading offset that changes linearly along the distance
// travelled and scaled:
//   p_i = P_a + s sum_{m = a}^{i-1} R(alpha + beta f_m) (DR_{m+1} - DR_m),  f_m the fraction of
//   the segment's distance at the middle of step m,
// with (alpha, beta, s) the weighted least squares of
//   (p_b - P_b) / sigma_p        (the segment must end on the solved pose b; 2 rows)
//   (alpha - phi_a) / sigma_a    (the heading offset of the solved stretch before the gap)
//   (alpha + beta - phi_b) / sigma_b   (... and of the solved stretch after it)
//   (s - 1) / kScaleSigma        (the path is calibrated: its scale is right to a few %)
// phi_a, phi_b are rotation fits of the solved positions onto dead reckoning over up to
// `stretch_s` of contiguous solved poses beside the gap (the direction of travel of the solved
// path, not the heading of the window-edge pose), sigma_a, sigma_b their standard errors from the
// fits' own residuals, sigma_p the residual scatter of the solved positions about those fits. A
// long chord P_b - P_a fixes the rotation; on a segment that turns back (chord short), the two
// stretch headings do. What mismatch is left at b is spread along the distance, so the fill ends
// exactly on b. A run of unsolved poses with a solved pose on one side only (start or end of the
// run) is dead-reckoned from it with that side's stretch heading and no scale change.
// Before the fill, the solved poses beside each gap are checked: those near the gap that the rigid
// fit of the stretch's far half (onto dead reckoning) misses by more than 4x its scatter and 2 m
// rested on windows that saw ranges on one side only, and are filled too.
#pragma once

#include <vector>

#include "odometry_path.hpp"
#include "roam/types.hpp"

namespace roam::spectral {

// out: one pose per pose of path; the poses with solved[k] hold their solution (x, y and
// heading), the rest are filled. heading_offset_rad[k] (learned - dead-reckoned heading) is used
// at a solved pose beside a gap when no stretch fit is possible there (fewer than 3 solved poses,
// or no extent). stretch_s: how far beside a gap the stretch fits reach (seconds of poses).
void fillUnsolvedPoses(const OdometryPath& path, const std::vector<bool>& solved,
                       const std::vector<double>& heading_offset_rad, double stretch_s, Path& out);

}  // namespace roam::spectral
