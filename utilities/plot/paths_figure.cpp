#include "paths_figure.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "plot_axes.hpp"
#include "plot_marks.hpp"
#include "svg_writer.hpp"

namespace roam {
namespace plot {
namespace {


Box window(const ResultLog& log, const std::vector<Series>& series) {
  Box core;
  for (const Pose& p : log.ground_truth) core.add(p.x_m, p.y_m);
  if (log.beacons)
    for (const Beacon& b : *log.beacons) core.add(b.x_m, b.y_m);
  if (core.empty()) {  // no truth: the estimates themselves
    for (const Series& s : series)
      for (const Pose& p : s.path) core.add(p.x_m, p.y_m);
  }
  if (core.empty()) core.add(0, 0);
  const double size = std::max({core.x_hi - core.x_lo, core.y_hi - core.y_lo, 1.0});
  const double cap = 0.5 * size;
  Box box = core;
  auto widen = [&](double x, double y) {
    if (!std::isfinite(x) || !std::isfinite(y)) return;
    box.add(std::clamp(x, core.x_lo - cap, core.x_hi + cap), std::clamp(y, core.y_lo - cap, core.y_hi + cap));
  };
  for (const Series& s : series) {
    for (const Pose& p : s.path) widen(p.x_m, p.y_m);
    if (s.map)
      for (const Beacon& b : *s.map) widen(b.x_m, b.y_m);
  }
  const double pad = 0.04 * std::max({box.x_hi - box.x_lo, box.y_hi - box.y_lo, 1.0});
  box.x_lo -= pad; box.x_hi += pad; box.y_lo -= pad; box.y_hi += pad;
  return box;
}

std::string meanLabel(double mean_m) {
  if (!std::isfinite(mean_m)) return "no matched poses";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "mean error %.2f m", mean_m);
  return buffer;
}

void drawSeries(SvgWriter& svg, const Frame& frame, const Series& s) {
  std::vector<double> xs, ys;
  for (const Pose& p : s.path) { xs.push_back(p.x_m); ys.push_back(p.y_m); }
  svg.polyline(toPixels(frame, xs, ys), estimateStroke(s.colour, s.dashed), "estimate", s.name);
  if (!s.map) return;
  for (const Beacon& b : *s.map) {
    if (!std::isfinite(b.x_m) || !std::isfinite(b.y_m)) continue;
    const Point c = frame.toPixel(b.x_m, b.y_m);
    Ellipse e;
    if (twoSigmaEllipse(b.covariance[0], b.covariance[1], b.covariance[3], &e)) {
      const double px = frame.pixelsPerUnitX();
      svg.ellipse(c.x, c.y, std::max(e.major_m * px, 0.5), std::max(e.minor_m * px, 0.5),
                  -e.angle_rad * 180.0 / M_PI, "none", Stroke{s.colour, 1.0, "3 2"});
    }
    drawEstimatedBeacon(svg, c.x, c.y, s.colour);
  }
}

void drawTruth(SvgWriter& svg, const Frame& frame, const ResultLog& log) {
  std::vector<double> xs, ys;
  for (const Pose& p : log.ground_truth) { xs.push_back(p.x_m); ys.push_back(p.y_m); }
  if (!xs.empty()) svg.polyline(toPixels(frame, xs, ys), truthStroke(), "truth", "ground truth");
}

void drawTruthMarks(SvgWriter& svg, const Frame& frame, const ResultLog& log) {
  if (!log.ground_truth.empty()) {
    const Point s = frame.toPixel(log.ground_truth.front().x_m, log.ground_truth.front().y_m);
    drawStart(svg, s.x, s.y);
  }
  if (!log.beacons) return;
  TextStyle id;
  id.size_px = 11;
  id.colour = "#222222";
  const double right = frame.left_px + frame.width_px, bottom = frame.top_px + frame.height_px;
  for (const Beacon& b : *log.beacons) {
    const Point c = frame.toPixel(b.x_m, b.y_m);
    if (c.x < frame.left_px || c.x > right || c.y < frame.top_px || c.y > bottom) continue;
    drawTrueBeacon(svg, c.x, c.y);
    const bool near_right = c.x > right - 24;  // label on the left, inside the frame
    id.anchor = near_right ? "end" : "start";
    svg.text(near_right ? c.x - 8 : c.x + 8, c.y - 6, std::to_string(b.id), id);
  }
}

}  // namespace

bool twoSigmaEllipse(double a, double b, double c, Ellipse* ellipse) {
  if (!std::isfinite(a) || !std::isfinite(b) || !std::isfinite(c)) return false;
  const double mean = 0.5 * (a + c), half_diff = 0.5 * (a - c);
  const double radius = std::hypot(half_diff, b);
  const double l1 = mean + radius, l2 = mean - radius;
  if (l2 < -1e-12 * std::max(1.0, std::fabs(l1)) || l1 <= 0) return false;
  ellipse->major_m = 2.0 * std::sqrt(l1);
  ellipse->minor_m = 2.0 * std::sqrt(std::max(l2, 0.0));
  ellipse->angle_rad = 0.5 * std::atan2(2.0 * b, a - c);
  return true;
}

std::string pathsFigureSvg(const ResultLog& log, const std::vector<Series>& series, const FigureOptions& options) {
  const double width = options.width_px, height = options.height_px;
  SvgWriter svg(options.width_px, options.height_px);
  svg.rect(0, 0, width, height, "#ffffff");

  // Header: title, then the legend (wrapped as needed).
  TextStyle title;
  title.size_px = 17;
  title.bold = true;
  svg.text(kOuterPx + 6, 24, options.title.empty() ? "paths" : options.title + ": paths", title);
  std::vector<LegendItem> legend{{Mark::kTruthLine, "", "ground truth"},
                                 {Mark::kStart, "", "start"},
                                 {Mark::kTrueBeacon, "", "true beacon"},
                                 {Mark::kEstimatedBeacon, "#555555", "estimated beacon"},
                                 {Mark::kEllipse, "#555555", "2\u03C3 ellipse"}};
  const bool overlay = options.layout == Layout::kOverlay || series.size() <= 1;
  if (overlay) {
    for (const Series& s : series)
      legend.push_back({s.dashed ? Mark::kDashedLine : Mark::kLine, s.colour, s.name + " (" + meanLabel(s.mean_error_m) + ")"});
  }
  const double header = drawLegend(&svg, legend, kOuterPx + 6, 46, width - kOuterPx);

  // Panels: the grid whose cells give the largest common scale.
  const Box world = window(log, series);
  const size_t panels = overlay ? 1 : series.size();
  const PanelGrid grid = panelGrid(world.x_lo, world.x_hi, world.y_lo, world.y_hi, panels, width, height, header, kOuterPx);
  const AxisLabels& labels = grid.labels;

  for (size_t i = 0; i < panels; ++i) {
    const Frame& frame = grid.frames[i];
    drawAxes(svg, frame, labels);
    const std::string clip = "panel" + std::to_string(i);
    svg.clipRect(clip, frame.left_px, frame.top_px, frame.width_px, frame.height_px);
    svg.openGroup(overlay ? "overlay" : "panel", clip);
    drawTruth(svg, frame, log);
    if (overlay) {
      for (const Series& s : series) drawSeries(svg, frame, s);
    } else {
      drawSeries(svg, frame, series[i]);
    }
    svg.closeGroup();
    drawTruthMarks(svg, frame, log);  // unclipped, so that labels near the edge stay whole
    drawScaleBar(svg, frame);
    if (!overlay) {
      TextStyle name;
      name.size_px = 14;
      name.bold = true;
      name.colour = series[i].colour;
      // Two lines, so that a long name never runs into the figure: name, then its error.
      svg.text(frame.left_px, frame.top_px - 22, series[i].name, name);
      TextStyle detail;
      detail.size_px = 12;
      detail.colour = "#444444";
      svg.text(frame.left_px, frame.top_px - 6, meanLabel(series[i].mean_error_m), detail);
    }
  }
  return svg.str();
}

}  // namespace plot
}  // namespace roam
