// roam-export RESULT_LOG --estimator NAME [-o FILE]   the path roam-eval scores (the last
//                                                     TRAJECTORY_<NAME>, else every POSE_<NAME>)
// roam-export RESULT_LOG --ground-truth [-o FILE]     GROUND_TRUTH
//   both as CSV time_s,x_m,y_m,heading_rad
// roam-export RESULT_LOG --map --estimator NAME       the last MAP_<NAME> as beacon_id,x_m,y_m
// roam-export RESULT_LOG --map                        the surveyed BEACONS, same layout
// NAME may also be 'odometry': dead reckoning integrated from INITIAL_POSE and ODOMETRY, as in
// roam-eval. Output to stdout unless -o FILE. Exit 2 with a one-line message on any error.
#include <boost/program_options.hpp>
#include <cstdio>
#include <exception>
#include <fstream>
#include <iostream>
#include <string>

#include "result_log.hpp"
#include "score_table.hpp"

namespace po = boost::program_options;

namespace {

std::string number(double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.17g", value);
  return buffer;
}

void writePath(std::ostream& out, const roam::Path& path) {
  out << "time_s,x_m,y_m,heading_rad\n";
  for (const roam::Pose& p : path) {
    char time[32];
    std::snprintf(time, sizeof time, "%.6f", 1e-6 * static_cast<double>(p.utime));
    out << time << "," << number(p.x_m) << "," << number(p.y_m) << "," << number(p.heading_rad) << "\n";
  }
}

void writeMap(std::ostream& out, const roam::Map& map) {
  out << "beacon_id,x_m,y_m\n";
  for (const roam::Beacon& b : map) out << b.id << "," << number(b.x_m) << "," << number(b.y_m) << "\n";
}

}  // namespace

int main(int argc, char** argv) {
  std::string log_path, estimator, output;
  po::options_description visible(
      "roam-export RESULT_LOG (--estimator NAME | --ground-truth) [--map] [-o FILE]: a path as CSV\n"
      "time_s,x_m,y_m,heading_rad, or with --map beacons as beacon_id,x_m,y_m");
  visible.add_options()
      ("help,h", "this help")
      ("estimator", po::value(&estimator), "NAME: the path roam-eval scores for this estimator")
      ("ground-truth", "GROUND_TRUTH instead of an estimator's path")
      ("map", "the last MAP_<NAME> of --estimator, or the surveyed BEACONS without --estimator")
      ("output,o", po::value(&output), "FILE to write (default: stdout)");
  po::options_description all;
  all.add(visible).add_options()("log", po::value(&log_path));
  po::positional_options_description positional;
  positional.add("log", 1);
  try {
    po::variables_map vm;
    po::store(po::command_line_parser(argc, argv).options(all).positional(positional).run(), vm);
    if (vm.count("help")) {
      std::cout << visible << "\n";
      return 0;
    }
    po::notify(vm);
    const bool ground_truth = vm.count("ground-truth") > 0, map = vm.count("map") > 0;
    if (log_path.empty()) throw std::runtime_error("missing RESULT_LOG");
    if (ground_truth && !estimator.empty()) throw std::runtime_error("give --estimator NAME or --ground-truth, not both");
    if (ground_truth && map) throw std::runtime_error("--map exports beacons; --ground-truth a path: choose one");
    if (!ground_truth && !map && estimator.empty())
      throw std::runtime_error("missing --estimator NAME (or --ground-truth, or --map)");

    const roam::ResultLog log = roam::readResultLog(log_path);
    if (log.skipped > 0) {
      std::fprintf(stderr, "roam-export: %s: skipped %ld corrupt or undecodable event%s\n", log_path.c_str(),
                   log.skipped, log.skipped == 1 ? "" : "s");
    }
    auto names = [&] {
      std::string list;
      for (const auto& e : log.estimators) list += (list.empty() ? "" : ", ") + e.name;
      return list.empty() ? std::string("none") : list;
    };
    std::ofstream file;
    if (!output.empty()) {
      file.open(output);
      if (!file) throw std::runtime_error(output + ": cannot open for writing");
    }
    std::ostream& out = output.empty() ? std::cout : file;

    if (map) {
      if (estimator.empty()) {
        if (!log.beacons) throw std::runtime_error(log_path + ": no BEACONS in the log");
        writeMap(out, *log.beacons);
      } else {
        const roam::EstimatorOutputs* e = log.find(estimator);
        if (!e) throw std::runtime_error(log_path + ": no estimator '" + estimator + "' (found: " + names() + ")");
        if (!e->map) throw std::runtime_error(log_path + ": no MAP_" + e->suffix + " in the log");
        writeMap(out, *e->map);
      }
    } else if (ground_truth) {
      if (log.ground_truth.empty()) throw std::runtime_error(log_path + ": no GROUND_TRUTH in the log");
      writePath(out, log.ground_truth);
    } else if (estimator == roam::kOdometryRowName && !log.find(estimator)) {
      if (!log.start || log.odometry.empty())
        throw std::runtime_error(log_path + ": 'odometry' needs INITIAL_POSE and ODOMETRY in the log");
      writePath(out, roam::integrateOdometry(*log.start, log.odometry));
    } else {
      const roam::EstimatorOutputs* e = log.find(estimator);
      if (!e) throw std::runtime_error(log_path + ": no estimator '" + estimator + "' (found: " + names() + ")");
      writePath(out, e->scoredPath());
    }
    out.flush();
    if (!out) throw std::runtime_error((output.empty() ? std::string("stdout") : output) + ": write failed");
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "roam-export: error: %s\n", e.what());
    return 2;
  }
}
