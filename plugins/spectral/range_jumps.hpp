// Ranges in stretches that sit above both neighbours by more than the robot can have moved.
//
// Model: a range to a fixed beacon changes between two of its ranges by at most the distance the
// robot travelled in between (the triangle inequality), so |r_j - r_i| <= kappa D_ij + c sqrt(2)
// sigma_r, with D_ij the dead-reckoned distance between the two times, kappa the largest
// product of a range scale and an odometry distance correction the run can hold, and c sigma_r
// the range noise. A pair beyond it is a jump: one side is off. Non-line-of-sight only adds
// (a UWB radio's first path is never shorter than the straight line), so each beacon's ranges are
// cut at the jumps into stretches, and a stretch entered by a jump up and left by a jump down is
// long throughout: an NLOS stretch, every range of it off by about one excess, which no window
// fit can tell from the beacon's true distance. Such stretches are returned for dropping. One
// that opens or closes the run has one neighbour to vouch for it (a short range would do the
// same) and is kept. A beacon for which they would be more than half its ranges keeps them all
// (the bound does not hold there: a beacon that moves, a time stamp off).
#pragma once

#include <vector>

#include "odometry_path.hpp"
#include "range_interpolation.hpp"

namespace roam::spectral {

struct RangeJumpBound {
  double max_scale = 1.3;  // kappa: ranges up to 20 % long against odometry up to 8 % short
  double sigmas = 4.0;     // c
  double range_sigma_m = 0.5;
};

// true for each range (in the order given) that lies in an NLOS stretch as above.
std::vector<bool> rangesInJumpStretches(const OdometryPath& path, const std::vector<RangeSample>& ranges,
                                        int num_beacons, const RangeJumpBound& bound);

}  // namespace roam::spectral
