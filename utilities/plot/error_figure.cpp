#include "error_figure.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "plot_axes.hpp"
#include "plot_marks.hpp"
#include "svg_writer.hpp"

namespace roam {
namespace plot {

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
  std::vector<double> max_error(series.size(), 0.0), top_of(series.size(), 0.0), means;
  for (size_t i = 0; i < series.size(); ++i) {
    std::vector<double> errors;
    for (const MatchedPosition& m : series[i].matched) {
      errors.push_back(m.error_m());
      t_end = std::max(t_end, 1e-6 * static_cast<double>(m.utime - t0));
    }
    means.push_back(series[i].mean_error_m);
    if (errors.empty()) continue;
    max_error[i] = *std::max_element(errors.begin(), errors.end());
    top_of[i] = curveTop(errors);
  }
  // The axis fits the estimators, not the baselines far above them (plot_axes.hpp).
  double y_step = 1.0;
  y_top = errorAxisTop(top_of, means, height, &y_step);

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
