#include "plot_axes.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace roam {
namespace plot {

double curveTop(std::vector<double> errors_m) {
  constexpr double kSpikeRatio = 2.0;
  if (errors_m.empty()) return 0.0;
  std::sort(errors_m.begin(), errors_m.end());
  const double p99 = errors_m[static_cast<size_t>(std::floor(0.99 * static_cast<double>(errors_m.size() - 1)))];
  return errors_m.back() <= kSpikeRatio * p99 ? errors_m.back() : p99;
}

double errorAxisTop(const std::vector<double>& tops_m, const std::vector<double>& means_m, double height_px,
                    double* step) {
  constexpr double kHeadroom = 1.05, kOffScaleRatio = 5.0;
  std::vector<double> finite;
  for (double mean : means_m)
    if (std::isfinite(mean)) finite.push_back(mean);
  double median_mean = std::numeric_limits<double>::infinity();
  if (!finite.empty()) {
    std::nth_element(finite.begin(), finite.begin() + finite.size() / 2, finite.end());
    median_mean = finite[finite.size() / 2];
  }
  double top = 0.0;
  for (size_t i = 0; i < tops_m.size(); ++i)
    if (!(means_m[i] > kOffScaleRatio * median_mean)) top = std::max(top, tops_m[i]);
  if (!(top > 0) || !std::isfinite(top)) top = 1.0;
  *step = niceStep(kHeadroom * top, std::max(2, static_cast<int>(height_px / 70)));
  return std::ceil(kHeadroom * top / *step) * *step;
}

PanelGrid panelGrid(double x_lo, double x_hi, double y_lo, double y_hi, size_t panels, double width_px,
                    double height_px, double header_px, double outer_px) {
  // Room around each frame for its title, tick labels and scale bar.
  constexpr double kPanelLeftPx = 58, kPanelRightPx = 14, kPanelTopPx = 40, kPanelBottomPx = 42;
  const double world_w = x_hi - x_lo, world_h = y_hi - y_lo;
  const double area_w = width_px - 2 * outer_px, area_h = height_px - header_px - outer_px + 6;
  size_t best_cols = 1;
  double scale = 0;
  for (size_t cols = 1; cols <= panels; ++cols) {
    const size_t rows = (panels + cols - 1) / cols;
    const double fw = area_w / cols - kPanelLeftPx - kPanelRightPx;
    const double fh = area_h / rows - kPanelTopPx - kPanelBottomPx;
    const double s = std::min(fw / world_w, fh / world_h);
    if (s > scale) { scale = s; best_cols = cols; }
  }
  if (!(scale > 0)) scale = 1e-3;
  const size_t cols = best_cols, rows = (panels + cols - 1) / cols;
  const double cell_w = area_w / cols, cell_h = area_h / rows;
  const double frame_w = std::max(cell_w - kPanelLeftPx - kPanelRightPx, 10.0);
  const double frame_h = std::max(cell_h - kPanelTopPx - kPanelBottomPx, 10.0);
  const double cx = 0.5 * (x_lo + x_hi), cy = 0.5 * (y_lo + y_hi);
  PanelGrid grid;
  grid.labels = AxisLabels{"x (m)", "y (m)", 1, 1};
  grid.labels.x_step = grid.labels.y_step = niceStep(frame_w / scale, std::max(2, static_cast<int>(frame_w / 70)));
  for (size_t i = 0; i < panels; ++i) {
    Frame frame;
    frame.left_px = outer_px + (i % cols) * cell_w + kPanelLeftPx;
    frame.top_px = header_px - 6 + (i / cols) * cell_h + kPanelTopPx;
    frame.width_px = frame_w;
    frame.height_px = frame_h;
    frame.x_lo = cx - 0.5 * frame_w / scale;
    frame.x_hi = cx + 0.5 * frame_w / scale;
    frame.y_lo = cy - 0.5 * frame_h / scale;
    frame.y_hi = cy + 0.5 * frame_h / scale;
    grid.frames.push_back(frame);
  }
  return grid;
}

Frame errorFrame(double width_px, double height_px, double header_px, double t_end_s, double y_top_m) {
  constexpr double kLeftPx = 72, kRightPx = 24, kBottomPx = 50;
  Frame frame;
  frame.left_px = kLeftPx;
  frame.top_px = header_px + 6;
  frame.width_px = std::max(width_px - kLeftPx - kRightPx, 10.0);
  frame.height_px = std::max(height_px - header_px - 6 - kBottomPx, 10.0);
  frame.x_lo = 0;
  frame.x_hi = t_end_s;
  frame.y_lo = 0;
  frame.y_hi = y_top_m;
  return frame;
}

double niceStep(double span, int max_ticks) {
  const double raw = span / std::max(1, max_ticks);
  double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  for (;;) {
    for (double m : {1.0, 2.0, 5.0}) {
      if (m * magnitude >= raw * (1 - 1e-12)) return m * magnitude;
    }
    magnitude *= 10;
  }
}

std::vector<double> tickValues(double lo, double hi, double step) {
  std::vector<double> ticks;
  const double eps = 1e-9 * step;
  for (double k = std::ceil((lo - eps) / step); k * step <= hi + eps; k += 1) ticks.push_back(k * step);
  return ticks;
}

std::string tickLabel(double value, double step) {
  int decimals = 0;
  while (decimals < 6 && std::fabs(step * std::pow(10.0, decimals) - std::round(step * std::pow(10.0, decimals))) >
                             1e-6 * step * std::pow(10.0, decimals))
    ++decimals;
  if (std::fabs(value) < 0.5 * step * 1e-6) value = 0.0;
  char buffer[48];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, value);
  return buffer;
}

