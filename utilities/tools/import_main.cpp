// roam-import DIR -o LOG [--heading-offset RAD|auto] [--odometry-from-path FILE]
// roam-import FILE.pyfg -o LOG [--forward-axis x|y|auto] [--pose-interval-s S] [--robot LETTER]
// A run in the CSV layout of data/plaza1 (see utilities/dataset/csv_dataset.hpp) or a
// pyfg file (utilities/dataset/pyfg_dataset.hpp) to an LCM log (see dataset_log.hpp). The format
// is known from the argument (a folder: csv; a name ending in .pyfg: pyfg) or --format. Prints
// a one-line summary; exit 2 with a one-line error. A pyfg file of several robots without
// --robot is read whole (utilities/dataset/pyfg_team.hpp) and written as a team log, with a
// summary line per robot and the [team] config line that names its robots.
#include <boost/program_options.hpp>
#include <algorithm>
#include <cmath>
#include <map>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <stdexcept>
#include <string>
#include <vector>

#include "command_line.hpp"
#include "csv_dataset.hpp"
#include "dataset_log.hpp"
#include "pyfg_dataset.hpp"
#include "pyfg_team.hpp"

namespace po = boost::program_options;

namespace {

// From the start pose to the run's last event (odometry, range or ground truth), in seconds.
double runSeconds(const roam::Dataset& dataset) {
  int64_t last = dataset.start.utime;
  if (!dataset.odometry.empty()) last = std::max(last, dataset.odometry.back().utime);
  if (!dataset.ranges.empty()) last = std::max(last, dataset.ranges.back().utime);
  if (!dataset.ground_truth.empty()) last = std::max(last, dataset.ground_truth.back().utime);
  return 1e-6 * static_cast<double>(last - dataset.start.utime);
}

// A pyfg file of several robots as a team log: a line for the log, one per robot, the beacons,
// the [team] config line, then the notes.
int importTeam(const std::string& file, const std::string& output, const roam::PyfgImportOptions& options,
               bool auto_axis) {
  const roam::TeamImport imported = roam::loadPyfgTeam(file, options);
  const roam::TeamDataset& team = imported.team;
  const roam::TeamLogWriteSummary s = roam::writeTeamLog(output, team);
  long robot_ranges = 0;
  for (long count : s.robot_ranges) robot_ranges += count;
  std::printf("roam-import: %s: a team of %zu robots, %ld events (%ld ranges between robots, %ld beacons); body "
              "frame forward axis %s%s\n",
              output.c_str(), team.robots.size(), s.events, robot_ranges, s.beacons,
              imported.forward_axis == roam::ForwardAxis::kY ? "+y (headings + pi/2)" : "+x", auto_axis ? " (auto)" : "");
  for (size_t r = 0; r < team.robots.size(); ++r) {
    const roam::Dataset& d = team.members[r];
    const roam::LogWriteSummary& m = s.members[r];
    std::printf("roam-import: robot %s: %ld odometry, %ld ranges to beacons, %ld ranges to robots, %ld ground truth, "
                "%.3f s from utime %lld\n",
                team.robots[r].c_str(), m.odometry, m.ranges, s.robot_ranges[r], m.ground_truth, runSeconds(d),
                static_cast<long long>(d.start.utime));
  }
  std::string ids;
  for (const roam::Beacon& b : team.beacons) ids += (ids.empty() ? " (ids " : " ") + std::to_string(b.id);
  std::printf("roam-import: the team's beacons: %zu%s\n", team.beacons.size(), ids.empty() ? "" : (ids + ")").c_str());
  std::string names;
  for (const std::string& name : team.robots) names += " " + name;
  std::printf("roam-import: config: [team] robots =%s\n", names.c_str());
  for (const std::string& note : imported.notes) std::printf("roam-import: note: %s\n", note.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::string dir, output, format, forward_axis = "auto", heading_offset = "auto";
  double pose_interval_s = 0.0;
  std::string robot, time_unit = "auto";
  roam::CsvImportOptions options;
  po::options_description visible(
      "roam-import DIR -o LOG: a run in the CSV layout (odometry.csv, ranges.csv, and where there are\n"
      "groundtruth.csv and landmarks.csv) to an LCM log with INITIAL_POSE, BEACONS, GROUND_TRUTH,\n"
      "ODOMETRY, RANGE (no groundtruth.csv: the start pose is the origin, heading 0, or the first\n"
      "row of --odometry-from-path)\n"
      "roam-import FILE.pyfg -o LOG: the same from a pyfg file (2-D); a file of several robots\n"
      "without --robot: a team log (INITIAL_POSE_<R>, GROUND_TRUTH_<R>, ODOMETRY_<R>, RANGE_<R>,\n"
      "ROBOT_RANGE_<R> per robot R, BEACONS), a summary per robot and the [team] config line");
  visible.add_options()
      ("help,h", "this help")
      ("output,o", po::value(&output), "the LCM log to write (required)")
      ("format", po::value(&format), "csv | pyfg (default: pyfg for a name ending in .pyfg, csv for a folder)")
      ("forward-axis", po::value(&forward_axis)->default_value(forward_axis),
       "pyfg: the body axis the robot moves along: x | y | auto (y when the edges' median |dy| is "
       "over twice their median |dx|)")
      ("pose-interval-s", po::value(&pose_interval_s)->default_value(0.0),
       "pyfg: SECONDS between consecutive poses, for a file whose poses carry no times (all at one "
       "time); 0: the file's times")
      ("time-unit", po::value(&time_unit)->default_value(time_unit),
       "pyfg: the unit of the file's times: s | ms | us | ns | auto (the largest unit that puts the "
       "latest time within 1e11 s: published runs stamp poses in nanoseconds)")
      ("robot", po::value(&robot),
       "pyfg: the LETTER of the robot to read from a file of several (A, B, ...); the other robots' "
       "lines and the ranges between robots are set aside with a note (without it: the whole team)")
      ("heading-offset", po::value(&heading_offset)->default_value(heading_offset),
       "RAD added to every ground-truth heading (e.g. 3.14159265 for reversed headings), or auto: "
       "measured, and applied where the ground truth's heading is its direction of travel plus a "
       "steady offset of 0.1 rad or more (with a note)")
      ("odometry-from-path", po::value(&options.odometry_from_path),
       "FILE: derive odometry from a dead-reckoned path CSV (time_s,x_m,y_m[,heading_rad]) "
       "instead of odometry.csv");
  po::options_description hidden;
  hidden.add_options()("dir", po::value(&dir));
  po::positional_options_description positional;
  positional.add("dir", 1);
  try {
    po::variables_map vm;
    if (!roam::tools::parseCommandLine(argc, argv, visible, hidden, positional, &vm)) return 0;
    if (dir.empty()) throw std::runtime_error("missing DIR or FILE.pyfg (the run to import)");
    if (output.empty()) throw std::runtime_error("missing -o LOG (the log to write)");
    if (format.empty()) {
      const bool pyfg_name = dir.size() > 5 && dir.compare(dir.size() - 5, 5, ".pyfg") == 0;
      format = pyfg_name ? "pyfg" : "csv";
    }
    if (format == "pyfg") {
      roam::PyfgImportOptions pyfg;
      if (forward_axis == "x") pyfg.forward_axis = roam::ForwardAxis::kX;
      else if (forward_axis == "y") pyfg.forward_axis = roam::ForwardAxis::kY;
      else if (forward_axis != "auto") throw std::runtime_error("--forward-axis: expected x | y | auto, got '" + forward_axis + "'");
      if (!(pose_interval_s >= 0.0) || !std::isfinite(pose_interval_s))
        throw std::runtime_error("--pose-interval-s: expected seconds >= 0, got " + std::to_string(pose_interval_s));
      pyfg.pose_interval_s = pose_interval_s;
      const std::map<std::string, double> units = {{"s", 1.0}, {"ms", 1e-3}, {"us", 1e-6}, {"ns", 1e-9}, {"auto", 0.0}};
      if (!units.count(time_unit)) throw std::runtime_error("--time-unit: expected s | ms | us | ns | auto, got '" + time_unit + "'");
      pyfg.time_unit_s = units.at(time_unit);
      if (vm.count("robot")) {
        if (robot.size() != 1) throw std::runtime_error("--robot: expected one robot letter (A, B, ...), got '" + robot + "'");
        pyfg.robot = robot[0];
      }
      if (!vm["heading-offset"].defaulted() || !options.odometry_from_path.empty())
        throw std::runtime_error("--heading-offset and --odometry-from-path are for the CSV layout, not pyfg");
      if (pyfg.robot == 0 && roam::pyfgRobotLetters(dir).size() > 1) return importTeam(dir, output, pyfg, forward_axis == "auto");
      const roam::PyfgImport imported = roam::loadPyfgDataset(dir, pyfg);
      const roam::Dataset& dataset = imported.dataset;
      const roam::LogWriteSummary s = roam::writeDatasetLog(output, dataset);
      std::printf("roam-import: %s: %ld events (%ld odometry, %ld ranges, %ld ground truth, %ld beacons), "
                  "%.3f s from utime %lld; body frame forward axis %s%s\n",
                  output.c_str(), s.events, s.odometry, s.ranges, s.ground_truth, s.beacons,
                  runSeconds(dataset),
                  static_cast<long long>(dataset.start.utime),
                  imported.forward_axis == roam::ForwardAxis::kY ? "+y (headings + pi/2)" : "+x",
                  forward_axis == "auto" ? " (auto)" : "");
      for (const std::string& note : imported.notes) std::printf("roam-import: note: %s\n", note.c_str());
      return 0;
    }
    if (format != "csv") throw std::runtime_error("--format: expected csv | pyfg, got '" + format + "'");
    if (!vm["pose-interval-s"].defaulted()) throw std::runtime_error("--pose-interval-s is for pyfg, not the CSV layout");
    if (vm.count("robot")) throw std::runtime_error("--robot is for pyfg, not the CSV layout");
    if (!vm["time-unit"].defaulted()) throw std::runtime_error("--time-unit is for pyfg, not the CSV layout");
    if (heading_offset != "auto") {
      size_t used = 0;
      double offset_rad = 0.0;
      try {
        offset_rad = std::stod(heading_offset, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != heading_offset.size() || !std::isfinite(offset_rad))
        throw std::runtime_error("--heading-offset: expected radians or auto, got '" + heading_offset + "'");
      options.heading_offset_rad = offset_rad;
    }
    std::vector<std::string> notes;
    const roam::Dataset dataset = roam::loadCsvDataset(dir, options, &notes);
    const roam::LogWriteSummary s = roam::writeDatasetLog(output, dataset);
    std::printf("roam-import: %s: %ld events (%ld odometry%s, %ld ranges, %ld ground truth, %ld beacons), "
                "%.3f s from utime %lld\n",
                output.c_str(), s.events, s.odometry,
                options.odometry_from_path.empty() ? "" : " from the path", s.ranges, s.ground_truth,
                s.beacons,
                runSeconds(dataset),
                static_cast<long long>(dataset.start.utime));
    for (const std::string& note : notes) std::printf("roam-import: note: %s\n", note.c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "roam-import: error: %s\n", e.what());
    return 2;
  }
}
