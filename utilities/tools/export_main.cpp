// roam-export RESULT_LOG --estimator NAME [-o FILE]   the path roam-eval scores (the last
//                                                     TRAJECTORY_<NAME>, else every POSE_<NAME>)
// roam-export RESULT_LOG --ground-truth [-o FILE]     GROUND_TRUTH
//   --format csv (default): time_s,x_m,y_m,heading_rad
//   --format tum: "timestamp x y z qx qy qz qw" (evo's TUM trajectory format; z = 0, the
//                 heading as a rotation about +z)
//   --format pyfg: the path at the log's odometry times (interpolated; the start pose and one
//                 pose per step) as VERTEX_SE2, the estimator's last map (else the surveyed
//                 BEACONS) as VERTEX_XY, and the log's odometry and ranges as EDGE_SE2 and
//                 EDGE_RANGE: the run as a factor graph initialised at roam's answer
// roam-export RESULT_LOG --map --estimator NAME       the last MAP_<NAME> as beacon_id,x_m,y_m
// roam-export RESULT_LOG --map                        the surveyed BEACONS, same layout
// NAME may also be 'odometry': dead reckoning integrated from INITIAL_POSE and ODOMETRY, as in
// roam-eval. Output to stdout unless -o FILE. Exit 2 with a one-line message on any error.
// A team log (GROUND_TRUTH_<R> per robot R; result_log.hpp): --robot R exports robot R's path
// (GROUND_TRUTH_R, or TRAJECTORY_<NAME>_R, else every POSE_<NAME>_R) as csv or tum; without
// --robot, -o FILE writes one file per robot, FILE with _<R> before its extension (out.tum ->
// out_A.tum), skipping with a warning a robot the estimator published no path for.
#include <boost/program_options.hpp>
#include <algorithm>
#include <cmath>
#include <optional>
#include <cstdio>
#include <exception>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "command_line.hpp"
#include "pyfg_dataset.hpp"
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

void writeTum(std::ostream& out, const roam::Path& path) {
  for (const roam::Pose& p : path) {
    char time[32];
    std::snprintf(time, sizeof time, "%.6f", 1e-6 * static_cast<double>(p.utime));
    out << time << " " << number(p.x_m) << " " << number(p.y_m) << " 0 0 0 " << number(std::sin(0.5 * p.heading_rad))
        << " " << number(std::cos(0.5 * p.heading_rad)) << "\n";
  }
}

// The path at time t: linear between the bracketing poses (heading along the shorter arc),
// the end pose outside the path's span.
roam::Pose poseAt(const roam::Path& path, int64_t utime) {
  auto after = std::lower_bound(path.begin(), path.end(), utime,
                                [](const roam::Pose& p, int64_t t) { return p.utime < t; });
  roam::Pose out;
  if (after == path.begin()) out = path.front();
  else if (after == path.end()) out = path.back();
  else if (after->utime == utime) out = *after;
  else {
    const roam::Pose& a = *(after - 1);
    const roam::Pose& b = *after;
    const double f = static_cast<double>(utime - a.utime) / static_cast<double>(b.utime - a.utime);
    out.x_m = a.x_m + f * (b.x_m - a.x_m);
    out.y_m = a.y_m + f * (b.y_m - a.y_m);
    out.heading_rad = a.heading_rad + f * roam::wrapAngle(b.heading_rad - a.heading_rad);
  }
  out.utime = utime;
  return out;
}

void writePyfgExport(const std::string& file, const roam::ResultLog& log, roam::Path path,
                     const std::optional<roam::Map>& map) {
  if (!log.start || log.odometry.empty())
    throw std::runtime_error(log.path + ": pyfg export needs INITIAL_POSE and ODOMETRY in the log");
  if (path.empty()) throw std::runtime_error(log.path + ": the path to export is empty");
  std::stable_sort(path.begin(), path.end(), [](const roam::Pose& a, const roam::Pose& b) { return a.utime < b.utime; });
  roam::Dataset graph;
  graph.start = *log.start;
  graph.ground_truth.push_back(poseAt(path, log.start->utime));
  for (const roam::Odometry& o : log.odometry) graph.ground_truth.push_back(poseAt(path, o.utime));
  graph.odometry = log.odometry;
  graph.ranges = log.ranges;
  if (map) graph.beacons = *map;
  else if (log.beacons) graph.beacons = *log.beacons;
  roam::writePyfg(file, graph);
}

