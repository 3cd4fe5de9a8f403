// PREFIX-paths.svg: ground truth, each estimator's scored path, true beacons and each
// estimator's last map (2-sigma ellipses where the beacon covariance is finite), in metres with
// equal x and y scales — one panel per estimator on one shared window and scale, or an overlay.
//
// The window holds the ground truth and the true beacons, widened to take in the estimates but
// by at most half the ground truth's size on each side (a diverged estimate is clipped, not
// allowed to shrink everything else).
#pragma once

#include <string>
#include <vector>

#include "figure_options.hpp"
#include "plot_series.hpp"
#include "result_log.hpp"

namespace roam {
namespace plot {

std::string pathsFigureSvg(const ResultLog& log, const std::vector<Series>& series, const FigureOptions& options);

// The 2-sigma ellipse of a row-major 2x2 covariance [a b; b c]: semi-axes (m) and the angle of
// the major axis (rad, CCW from x). False when the covariance is not finite or not PSD.
struct Ellipse {
  double major_m = 0, minor_m = 0, angle_rad = 0;
};
bool twoSigmaEllipse(double a, double b, double c, Ellipse* ellipse);

}  // namespace plot
}  // namespace roam
