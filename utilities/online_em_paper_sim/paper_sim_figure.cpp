#include "paper_sim_figure.hpp"

#include <cmath>
#include <cstdio>

#include "figure_options.hpp"
#include "paths_figure.hpp"
#include "plot_series.hpp"
#include "result_log.hpp"

namespace roam {
namespace paper_sim {

std::string figureSvg(const Study& study) {
  ResultLog log;
  log.ground_truth = study.truth;
  log.beacons = study.true_map;
  log.start = study.truth.front();
  plot::Series mean;
  char name[96];
  std::snprintf(name, sizeof name, "online EM, mean of %d runs", static_cast<int>(study.runs.size()));
  mean.name = name;
  mean.colour = plot::seriesColour(1);
  mean.path = study.mean_path;
  mean.map = study.mean_map;
  double sum_m = 0.0;
  for (size_t t = 0; t < study.truth.size(); ++t)
    sum_m += std::hypot(study.truth[t].x_m - study.mean_path[t].x_m, study.truth[t].y_m - study.mean_path[t].y_m);
  mean.mean_error_m = sum_m / static_cast<double>(study.truth.size());
  plot::FigureOptions options;
  options.width_px = kFigureWidthPx;
  options.height_px = kFigureHeightPx;
  options.layout = plot::Layout::kOverlay;
  options.title = "Le Corff, Fort & Moulines 2011, Sec. 4.1 simulation (T = " +
                  std::to_string(study.options.steps) + ")";
  return plot::pathsFigureSvg(log, {mean}, options);
}

}  // namespace paper_sim
}  // namespace roam
