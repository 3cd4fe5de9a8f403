// roam-spectral-fig1b: the spectral paper's Fig. 1B — error of the learned measurement model
// against the number of range readings, over many random worlds (measurement_model_study.hpp).
// Prints the table, the log-log slope of the median, and optionally writes it as CSV and draws
// the log-log figure (SVG, and PNG through rsvg-convert).
#include <boost/program_options.hpp>

#include <cmath>
#include <cstdio>
#include <exception>
#include <fstream>
#include <string>
#include <vector>

#include "command_line.hpp"
#include "loglog_figure.hpp"
#include "measurement_model_study.hpp"
#include "png_render.hpp"

namespace po = boost::program_options;

namespace {

void writeFile(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error("cannot write " + path);
  out << text;
  if (!out) throw std::runtime_error("failed writing " + path);
}

std::string figureSvg(const std::vector<roam::MeasurementModelRow>& rows, const roam::MeasurementModelStudy& study,
                      double slope) {
  roam::plot::LogLogFigure figure;
  char title[160];
  std::snprintf(title, sizeof title, "Learned measurement model vs readings (%d worlds, %d beacons, sigma %.2g m)",
                study.worlds, study.beacons, study.range_sigma_m);
  figure.title = title;
  figure.x_label = "range readings (beacons x poses)";
  figure.y_label = "||sin Psi|| (subspace error)";
  roam::plot::LogLogSeries median, p25, p75, mean, bound;
  char median_name[64];
  std::snprintf(median_name, sizeof median_name, "median (slope %.2f)", slope);
  median.name = median_name;
  median.colour = "#0072B2";
  p25.name = "25 % / 75 %";
  p25.colour = p75.colour = "#56B4E9";
  p25.dashed = p75.dashed = true;
  p25.markers = p75.markers = false;
  mean.name = "mean";
  mean.colour = "#D55E00";
  bound.name = "rate of the bound, sqrt(log T / T)";
  bound.colour = "#444444";
  bound.dashed = true;
  bound.markers = false;
  const double t0 = rows.front().readings;
  const double k = rows.front().median / std::sqrt(std::log(t0) / t0);
  for (const roam::MeasurementModelRow& row : rows) {
    for (roam::plot::LogLogSeries* s : {&median, &p25, &p75, &mean, &bound}) s->x.push_back(row.readings);
    median.y.push_back(row.median);
    p25.y.push_back(row.p25);
    p75.y.push_back(row.p75);
    mean.y.push_back(row.mean);
    bound.y.push_back(k * std::sqrt(std::log(row.readings) / row.readings));
  }
  p75.name = "";
  figure.series = {median, p25, p75, mean, bound};
  return roam::plot::logLogFigureSvg(figure);
}

}  // namespace

int main(int argc, char** argv) {
  roam::MeasurementModelStudy study;
  std::string csv_path, svg_path, png_path;
  po::options_description visible(
      "roam-spectral-fig1b [options]: the spectral paper's Fig. 1B, error of the learned measurement model\n"
      "against the number of range readings, averaged over random worlds");
  // clang-format off
  visible.add_options()
      ("help,h", "this help")
      ("worlds", po::value(&study.worlds)->default_value(study.worlds), "random worlds per path length (the paper: 1000)")
      ("beacons", po::value(&study.beacons)->default_value(study.beacons), "beacons per world (>= 4)")
      ("range-sigma", po::value(&study.range_sigma_m)->default_value(study.range_sigma_m), "range noise std (m)")
      ("steps", po::value(&study.steps)->multitoken()->default_value(study.steps, "400 800 1600 3200 6400"),
       "path lengths (steps) to evaluate")
      ("csv", po::value(&csv_path), "FILE: write the table as CSV")
      ("svg", po::value(&svg_path), "FILE: draw the log-log figure")
      ("png", po::value(&png_path), "FILE: the figure as PNG too (needs --svg and rsvg-convert)");
  // clang-format on
  try {
    po::variables_map vm;
    if (!roam::tools::parseCommandLine(argc, argv, visible, &vm)) return 0;
    if (!png_path.empty() && svg_path.empty()) throw std::runtime_error("--png needs --svg");
    if (!(study.range_sigma_m >= 0.0)) throw std::runtime_error("--range-sigma: expected >= 0");
    if (study.steps.size() < 2) throw std::runtime_error("--steps: expected at least two lengths");

    const std::vector<roam::MeasurementModelRow> rows = roam::runMeasurementModelStudy(study);
    const double slope = roam::logLogSlopeOfMedian(rows);
    std::printf("| steps | readings | mean sin(Psi) | median | 25 %% | 75 %% |\n|---:|---:|---:|---:|---:|---:|\n");
    std::string csv = "steps,readings,mean,median,p25,p75\n";
    for (const roam::MeasurementModelRow& row : rows) {
      std::printf("| %d | %.0f | %.5f | %.5f | %.5f | %.5f |\n", row.steps, row.readings, row.mean, row.median,
                  row.p25, row.p75);
      char line[160];
      std::snprintf(line, sizeof line, "%d,%.0f,%.9g,%.9g,%.9g,%.9g\n", row.steps, row.readings, row.mean,
                    row.median, row.p25, row.p75);
      csv += line;
    }
    std::printf("\nlog-log slope of the median: %.3f (the bound: -1/2 up to sqrt(log T))\n", slope);
    if (!csv_path.empty()) writeFile(csv_path, csv);
    if (!svg_path.empty()) {
      writeFile(svg_path, figureSvg(rows, study, slope));
      if (!png_path.empty()) roam::plot::renderPng(svg_path, png_path, 860, 560);
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "roam-spectral-fig1b: error: %s\n", e.what());
    return 2;
  }
}
