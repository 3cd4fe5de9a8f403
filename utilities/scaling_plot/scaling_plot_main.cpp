// scaling_plot: the log-log figure of the scaling study (utilities/scaling) — CPU per solve
// against the number of odometry steps T, one line per (solver, beacons), and a dashed slope-1
// line (time proportional to T) below the first point of the first series.
//
//   scaling_plot --csv scaling.csv --svg scaling.svg [--png scaling.png]
//
// The CSV has a header naming (at least) the columns solver, N, T and cpu_s, in any order (lines
// starting with # before it are comments); rows of a series in any order.
#include <boost/program_options.hpp>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "loglog_figure.hpp"
#include "png_render.hpp"

namespace po = boost::program_options;

namespace {

struct Point {
  double steps, cpu_s;
};

std::vector<std::string> splitCsv(const std::string& line) {
  std::vector<std::string> fields;
  std::istringstream in(line);
  std::string field;
  while (std::getline(in, field, ',')) fields.push_back(field);
  return fields;
}

// (solver, N) -> points, in the order the series first appear.
std::vector<std::pair<std::string, std::vector<Point>>> readCsv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::string line;
  int number = 0;
  do {  // lines starting with # before the header are comments
    if (!std::getline(in, line)) throw std::runtime_error(path + ": no header");
    ++number;
  } while (!line.empty() && line[0] == '#');
  const std::vector<std::string> header = splitCsv(line);
  auto column = [&](const std::string& name) {
    const auto it = std::find(header.begin(), header.end(), name);
    if (it == header.end()) throw std::runtime_error(path + ": no column '" + name + "' in the header");
    return static_cast<size_t>(it - header.begin());
  };
  const size_t solver = column("solver"), beacons = column("N"), steps = column("T"), cpu = column("cpu_s");
  std::vector<std::pair<std::string, std::vector<Point>>> series;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty()) continue;
    const std::vector<std::string> fields = splitCsv(line);
    if (fields.size() != header.size()) {
      throw std::runtime_error(path + ":" + std::to_string(number) + ": expected " + std::to_string(header.size()) +
                               " fields");
    }
    const std::string name = fields[solver] + ", N = " + fields[beacons];
    auto it = std::find_if(series.begin(), series.end(), [&](const auto& s) { return s.first == name; });
    if (it == series.end()) it = series.insert(series.end(), {name, {}});
    it->second.push_back({std::stod(fields[steps]), std::stod(fields[cpu])});
  }
  if (series.empty()) throw std::runtime_error(path + ": no rows");
  return series;
}

std::string figureSvg(std::vector<std::pair<std::string, std::vector<Point>>> series) {
  // Okabe-Ito colours; the spectral lines solid, the batch lines dashed.
  static const char* colours[] = {"#0072B2", "#009E73", "#56B4E9", "#D55E00", "#E69F00", "#CC79A7", "#000000"};
  roam::plot::LogLogFigure figure;
  figure.title = "Scaling: CPU per solve against run length";
  figure.x_label = "odometry steps T (5 Hz)";
  figure.y_label = "CPU per solve (s)";
  figure.legend_top_left = true;
  size_t i = 0;
  for (auto& [name, points] : series) {
    std::sort(points.begin(), points.end(), [](const Point& a, const Point& b) { return a.steps < b.steps; });
    roam::plot::LogLogSeries s;
    s.name = name;
    s.colour = colours[i++ % (sizeof colours / sizeof *colours)];
    s.dashed = name.rfind("spectral,", 0) != 0;
    for (const Point& p : points) {
      s.x.push_back(p.steps);
      s.y.push_back(p.cpu_s);
    }
    figure.series.push_back(s);
  }
  // Slope 1 a factor 3 below the first point of the first series (a guide that does not hide
  // it), over the whole range of T.
  double lo = 1e300, hi = 0.0;
  for (const auto& [name, points] : series)
    for (const Point& p : points) {
      lo = std::min(lo, p.steps);
      hi = std::max(hi, p.steps);
    }
  const Point anchor = series.front().second.front();
  roam::plot::LogLogSeries reference;
  reference.name = "slope 1 (time proportional to T)";
  reference.colour = "#888888";
  reference.dashed = true;
  reference.markers = false;
  reference.x = {lo, hi};
  reference.y = {anchor.cpu_s / 3.0 * lo / anchor.steps, anchor.cpu_s / 3.0 * hi / anchor.steps};
  figure.series.push_back(reference);
  return roam::plot::logLogFigureSvg(figure);
}

void writeFile(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error("cannot write " + path);
  out << text;
  if (!out) throw std::runtime_error("failed writing " + path);
}

}  // namespace

int main(int argc, char** argv) {
  std::string csv_path, svg_path, png_path;
  po::options_description options("scaling_plot [options]: the scaling study's log-log figure");
  // clang-format off
  options.add_options()
      ("help,h", "this help")
      ("csv", po::value(&csv_path)->required(), "FILE: a header naming solver, N, T, cpu_s; then the rows")
      ("svg", po::value(&svg_path)->required(), "FILE: the figure as SVG")
      ("png", po::value(&png_path), "FILE: the figure as PNG too (rsvg-convert)");
  // clang-format on
  try {
    po::variables_map vm;
    po::store(po::parse_command_line(argc, argv, options), vm);
    if (vm.count("help")) {
      std::cout << options << "\n";
      return 0;
    }
    po::notify(vm);
    writeFile(svg_path, figureSvg(readCsv(csv_path)));
    if (!png_path.empty()) roam::plot::renderPng(svg_path, png_path, 860, 560);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "scaling_plot: error: %s\n", e.what());
    return 2;
  }
}
