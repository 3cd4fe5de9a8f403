#include "error_figure.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "plot_axes.hpp"
#include "plot_marks.hpp"
#include "svg_writer.hpp"

namespace roam {
namespace plot {
namespace {

constexpr double kOuterPx = 10;
constexpr double kHeadroom = 1.05;  // the error axis ends at least this much above the top curve
constexpr double kSpikeRatio = 2.0;  // a curve whose max exceeds this times its p99 is clipped at p99
constexpr double kOffScaleRatio = 5.0;  // see the y axis below

double percentile99(std::vector<double> errors) {
  if (errors.empty()) return 0.0;
  std::sort(errors.begin(), errors.end());
  return errors[static_cast<size_t>(std::floor(0.99 * static_cast<double>(errors.size() - 1)))];
}

}  // namespace

std::string errorFigureSvg(const ResultLog& log, const std::vector<Series>& series, const FigureOptions& options) {
  const double width = options.width_px, height = options.height_px;
  SvgWriter svg(options.width_px, options.height_px);
  svg.rect(0, 0, width, height, "#ffffff");
  TextStyle title;
  title.size_px = 17;
  title.bold = true;
  svg.text(kOuterPx + 6, 24,
           options.title.empty() ? "position error" : options.title + ": position error against ground truth", title);

  // Time origin: the first ground-truth pose (else the first matched one).
  int64_t t0 = log.ground_truth.empty() ? 0 : log.ground_truth.front().utime;
  if (log.ground_truth.empty()) {
    for (const Series& s : series)
      if (!s.matched.empty()) { t0 = s.matched.front().utime; break; }
  }
  double t_end = 1.0, y_top = 0.0;
  for (const Pose& p : log.ground_truth) t_end = std::max(t_end, 1e-6 * static_cast<double>(p.utime - t0));
  std::vector<double> max_error(series.size(), 0.0), top_of(series.size(), 0.0);
  for (size_t i = 0; i < series.size(); ++i) {
    std::vector<double> errors;
    for (const MatchedPosition& m : series[i].matched) {
      errors.push_back(m.error_m());
      t_end = std::max(t_end, 1e-6 * static_cast<double>(m.utime - t0));
    }
    if (errors.empty()) continue;
    max_error[i] = *std::max_element(errors.begin(), errors.end());
    const double p99 = percentile99(errors);
    top_of[i] = max_error[i] <= kSpikeRatio * p99 ? max_error[i] : p99;
  }
  // The axis fits the estimators, not the baselines far above them: a series whose mean error
  // is beyond kOffScaleRatio x the median of the series' means (dead reckoning drifting tens of
  // metres) is drawn off the top and says so in the legend.
  std::vector<double> means;
  for (const auto& s : series)
    if (std::isfinite(s.mean_error_m)) means.push_back(s.mean_error_m);
  double median_mean = std::numeric_limits<double>::infinity();
  if (!means.empty()) {
    std::nth_element(means.begin(), means.begin() + means.size() / 2, means.end());
    median_mean = means[means.size() / 2];
  }
  for (size_t i = 0; i < series.size(); ++i)
    if (!(series[i].mean_error_m > kOffScaleRatio * median_mean)) y_top = std::max(y_top, top_of[i]);
  if (!(y_top > 0) || !std::isfinite(y_top)) y_top = 1.0;
  const double y_step = niceStep(kHeadroom * y_top, std::max(2, static_cast<int>(height / 70)));
  y_top = std::ceil(kHeadroom * y_top / y_step) * y_step;

  std::vector<LegendItem> legend;
  for (size_t i = 0; i < series.size(); ++i) {
    char label[160];
    if (std::isfinite(series[i].mean_error_m)) {
      std::snprintf(label, sizeof label, "%s (mean %.2f m%s)", series[i].name.c_str(), series[i].mean_error_m,
                    max_error[i] > y_top ? ", off the top" : "");
    } else {
      std::snprintf(label, sizeof label, "%s (no matched poses)", series[i].name.c_str());
    }
    legend.push_back({series[i].dashed ? Mark::kDashedLine : Mark::kLine, series[i].colour, label});
  }
  const double header = drawLegend(&svg, legend, kOuterPx + 6, 46, width - kOuterPx);

  const Frame frame = errorFrame(width, height, header, t_end, y_top);
  AxisLabels labels{"time since start (s)", "position error (m)", 1, y_step};
  labels.x_step = niceStep(t_end, std::max(2, static_cast<int>(frame.width_px / 90)));
  drawAxes(svg, frame, labels);

  svg.clipRect("plot", frame.left_px, frame.top_px, frame.width_px, frame.height_px);
  svg.openGroup("curves", "plot");
  for (const Series& s : series) {
    std::vector<double> ts, es;
    for (const MatchedPosition& m : s.matched) {
      ts.push_back(1e-6 * static_cast<double>(m.utime - t0));
      es.push_back(m.error_m());
    }
    svg.polyline(toPixels(frame, ts, es, 0.5), estimateStroke(s.colour, s.dashed), "error", s.name);
  }
  svg.closeGroup();
  return svg.str();
}

}  // namespace plot
}  // namespace roam
