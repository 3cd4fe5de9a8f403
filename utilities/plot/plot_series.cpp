#include "plot_series.hpp"

#include <stdexcept>

#include "score_table.hpp"

namespace roam {
namespace plot {

std::string seriesColour(size_t index) {
  static const char* const kPalette[] = {"#0072B2", "#D55E00", "#009E73", "#CC79A7",
                                         "#E69F00", "#56B4E9", "#8C564B", "#000000"};
  return kPalette[index % (sizeof kPalette / sizeof kPalette[0])];
}

namespace {

Series makeSeries(const std::string& name, const Path& path, const std::optional<Map>& map,
                  const ResultLog& log) {
  Series s;
  s.name = name;
  s.path = path;
  s.map = map;
  s.matched = matchToGroundTruth(path, log.ground_truth);
  s.mean_error_m = scorePath(path, log.ground_truth, false).full.mean_m;
  return s;
}

}  // namespace

std::vector<Series> collectSeries(const ResultLog& log, const std::vector<std::string>& only, bool with_odometry) {
  const bool has_odometry = log.start && !log.odometry.empty();
  std::vector<Series> all;
  if (has_odometry && (with_odometry || !only.empty())) {
    all.push_back(makeSeries(kOdometryRowName, integrateOdometry(*log.start, log.odometry), std::nullopt, log));
    all.back().colour = "#7F7F7F";
    all.back().dashed = true;
  }
  size_t colour = 0;
  for (const EstimatorOutputs& out : log.estimators) {
    all.push_back(makeSeries(out.name, out.scoredPath(), out.map, log));
    all.back().colour = seriesColour(colour++);
  }
  if (only.empty()) return all;

  std::vector<Series> chosen;
  for (const std::string& wanted : only) {
    const EstimatorOutputs* out = log.find(wanted);
    const std::string name = out ? out->name : wanted;
    bool found = false;
    for (const Series& s : all) {
      if (s.name == name) {
        chosen.push_back(s);
        found = true;
        break;
      }
    }
    if (!found) {
      std::string names;
      for (const Series& s : all) names += (names.empty() ? "" : ", ") + s.name;
      throw std::runtime_error("--estimators: no estimator '" + wanted + "' in " + log.path +
                               " (there are: " + (names.empty() ? "none" : names) + ")");
    }
  }
  return chosen;
}

}  // namespace plot
}  // namespace roam
