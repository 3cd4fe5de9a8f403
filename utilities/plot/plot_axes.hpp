// Axes for roam-plot: "nice" tick steps (1, 2, 5 x 10^k), a data-to-pixel frame, tick marks with
// labels and grid lines, and a metre scale bar.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "svg_writer.hpp"

namespace roam {
namespace plot {

// Pixel margin around a figure's frames: tick labels left and below, title above.
constexpr double kOuterPx = 10;

// The bounding box of the finite points added (empty until one is).
struct Box {
  double x_lo = std::numeric_limits<double>::infinity(), x_hi = -std::numeric_limits<double>::infinity();
  double y_lo = std::numeric_limits<double>::infinity(), y_hi = -std::numeric_limits<double>::infinity();
  void add(double x, double y) {
    if (!std::isfinite(x) || !std::isfinite(y)) return;
    x_lo = std::min(x_lo, x); x_hi = std::max(x_hi, x);
    y_lo = std::min(y_lo, y); y_hi = std::max(y_hi, y);
  }
  bool empty() const { return !(x_lo <= x_hi); }
};

// The top of an error curve as the axis should show it: its largest error, or its 99th percentile
// where the largest is a spike beyond twice that (clipped, said "off the top" in the legend).
double curveTop(std::vector<double> errors_m);

// An error figure's axis top: the largest of the series' tops, but for series whose mean error is
// beyond five times the median of the means (dead reckoning drifting tens of metres: drawn off the
// top), with 5 % headroom, rounded up to the tick step it returns in *step (height_px / 70 ticks).
double errorAxisTop(const std::vector<double>& tops_m, const std::vector<double>& means_m, double height_px,
                    double* step);

// The smallest of 1, 2, 5 x 10^k that cuts `span` into at most `max_ticks` intervals (span > 0).
double niceStep(double span, int max_ticks);

// Multiples of `step` inside [lo, hi] (with a tolerance of 1e-9 step at both ends).
std::vector<double> tickValues(double lo, double hi, double step);

// A tick label with as many decimals as `step` needs ("10", "2.5", "0.25"); never "-0".
std::string tickLabel(double value, double step);

// A rectangle of pixels showing data [x_lo, x_hi] x [y_lo, y_hi], data y pointing up.
struct Frame {
  double left_px = 0, top_px = 0, width_px = 0, height_px = 0;
  double x_lo = 0, x_hi = 1, y_lo = 0, y_hi = 1;

  Point toPixel(double x, double y) const;
  double pixelsPerUnitX() const { return width_px / (x_hi - x_lo); }
  double pixelsPerUnitY() const { return height_px / (y_hi - y_lo); }
};

struct AxisLabels {
  std::string x, y;
  double x_step = 1, y_step = 1;  // tick steps in data units
};

// Light grid lines, a frame, ticks and their labels outside the frame, and the axis titles.
void drawAxes(SvgWriter& svg, const Frame& frame, const AxisLabels& labels);

// A bar of a nice length up to a fifth of the frame's width, labelled "<n> m", right-aligned
// below the frame under the tick labels (so it never hides data; it needs ~36 px of margin).
// The frame must be metric (pixels per metre equal in x and y).
void drawScaleBar(SvgWriter& svg, const Frame& frame);

// The panels of a paths figure over the area right of and below `outer_px` and below `header_px`:
// the grid of `panels` cells whose frames give the largest common metric scale to the world box
// [x_lo, x_hi] x [y_lo, y_hi], each frame centred on the box, and the tick step for that scale.
struct PanelGrid {
  std::vector<Frame> frames;
  AxisLabels labels;
};
PanelGrid panelGrid(double x_lo, double x_hi, double y_lo, double y_hi, size_t panels, double width_px,
                    double height_px, double header_px, double outer_px);

// An error figure's one frame below `header_px`: time [0, t_end_s] across, error [0, y_top_m] up,
// with room on the left and below for the tick labels and axis titles.
Frame errorFrame(double width_px, double height_px, double header_px, double t_end_s, double y_top_m);

// Pixel points of a data polyline, dropping points closer than `min_spacing_px` to the last kept
// one (the last point is always kept) and non-finite ones; coordinates far outside the frame are
// clamped so that a diverged estimate still writes short numbers (the frame's clip hides them).
std::vector<Point> toPixels(const Frame& frame, const std::vector<double>& xs, const std::vector<double>& ys,
                            double min_spacing_px = 0.7);

}  // namespace plot
}  // namespace roam
