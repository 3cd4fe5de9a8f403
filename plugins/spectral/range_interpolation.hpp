// Missing-range interpolation of Boots & Gordon 2013, Sec. 3.4.
//
// Model: inside a window of the dead-reckoned path (where dead reckoning differs from the truth
// by a rigid motion), the half squared range to beacon n is linear in the features of the
// dead-reckoned position p = (x, y):
//   d^2/2 = theta . phi(p),  phi(p) = [1, -x, -y, (x^2 + y^2)/2]                       (Eq. 5)
// (a rigid motion of p maps phi linearly into itself). theta is fitted by least squares to the
// window's ranges (the position at a range's time is interpolated linearly between poses), with
// p centred on the window and scaled to unit RMS radius, and a relative singular-value cut-off
// so that a near-straight window (phi nearly collinear) does not invent a fourth direction.
// The model predicts d^2/2 at every pose between that beacon's first and last range in the window
// (never beyond: no extrapolation across ranging gaps), and also the heading row of Eq. 9 in its
// zero-step limit, the derivative along the direction of travel u(heading_k):
//   r_k = grad(d^2/2) . u = (p_k - m) . u_k,
// which needs no division by a (possibly zero) step length. Predictions of all windows covering a
// pose are averaged, except that a fit whose ranges of that beacon span under half its window (the
// window reaches into a radio silence or past the beacon's last range: few ranges, one side) is
// used only where no fuller fit covers the pose. Windows are fixed in time: window w covers
// [t0 + w * stride, t0 + w * stride + window_s], stride = window_s * (1 - overlap).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "odometry_path.hpp"

namespace roam::spectral {

struct RangeSample {
  int64_t utime = 0;
  int beacon = 0;  // row index (0..num_beacons-1), not the beacon id
  double range_m = 0.0;
};

struct InterpolationConfig {
  double window_s = 30.0;
  double window_overlap = 0.5;
  int min_ranges_per_window = 8;
  double rcond = 1e-3;
  // Iteratively reweighted fit with Tukey's biweight on the range residual (scale from the
  // median absolute residual), so that NLOS outliers, which read metres long, drop out of the
  // window's model; false: the paper's plain least squares.
  bool robust = true;
  double range_sigma_m = 0.5;  // the robust fit's Huber scale
};

class RangeInterpolator {
 public:
  RangeInterpolator(int num_beacons, const InterpolationConfig& config, int64_t origin_utime);

  int64_t windowBegin(int window) const;
  int64_t windowEnd(int window) const;
  // Windows [0, n) are needed to cover poses up to `last_utime`.
  int windowsToCover(int64_t last_utime) const;

  // Fits the window's per-beacon models and adds their predictions. `ranges` sorted by time.
  void addWindow(int window, const OdometryPath& path, const std::vector<RangeSample>& ranges);

  // Averages at pose k; false if no window covered (beacon, k).
  bool halfSquaredRange(int beacon, int pose, double* value) const;
  bool rangeRate(int beacon, int pose, double* value) const;
  int numBeacons() const { return num_beacons_; }

 private:
  void grow(int poses);
  int num_beacons_;
  InterpolationConfig config_;
  int64_t origin_utime_;
  int64_t window_us_, stride_us_;
  // Which sums answer for (beacon, pose): 0 (fits whose ranges span at least half their window)
  // if any covered it, else 1 (the shorter fits), -1 if none.
  int part(int beacon, int pose) const;
  // [part][beacon][pose]
  std::array<std::vector<std::vector<double>>, 2> sum_half_sq_, sum_rate_;
  std::array<std::vector<std::vector<int>>, 2> count_;
};

}  // namespace roam::spectral
