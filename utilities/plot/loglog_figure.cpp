#include "loglog_figure.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "plot_marks.hpp"
#include "svg_writer.hpp"

namespace roam {
namespace plot {
namespace {

constexpr double kLeftPx = 80, kRightPx = 24, kTopPx = 44, kBottomPx = 56;

}  // namespace

std::string logTickLabel(double value) {
  char text[32];
  const double exponent = std::log10(value);
  if (exponent >= 6.0 || exponent < -4.0)
    std::snprintf(text, sizeof text, "%.0e", value);
  else
    std::snprintf(text, sizeof text, "%g", value);
  return text;
}

std::string logLogFigureSvg(const LogLogFigure& figure) {
  double x_lo = std::numeric_limits<double>::infinity(), x_hi = -x_lo, y_lo = x_lo, y_hi = -x_lo;
  for (const LogLogSeries& s : figure.series)
    for (size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
      if (!(s.x[i] > 0.0) || !(s.y[i] > 0.0) || !std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      x_lo = std::min(x_lo, std::log10(s.x[i]));
      x_hi = std::max(x_hi, std::log10(s.x[i]));
      y_lo = std::min(y_lo, std::log10(s.y[i]));
      y_hi = std::max(y_hi, std::log10(s.y[i]));
    }
  if (!(x_lo <= x_hi)) throw std::invalid_argument("log-log figure: no series has a point with x, y > 0");
  // Whole decades around the data (at least one decade per axis).
  x_lo = std::floor(x_lo);
  x_hi = std::max(std::ceil(x_hi), x_lo + 1.0);
  y_lo = std::floor(y_lo);
  y_hi = std::max(std::ceil(y_hi), y_lo + 1.0);

  const double width = figure.width_px, height = figure.height_px;
  const double plot_w = width - kLeftPx - kRightPx, plot_h = height - kTopPx - kBottomPx;
  auto px = [&](double x) { return kLeftPx + (std::log10(x) - x_lo) / (x_hi - x_lo) * plot_w; };
  auto py = [&](double y) { return kTopPx + (y_hi - std::log10(y)) / (y_hi - y_lo) * plot_h; };

  SvgWriter svg(figure.width_px, figure.height_px);
  svg.rect(0, 0, width, height, "#ffffff");
  TextStyle title;
  title.size_px = 17;
  title.bold = true;
  svg.text(16, 26, figure.title, title);

  // Grid: decades solid, 2..9 faint; labels at decades.
  const Stroke decade("#c8c8c8", 1.0), minor("#ececec", 1.0);
  TextStyle tick;
  tick.size_px = 12;
  tick.anchor = "middle";
  for (int e = static_cast<int>(x_lo); e <= static_cast<int>(x_hi); ++e) {
    const double base = std::pow(10.0, e);
    for (int m = 1; m < 10 && (e < x_hi || m == 1); ++m) {
      const double x = px(m * base);
      svg.line(x, kTopPx, x, kTopPx + plot_h, m == 1 ? decade : minor);
    }
    svg.text(px(base), kTopPx + plot_h + 18, logTickLabel(base), tick);
  }
  tick.anchor = "end";
  for (int e = static_cast<int>(y_lo); e <= static_cast<int>(y_hi); ++e) {
    const double base = std::pow(10.0, e);
    for (int m = 1; m < 10 && (e < y_hi || m == 1); ++m) {
      const double y = py(m * base);
      svg.line(kLeftPx, y, kLeftPx + plot_w, y, m == 1 ? decade : minor);
    }
    svg.text(kLeftPx - 6, py(base) + 4, logTickLabel(base), tick);
  }
  svg.rect(kLeftPx, kTopPx, plot_w, plot_h, "none", Stroke("#444444", 1.0));
  TextStyle axis;
  axis.size_px = 13;
  axis.anchor = "middle";
  svg.text(kLeftPx + plot_w / 2, height - 14, figure.x_label, axis);
  axis.rotate_deg = -90;
  svg.text(20, kTopPx + plot_h / 2, figure.y_label, axis);

  std::vector<LegendItem> legend;
  for (const LogLogSeries& s : figure.series) {
    std::vector<Point> points;
    for (size_t i = 0; i < s.x.size() && i < s.y.size(); ++i)
      if (s.x[i] > 0.0 && s.y[i] > 0.0 && std::isfinite(s.x[i]) && std::isfinite(s.y[i]))
        points.push_back({px(s.x[i]), py(s.y[i])});
    if (points.empty()) continue;
    const Stroke stroke(s.colour, 2.0, s.dashed ? "7 4" : "");
    svg.polyline(points, stroke, "series", s.name);
    if (s.markers)
      for (const Point& p : points) svg.circle(p.x, p.y, 3.2, s.colour);
    if (s.name.empty()) continue;  // drawn, not listed (e.g. the second line of a band)
    LegendItem item;
    item.mark = s.dashed ? Mark::kDashedLine : Mark::kLine;
    item.colour = s.colour;
    item.label = s.name;
    legend.push_back(item);
  }
  // The legend in a white box at the top right (or top left) of the frame.
  const double legend_x = figure.legend_top_left ? kLeftPx + 6 : kLeftPx + plot_w * 0.45;
  const double legend_w = plot_w * 0.55 - 6, legend_right = legend_x + legend_w + 6 - 8;
  const double bottom = drawLegend(nullptr, legend, legend_x + 8, kTopPx + 22, legend_right);
  svg.rect(legend_x, kTopPx + 6, legend_w, bottom - kTopPx - 12, "#ffffff", Stroke("#bbbbbb", 1.0));
  drawLegend(&svg, legend, legend_x + 8, kTopPx + 22, legend_right);
  return svg.str();
}

}  // namespace plot
}  // namespace roam
