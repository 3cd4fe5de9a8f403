// roam-online-em-paper-sim: the simulation of Le Corff, Fort & Moulines 2011, Sec. 4.1
// (paper_sim_world.hpp: the setting; paper_sim_study.hpp: the Monte-Carlo runs).
// Prints, over the runs, the quantiles of the x error (true - estimated) of the estimated path at
// several times (the data behind the paper's Fig. 2 boxplots), of the y error and of the mean
// landmark error; optionally writes them as CSV and draws the paper's Fig. 1 (true path and
// landmarks, mean estimated path and map over the runs) as SVG, and PNG through rsvg-convert.
#include <boost/program_options.hpp>

#include <cstdio>
#include <exception>
#include <fstream>
#include <string>
#include <vector>

#include "command_line.hpp"
#include "paper_sim_figure.hpp"
#include "paper_sim_study.hpp"
#include "png_render.hpp"

namespace po = boost::program_options;
namespace ps = roam::paper_sim;

namespace {

void writeFile(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error("cannot write " + path);
  out << text;
  if (!out) throw std::runtime_error("failed writing " + path);
}

struct Table {
  const char* title;
  std::vector<double> ps::RunResult::*series;
};

}  // namespace

int main(int argc, char** argv) {
  ps::StudyOptions options;
  std::string csv_path, svg_path, png_path;
  bool quiet = false;
  po::options_description visible(
      "roam-online-em-paper-sim [options]: the simulation of Le Corff, Fort & Moulines 2011, Sec. 4.1 —\n"
      "online EM SLAM with range-bearing observations over Monte-Carlo runs; prints the quantiles of the\n"
      "x error at several times (the paper's Fig. 2) and draws the mean map and path (its Fig. 1)");
  // clang-format off
  visible.add_options()
      ("help,h", "this help")
      ("runs", po::value(&options.runs)->default_value(options.runs), "Monte-Carlo runs (the paper: 50)")
      ("seed", po::value(&options.seed)->default_value(options.seed), "run r uses seed + r (data and filter)")
      ("steps", po::value(&options.steps)->default_value(options.steps), "steps per run (the paper: T = 1626)")
      ("particles", po::value(&options.particles)->default_value(options.particles), "particles (the paper: 100)")
      ("indicators", po::value(&options.indicators)->default_value(options.indicators),
       "mixture indicators: sampled (Algorithm 1) | marginal (summed out)")
      ("times", po::value(&options.times)->multitoken()->default_value(options.times, "100 250 500 1000 1626"),
       "steps at which the errors are tabulated")
      ("csv", po::value(&csv_path), "FILE: write every run's errors at those times as CSV")
      ("svg", po::value(&svg_path), "FILE: draw Fig. 1 (true and mean estimated map and path)")
      ("png", po::value(&png_path), "FILE: the figure as PNG too (needs --svg and rsvg-convert)")
      ("quiet,q", po::bool_switch(&quiet), "no per-run progress on stderr");
  // clang-format on
  try {
    po::variables_map vm;
    if (!roam::tools::parseCommandLine(argc, argv, visible, &vm)) return 0;
    if (options.runs < 1) throw std::runtime_error("--runs: runs must be >= 1");
    if (options.steps < 1) throw std::runtime_error("--steps: steps must be >= 1");
    if (options.particles < 2) throw std::runtime_error("--particles: particles must be >= 2");
    for (int t : options.times)
      if (t < 1 || t > options.steps) throw std::runtime_error("--times: every time must be in [1, --steps]");
    if (options.indicators != "sampled" && options.indicators != "marginal")
      throw std::runtime_error("--indicators: expected sampled or marginal, got '" + options.indicators + "'");
    if (!png_path.empty() && svg_path.empty()) throw std::runtime_error("--png needs --svg");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "roam-online-em-paper-sim: error: %s\n", e.what());
    return 2;
  }
  try {
    options.progress = quiet ? nullptr : stderr;
    const ps::Study study = ps::runStudy(options);
    const std::vector<int>& times = study.options.times;
    int diverged = 0;
    for (const ps::RunResult& r : study.runs) diverged += r.diverged;
    std::printf("%d runs x %d steps, %d particles, %s indicators, seeds %llu..%llu; runs whose position error ever exceeded "
                "%.0f m: %d\n\n",
                options.runs, options.steps, options.particles, options.indicators.c_str(), static_cast<unsigned long long>(options.seed),
                static_cast<unsigned long long>(options.seed + options.runs - 1), options.diverged_m, diverged);
    const Table tables[] = {{"x error (true - estimated), m", &ps::RunResult::x_error_m},
                            {"y error (true - estimated), m", &ps::RunResult::y_error_m},
                            {"mean landmark error, m", &ps::RunResult::map_error_m},
                            {"mean landmark error after the best rigid fit (the map's shape), m",
                             &ps::RunResult::aligned_map_error_m}};
    for (const Table& table : tables) {
      std::printf("%s, over the runs:\n\n| t | min | 25 %% | median | 75 %% | max |\n|---:|---:|---:|---:|---:|---:|\n",
                  table.title);
      for (size_t i = 0; i < times.size(); ++i) {
        const ps::Quantiles q = ps::quantiles(ps::column(study, table.series, i));
        std::printf("| %d | %.2f | %.2f | %.2f | %.2f | %.2f |\n", times[i], q.min, q.q25, q.median, q.q75, q.max);
      }
      std::printf("\n");
    }
    if (!csv_path.empty()) {
      std::string csv = "run,t,x_error_m,y_error_m,map_error_m,aligned_map_error_m\n";
      for (size_t r = 0; r < study.runs.size(); ++r)
        for (size_t i = 0; i < times.size(); ++i) {
          char line[160];
          std::snprintf(line, sizeof line, "%zu,%d,%.6f,%.6f,%.6f,%.6f\n", r + 1, times[i],
                        study.runs[r].x_error_m[i], study.runs[r].y_error_m[i], study.runs[r].map_error_m[i],
                        study.runs[r].aligned_map_error_m[i]);
          csv += line;
        }
      writeFile(csv_path, csv);
    }
    if (!svg_path.empty()) {
      writeFile(svg_path, ps::figureSvg(study));
      if (!png_path.empty()) roam::plot::renderPng(svg_path, png_path, ps::kFigureWidthPx, ps::kFigureHeightPx);
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "roam-online-em-paper-sim: error: %s\n", e.what());
    return 1;
  }
}
