// PREFIX-error.svg: the position error of every estimator against time on one axis, with
// roam-eval's matching (each ground-truth time inside the estimate's span, the estimate
// interpolated linearly). Time is in seconds from the first ground-truth pose. The error axis
// runs from 0 to a nice value above every curve's maximum — except that a curve whose maximum is
// over twice its 99th percentile (a spike, a divergence) counts only to that percentile, so one
// diverged estimator does not flatten the others; a curve that leaves the top says so in the legend.
#pragma once

#include <string>
#include <vector>

#include "figure_options.hpp"
#include "plot_series.hpp"
#include "result_log.hpp"

namespace roam {
namespace plot {

std::string errorFigureSvg(const ResultLog& log, const std::vector<Series>& series, const FigureOptions& options);

}  // namespace plot
}  // namespace roam
