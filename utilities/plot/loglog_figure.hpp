// A log-log line chart: named series of (x, y) > 0, decade grid lines, a legend. Used for the
// spectral paper's Fig. 1B (roam-spectral-fig1b) and the scaling study.
#pragma once

#include <string>
#include <vector>

namespace roam {
namespace plot {

struct LogLogSeries {
  std::string name;
  std::vector<double> x, y;  // points with x <= 0 or y <= 0 are left out
  std::string colour = "#0072B2";
  bool dashed = false;
  bool markers = true;       // a dot at each point
};

struct LogLogFigure {
  std::string title, x_label, y_label;
  int width_px = 860, height_px = 560;
  std::vector<LogLogSeries> series;
  bool legend_top_left = false;  // the legend box at the top left instead of the top right
                                 // (series rising to the right: times against problem size)
};

// The figure as an SVG document. Throws std::invalid_argument if no series has a usable point.
std::string logLogFigureSvg(const LogLogFigure& figure);

// "1000", "0.01", "3e+06": a compact label for a tick value.
std::string logTickLabel(double value);

}  // namespace plot
}  // namespace roam
