// roam-eval RESULT_LOG [more logs...] [--format text|markdown|csv|json] [--aligned]
//           [--metric mean|rmse|both] [--no-odometry]
// Scores every estimator of each result log against its GROUND_TRUTH (see path_score.hpp and
// score_table.hpp); a team log (GROUND_TRUTH_<R> per robot) per robot and as a team
// (team_score.hpp), in a table of its own. Exit 2 with a one-line message when a log cannot be read or an option is bad.
#include <boost/program_options.hpp>
#include <cstdio>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include "command_line.hpp"
#include "result_log.hpp"
#include "score_table.hpp"

namespace po = boost::program_options;

namespace {

std::string runLabel(const std::string& path) {
  std::string name = path.substr(path.find_last_of('/') + 1);
  const std::string ext = ".lcmlog";
  if (name.size() > ext.size() && name.compare(name.size() - ext.size(), ext.size(), ext) == 0)
    name.resize(name.size() - ext.size());
  return name;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> logs;
  std::string format_name = "text", metric_name = "both";
  po::options_description visible(
      "roam-eval RESULT_LOG [more logs...]: the score table (full path, last / best / worst 10 %,\n"
      "mean error and RMSE, max, beacon error, CPU time) of every estimator in each log");
  visible.add_options()
      ("help,h", "this help")
      ("format", po::value(&format_name)->default_value("text"), "text | markdown | csv | json")
      ("metric", po::value(&metric_name)->default_value("both"), "mean | rmse | both (text and markdown)")
      ("aligned", "fit each path (and map) to ground truth by the best rigid 2-D motion first (a team "
                  "log: each robot's path alone; the team columns show both)")
      ("no-odometry", "leave out the 'odometry' row (dead reckoning integrated from the log's ODOMETRY)")
      ("status", "instead of scores: each estimator's last STATUS_ (state, accepted and rejected input, "
                 "diagnostics such as the odometry calibration it recovered), one line each");
  po::options_description hidden;
  hidden.add_options()("log", po::value(&logs));
  po::positional_options_description positional;
  positional.add("log", -1);
  try {
    po::variables_map vm;
    if (!roam::tools::parseCommandLine(argc, argv, visible, hidden, positional, &vm)) return 0;
    roam::TableFormat format;
    if (format_name == "text") format = roam::TableFormat::kText;
    else if (format_name == "markdown") format = roam::TableFormat::kMarkdown;
    else if (format_name == "csv") format = roam::TableFormat::kCsv;
    else if (format_name == "json") format = roam::TableFormat::kJson;
    else throw std::runtime_error("--format: expected text | markdown | csv | json, got '" + format_name + "'");
    roam::TableMetric metric;
    if (metric_name == "mean") metric = roam::TableMetric::kMean;
    else if (metric_name == "rmse") metric = roam::TableMetric::kRmse;
    else if (metric_name == "both") metric = roam::TableMetric::kBoth;
    else throw std::runtime_error("--metric: expected mean | rmse | both, got '" + metric_name + "'");
    if (logs.empty()) throw std::runtime_error("missing RESULT_LOG (a log with GROUND_TRUTH and estimator outputs)");

    if (vm.count("status")) {
      for (const std::string& path : logs) {
        const roam::ResultLog log = roam::readResultLog(path);
        for (const roam::EstimatorOutputs& e : log.estimators) {
          std::printf("%s %s: %s, odometry %ld/%ld rejected, ranges %ld/%ld rejected", runLabel(path).c_str(),
                      e.name.c_str(), e.state.empty() ? "no status" : e.state.c_str(), e.odometry_rejected,
                      e.odometry_accepted + e.odometry_rejected, e.ranges_rejected,
                      e.ranges_accepted + e.ranges_rejected);
          for (const auto& [key, value] : e.diagnostics) std::printf("; %s %.6g", key.c_str(), value);
          if (!e.last_error.empty()) std::printf("; error: %s", e.last_error.c_str());
          std::printf("\n");
        }
      }
      return 0;
    }
    std::vector<roam::RunScores> runs;
    for (const std::string& path : logs) {
      const roam::ResultLog log = roam::readResultLog(path);
      if (log.skipped > 0) {
        std::fprintf(stderr, "roam-eval: %s: skipped %ld corrupt or undecodable event%s\n", path.c_str(),
                     log.skipped, log.skipped == 1 ? "" : "s");
      }
      if (log.ground_truth.empty() && !log.isTeam()) {
        std::fprintf(stderr, "roam-eval: %s: no GROUND_TRUTH: nothing can be scored\n", path.c_str());
      }
      std::string label = runLabel(path);
      for (const auto& run : runs) {
        if (run.run == label) label = path;  // two logs of the same name: use the paths
      }
      runs.push_back(roam::scoreRun(log, label, vm.count("aligned") > 0, vm.count("no-odometry") == 0));
      for (const auto& e : runs.back().estimators) {
        if (e.state == "failed") {
          std::fprintf(stderr, "roam-eval: %s: estimator '%s' failed\n", path.c_str(), e.estimator.c_str());
        }
      }
    }
    std::cout << roam::formatScores(runs, format, metric);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "roam-eval: error: %s\n", e.what());
    return 2;
  }
}