Point Frame::toPixel(double x, double y) const {
  return {left_px + (x - x_lo) * pixelsPerUnitX(), top_px + (y_hi - y) * pixelsPerUnitY()};
}

void drawAxes(SvgWriter& svg, const Frame& frame, const AxisLabels& labels) {
  const Stroke grid{"#e3e3e3", 1.0};
  const Stroke tick{"#555555", 1.0};
  TextStyle label;
  label.size_px = 11;
  label.colour = "#444444";
  const double right = frame.left_px + frame.width_px, bottom = frame.top_px + frame.height_px;
  svg.openGroup("axes");
  for (double x : tickValues(frame.x_lo, frame.x_hi, labels.x_step)) {
    const double px = frame.toPixel(x, 0).x;
    svg.line(px, frame.top_px, px, bottom, grid);
    svg.line(px, bottom, px, bottom + 4, tick);
    label.anchor = "middle";
    svg.text(px, bottom + 16, tickLabel(x, labels.x_step), label);
  }
  for (double y : tickValues(frame.y_lo, frame.y_hi, labels.y_step)) {
    const double py = frame.toPixel(0, y).y;
    svg.line(frame.left_px, py, right, py, grid);
    svg.line(frame.left_px - 4, py, frame.left_px, py, tick);
    label.anchor = "end";
    svg.text(frame.left_px - 6, py + 4, tickLabel(y, labels.y_step), label);
  }
  svg.rect(frame.left_px, frame.top_px, frame.width_px, frame.height_px, "none", Stroke{"#888888", 1.0});
  TextStyle title;
  title.size_px = 12;
  title.anchor = "middle";
  title.colour = "#333333";
  if (!labels.x.empty()) svg.text(frame.left_px + frame.width_px / 2, bottom + 31, labels.x, title);
  if (!labels.y.empty()) {
    title.rotate_deg = -90;
    const double x = frame.left_px - 40, y = frame.top_px + frame.height_px / 2;
    svg.text(x, y, labels.y, title);
  }
  svg.closeGroup();
}

void drawScaleBar(SvgWriter& svg, const Frame& frame) {
  const double px_per_m = frame.pixelsPerUnitX();
  const double target_m = 0.2 * frame.width_px / px_per_m;
  // The largest 1, 2, 5 x 10^k not above a fifth of the width.
  double length_m = niceStep(target_m, 1);
  if (length_m > target_m * (1 + 1e-12)) {  // one nice value down: 5 -> 2, 2 -> 1, 1 -> 0.5
    const double mantissa = length_m / std::pow(10.0, std::floor(std::log10(length_m) + 1e-12));
    length_m /= std::fabs(mantissa - 5.0) < 1e-6 ? 2.5 : 2.0;
  }
  const double length_px = length_m * px_per_m;
  const double right = frame.left_px + frame.width_px, y = frame.top_px + frame.height_px + 31;
  svg.openGroup("scale-bar");
  const Stroke bar{"#222222", 2.0};
  svg.line(right - length_px, y, right, y, bar);
  svg.line(right - length_px, y - 5, right - length_px, y + 3, bar);
  svg.line(right, y - 5, right, y + 3, bar);
  TextStyle text;
  text.size_px = 11;
  text.anchor = "end";
  svg.text(right - length_px - 6, y + 4, tickLabel(length_m, length_m) + " m", text);
  svg.closeGroup();
}

std::vector<Point> toPixels(const Frame& frame, const std::vector<double>& xs, const std::vector<double>& ys,
                            double min_spacing_px) {
  std::vector<Point> points;
  const double limit = 20.0 * std::max(frame.width_px, frame.height_px);
  auto clamp = [&](double v, double origin) { return std::clamp(v, origin - limit, origin + limit); };
  const size_t n = std::min(xs.size(), ys.size());
  size_t last_index = 0;
  bool pending = false;
  for (size_t i = 0; i < n; ++i) {
    if (!std::isfinite(xs[i]) || !std::isfinite(ys[i])) continue;
    Point p = frame.toPixel(xs[i], ys[i]);
    p.x = clamp(p.x, frame.left_px);
    p.y = clamp(p.y, frame.top_px);
    if (!points.empty() && std::hypot(p.x - points.back().x, p.y - points.back().y) < min_spacing_px) {
      last_index = i;
      pending = true;
      continue;
    }
    points.push_back(p);
    pending = false;
  }
  if (pending) {  // keep the very last point
    Point p = frame.toPixel(xs[last_index], ys[last_index]);
    points.push_back({clamp(p.x, frame.left_px), clamp(p.y, frame.top_px)});
  }
  return points;
}

}  // namespace plot
}  // namespace roam