// "dir/out.tum" + "A" -> "dir/out_A.tum"; "out" -> "out_A".
std::string robotFile(const std::string& file, const std::string& robot) {
  const size_t slash = file.find_last_of('/');
  const size_t dot = file.find_last_of('.');
  const bool has_extension = dot != std::string::npos && (slash == std::string::npos || dot > slash + 1);
  return has_extension ? file.substr(0, dot) + "_" + robot + file.substr(dot) : file + "_" + robot;
}

void writePathAs(std::ostream& out, const roam::Path& path, const std::string& format) {
  if (format == "tum") writeTum(out, path);
  else writePath(out, path);
}

std::string joined(const std::vector<std::string>& names) {
  std::string list;
  for (const auto& name : names) list += (list.empty() ? "" : ", ") + name;
  return list;
}

void writeMap(std::ostream& out, const roam::Map& map) {
  out << "beacon_id,x_m,y_m\n";
  for (const roam::Beacon& b : map) out << b.id << "," << number(b.x_m) << "," << number(b.y_m) << "\n";
}

}  // namespace

int main(int argc, char** argv) {
  std::string log_path, estimator, output, format = "csv";
  po::options_description visible(
      "roam-export RESULT_LOG (--estimator NAME | --ground-truth) [--map] [--format csv|tum|pyfg] [--robot R]\n"
      "[-o FILE]:\n"
      "a path as CSV time_s,x_m,y_m,heading_rad, as TUM (evo) or as a pyfg factor graph; with --map\n"
      "beacons as beacon_id,x_m,y_m");
  visible.add_options()
      ("help,h", "this help")
      ("format", po::value(&format)->default_value(format),
       "csv | tum (timestamp x y z qx qy qz qw, for evo) | pyfg (poses at the odometry times, "
       "the map, the log's odometry and ranges; needs -o FILE)")
      ("estimator", po::value(&estimator), "NAME: the path roam-eval scores for this estimator")
      ("ground-truth", "GROUND_TRUTH instead of an estimator's path")
      ("map", "the last MAP_<NAME> of --estimator, or the surveyed BEACONS without --estimator")
      ("robot", po::value<std::string>(), "R: on a team log, robot R's path; without it, -o FILE writes "
                                          "one file per robot, FILE_<R> (out.tum -> out_A.tum)")
      ("output,o", po::value(&output), "FILE to write (default: stdout)");
  po::options_description hidden;
  hidden.add_options()("log", po::value(&log_path));
  po::positional_options_description positional;
  positional.add("log", 1);
  try {
    po::variables_map vm;
    if (!roam::tools::parseCommandLine(argc, argv, visible, hidden, positional, &vm)) return 0;
    const bool ground_truth = vm.count("ground-truth") > 0, map = vm.count("map") > 0;
    if (log_path.empty()) throw std::runtime_error("missing RESULT_LOG");
    if (ground_truth && !estimator.empty()) throw std::runtime_error("give --estimator NAME or --ground-truth, not both");
    if (ground_truth && map) throw std::runtime_error("--map exports beacons; --ground-truth a path: choose one");
    if (!ground_truth && !map && estimator.empty())
      throw std::runtime_error("missing --estimator NAME (or --ground-truth, or --map)");
    if (format != "csv" && format != "tum" && format != "pyfg")
      throw std::runtime_error("--format: expected csv | tum | pyfg, got '" + format + "'");
    if (map && format != "csv") throw std::runtime_error("--map writes CSV; --format " + format + " is for paths");
    if (format == "pyfg" && output.empty()) throw std::runtime_error("--format pyfg needs -o FILE");

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
    const std::string robot = vm.count("robot") ? vm["robot"].as<std::string>() : "";
    if (vm.count("robot") && !log.isTeam())
      throw std::runtime_error("--robot " + robot + ": " + log_path + " is not a team log (no GROUND_TRUTH_<R>)");
    if (log.isTeam() && !map) {
      if (format == "pyfg") throw std::runtime_error("--format pyfg: a team log's paths export as csv or tum");
      const std::vector<std::string> robots = log.robotNames();
      const roam::EstimatorOutputs* e = nullptr;
      if (!ground_truth) {
        e = log.find(estimator);
        if (!e) throw std::runtime_error(log_path + ": no estimator '" + estimator + "' (found: " + names() + ")");
      }
      auto pathOf = [&](const std::string& r) { return e ? e->robotPath(r) : &log.team_ground_truth.at(r); };
      auto noPath = [&](const std::string& r) {
        return log_path + ": estimator '" + e->name + "' published no path for robot " + r;
      };
      if (vm.count("robot")) {
        if (!log.team_ground_truth.count(robot))
          throw std::runtime_error(log_path + ": no robot '" + robot + "' in the team (robots: " + joined(robots) + ")");
        const roam::Path* path = pathOf(robot);
        if (!path) throw std::runtime_error(noPath(robot));
        std::ofstream file;
        if (!output.empty()) {
          file.open(output);
          if (!file) throw std::runtime_error(output + ": cannot open for writing");
        }
        std::ostream& out = output.empty() ? std::cout : file;
        writePathAs(out, *path, format);
        out.flush();
        if (!out) throw std::runtime_error((output.empty() ? std::string("stdout") : output) + ": write failed");
        return 0;
      }
      if (output.empty())
        throw std::runtime_error(log_path + " is a team log (robots " + joined(robots) +
                                 "): give --robot R, or -o FILE for one file per robot (FILE_<R>)");
      size_t written = 0;
      for (const std::string& r : robots) {
        const roam::Path* path = pathOf(r);
        if (!path) {
          std::fprintf(stderr, "roam-export: %s: no file for it\n", noPath(r).c_str());
          continue;
        }
        const std::string name = robotFile(output, r);
        std::ofstream file(name);
        if (!file) throw std::runtime_error(name + ": cannot open for writing");
        writePathAs(file, *path, format);
        file.flush();
        if (!file) throw std::runtime_error(name + ": write failed");
        ++written;
      }
      if (written == 0) throw std::runtime_error(log_path + ": estimator '" + e->name + "' published no path for any robot");
      return 0;
    }
    std::ofstream file;
    if (!output.empty() && format != "pyfg") {
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
    } else {
      roam::Path path;
      std::optional<roam::Map> estimated_map;
      if (ground_truth) {
        if (log.ground_truth.empty()) throw std::runtime_error(log_path + ": no GROUND_TRUTH in the log");
        path = log.ground_truth;
      } else if (estimator == roam::kOdometryRowName && !log.find(estimator)) {
        if (!log.start || log.odometry.empty())
          throw std::runtime_error(log_path + ": 'odometry' needs INITIAL_POSE and ODOMETRY in the log");
        path = roam::integrateOdometry(*log.start, log.odometry);
      } else {
        const roam::EstimatorOutputs* e = log.find(estimator);
        if (!e) throw std::runtime_error(log_path + ": no estimator '" + estimator + "' (found: " + names() + ")");
        path = e->scoredPath();
        estimated_map = e->map;
      }
      if (format == "csv") writePath(out, path);
      else if (format == "tum") writeTum(out, path);
      else {
        writePyfgExport(output, log, path, estimated_map);
        return 0;
      }
    }
    out.flush();
    if (!out) throw std::runtime_error((output.empty() ? std::string("stdout") : output) + ": write failed");
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "roam-export: error: %s\n", e.what());
    return 2;
  }
}
