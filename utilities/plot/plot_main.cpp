// roam-plot RESULT_LOG -o PREFIX [--width PX] [--height PX] [--estimators a,b] [--layout panels|overlay]
//           [--no-odometry] [--no-png]
// Writes PREFIX-paths.svg and PREFIX-error.svg (paths_figure.hpp, error_figure.hpp) and the same
// as PREFIX-paths.png and PREFIX-error.png at WIDTH x HEIGHT pixels (rsvg-convert). Exit 2 with
// a one-line message on a bad option, an unreadable log or a missing rsvg-convert.
// A team's log (GROUND_TRUTH_<R> per robot) is drawn by team_figures.hpp: a colour per robot, a
// line style per estimator, one error curve per robot and estimator.
#include <boost/program_options.hpp>
#include <cstdio>
#include <exception>
#include <fstream>
#include <string>
#include <vector>

#include "command_line.hpp"
#include "error_figure.hpp"
#include "paths_figure.hpp"
#include "plot_series.hpp"
#include "png_render.hpp"
#include "result_log.hpp"
#include "team_figures.hpp"

namespace po = boost::program_options;

namespace {

std::vector<std::string> splitList(const std::string& text) {
  std::vector<std::string> items;
  size_t begin = 0;
  while (begin <= text.size()) {
    size_t end = text.find(',', begin);
    if (end == std::string::npos) end = text.size();
    std::string item = text.substr(begin, end - begin);
    while (!item.empty() && item.front() == ' ') item.erase(item.begin());
    while (!item.empty() && item.back() == ' ') item.pop_back();
    if (!item.empty()) items.push_back(item);
    begin = end + 1;
  }
  return items;
}

std::string runLabel(const std::string& path) {
  std::string name = path.substr(path.find_last_of('/') + 1);
  const std::string ext = ".lcmlog";
  if (name.size() > ext.size() && name.compare(name.size() - ext.size(), ext.size(), ext) == 0)
    name.resize(name.size() - ext.size());
  return name;
}

void writeFile(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  out.close();
  if (!out) throw std::runtime_error(path + ": cannot write");
}

}  // namespace

int main(int argc, char** argv) {
  std::string log_path, prefix, estimators, layout_name = "panels";
  roam::plot::FigureOptions options;
  po::options_description visible(
      "roam-plot RESULT_LOG -o PREFIX: PREFIX-paths.svg/.png (ground truth, each estimator's path and map,\n"
      "one panel per estimator on a shared metric scale, or an overlay) and PREFIX-error.svg/.png (position\n"
      "error against time, matched as roam-eval does)");
  // clang-format off
  visible.add_options()
      ("help,h", "this help")
      ("output,o", po::value(&prefix), "PREFIX of the files to write (required)")
      ("width", po::value(&options.width_px)->default_value(options.width_px), "picture width (px)")
      ("height", po::value(&options.height_px)->default_value(options.height_px), "picture height (px)")
      ("estimators", po::value(&estimators), "a,b,...: only these estimators (names or channel suffixes; 'odometry' too)")
      ("layout", po::value(&layout_name)->default_value(layout_name), "panels | overlay")
      ("no-odometry", "leave out the 'odometry' baseline (dead reckoning integrated from the log's ODOMETRY)")
      ("no-png", "write the SVG pictures only");
  // clang-format on
  po::options_description hidden;
  hidden.add_options()("log", po::value(&log_path));
  po::positional_options_description positional;
  positional.add("log", 1);
  try {
    po::variables_map vm;
    if (!roam::tools::parseCommandLine(argc, argv, visible, hidden, positional, &vm)) return 0;
    if (log_path.empty()) throw std::runtime_error("missing RESULT_LOG (a log with GROUND_TRUTH and estimator outputs)");
    if (prefix.empty()) throw std::runtime_error("missing -o PREFIX (the files written are PREFIX-paths.svg, ...)");
    if (options.width_px < 200 || options.width_px > 10000 || options.height_px < 150 || options.height_px > 10000)
      throw std::runtime_error("--width, --height: expected 200..10000 x 150..10000 pixels");
    if (layout_name == "panels") options.layout = roam::plot::Layout::kPanels;
    else if (layout_name == "overlay") options.layout = roam::plot::Layout::kOverlay;
    else throw std::runtime_error("--layout: expected panels | overlay, got '" + layout_name + "'");

    const roam::ResultLog log = roam::readResultLog(log_path);
    if (log.skipped > 0)
      std::fprintf(stderr, "roam-plot: %s: skipped %ld corrupt or undecodable events\n", log_path.c_str(), log.skipped);
    if (log.ground_truth.empty() && !log.isTeam())
      std::fprintf(stderr, "roam-plot: %s: no GROUND_TRUTH: paths only, no errors\n", log_path.c_str());
    options.title = runLabel(log_path);
    std::string paths_svg, error_svg;
    if (log.isTeam()) {  // team_figures.hpp: a colour per robot, a line style per estimator
      const auto series = roam::plot::collectTeamSeries(log, splitList(estimators));
      paths_svg = roam::plot::teamPathsFigureSvg(log, series, options);
      error_svg = roam::plot::teamErrorFigureSvg(log, series, options);
    } else {
      const auto series = roam::plot::collectSeries(log, splitList(estimators), vm.count("no-odometry") == 0);
      paths_svg = roam::plot::pathsFigureSvg(log, series, options);
      error_svg = roam::plot::errorFigureSvg(log, series, options);
    }
    for (const char* figure : {"paths", "error"}) {
      const std::string svg_path = prefix + "-" + figure + ".svg";
      writeFile(svg_path, figure == std::string("paths") ? paths_svg : error_svg);
      std::printf("roam-plot: wrote %s\n", svg_path.c_str());
    }
    if (vm.count("no-png") == 0) {
      for (const char* figure : {"paths", "error"}) {
        const std::string base = prefix + "-" + figure;
        roam::plot::renderPng(base + ".svg", base + ".png", options.width_px, options.height_px);
        std::printf("roam-plot: wrote %s.png (%d x %d)\n", base.c_str(), options.width_px, options.height_px);
      }
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "roam-plot: error: %s\n", e.what());
    return 2;
  }
}
