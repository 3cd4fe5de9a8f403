#include "pyfg_dataset.hpp"

#include "pyfg_parse.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <utility>
#include <vector>

namespace roam {

using pyfg::Line;
using pyfg::RawEdge;
using pyfg::RawRange;
using pyfg::RawSighting;
using pyfg::splitName;

PyfgImport loadPyfgDataset(const std::string& path, const PyfgImportOptions& options) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open for reading");
  // The robot read: options.robot, or the first VERTEX_SE2's. With options.robot, every line of
  // another robot is set aside (other_robots), and so is a measurement between two robots
  // (inter_robot); without it a second robot is refused, naming the option.
  std::optional<int> robot;
  if (options.robot != 0) {
    if (!std::isalpha(static_cast<unsigned char>(options.robot)) || options.robot == 'L')
      throw std::runtime_error(path + ": robot '" + options.robot + "': expected a robot's letter (A-Z or a-z; L names beacons)");
    robot = options.robot;
  }
  std::set<int> robots_seen;
  auto robotLetters = [&](int except) {  // "A, B": the robots with a VERTEX_SE2, but one
    std::string letters;
    for (int letter : robots_seen)
      if (letter != except) letters += std::string(letters.empty() ? "" : ", ") + static_cast<char>(letter);
    return letters;
  };
  pyfg::RawPoses raw;  // the robot read's poses (heading as in the file) and odometry edges
  std::map<int, Pose>& poses = raw.poses;
  std::map<int, long>& pose_line = raw.line;
  std::map<int, Beacon> beacons;
  std::vector<RawEdge>& edges = raw.edges;
  std::vector<RawRange> ranges;
  std::vector<RawSighting> sightings;
  // What PyFactorGraph writes beside odometry and ranges, which roam's estimators do not take:
  // set aside and reported in PyfgImport::notes.
  LineTally pose_priors, loop_closures, other_robots, inter_robot;
  long ranges_to_robots = 0;  // of the robot read: ranges whose other end is another robot
  Line line;
  line.file = path;
  auto severalRobots = [&](const Line& l, int letter) {
    l.fail(std::string("several robots ('") + static_cast<char>(*robot) + "' and '" + static_cast<char>(letter) +
           "'): roam runs one robot per log; choose one with --robot " + static_cast<char>(*robot) +
           " (the other robots' lines are then set aside)");
  };
  // A pose name's robot letter and index (refused if the name is not a pose's).
  auto poseName = [&](const Line& l, const std::string& name, const char* role) {
    int letter = 0, index = 0;
    if (!splitName(name, &letter, &index) || letter == 'L') l.fail(std::string(role) + " '" + name + "' is not a pose name (a robot letter and an index, e.g. A12)");
    return std::make_pair(letter, index);
  };
  // With --robot: a pose of another robot (the line is set aside).
  auto ofOtherRobot = [&](const Line& l, const std::string& name, const char* role) {
    return options.robot != 0 && poseName(l, name, role).first != options.robot;
  };
  auto poseIndex = [&](const Line& l, const std::string& name, const char* role) {
    const auto [letter, index] = poseName(l, name, role);
    if (!robot) l.fail(std::string(role) + " '" + name + "' before any VERTEX_SE2");
    if (letter != *robot) severalRobots(l, letter);
    if (!poses.count(index)) l.fail(std::string(role) + " '" + name + "' has no VERTEX_SE2");
    return index;
  };
  auto checkNumbers = [](const Line& l, size_t first, size_t end, size_t measurements) {
    l.checkNumbers(first, end, measurements);
  };
  // With --robot: a line on one pose of another robot is checked and set aside (true).
  auto setAsideIfOtherRobot = [&](const Line& l, const std::string& name, const char* role, size_t first, size_t end,
                                  size_t measurements) {
    if (!ofOtherRobot(l, name, role)) return false;
    checkNumbers(l, first, end, measurements);
    other_robots.add(l.number);
    return true;
  };
  auto beaconIndex = [&](const Line& l, const std::string& name) {
    int letter = 0, index = 0;
    if (!splitName(name, &letter, &index) || letter != 'L') return -1;
    if (!beacons.count(index)) l.fail("beacon '" + name + "' has no VERTEX_XY");
    return index;
  };
  while (nextFields(in, &line)) {
    const std::string& type = line.fields[0];
    if (type == "VERTEX_SE2") {
      line.expectFields(6, "time name x y theta");
      int letter = 0, index = 0;
      if (!splitName(line.fields[2], &letter, &index) || letter == 'L') line.fail("VERTEX_SE2: '" + line.fields[2] + "' is not a pose name (e.g. A12)");
      robots_seen.insert(letter);
      if (!robot) robot = letter;
      if (letter != *robot) {
        if (options.robot == 0) severalRobots(line, letter);
        checkNumbers(line, 3, 6, 3);
        line.number_at(1, "time");
        other_robots.add(line.number);
        continue;
      }
      if (poses.count(index)) line.fail("VERTEX_SE2: pose '" + line.fields[2] + "' given twice (first on line " + std::to_string(pose_line[index]) + ")");
      poses[index] = pyfg::readPose(line, &raw.time[index]);
      pose_line[index] = line.number;
    } else if (type == "VERTEX_XY") {
      pyfg::readBeacon(line, &beacons);
    } else if (type == "VERTEX_XY:PRIOR") {
      pyfg::readBeaconPrior(line, &beacons);
    } else if (type == "EDGE_SE2") {
      line.expectFields(13, "time from to dx dy dtheta and 6 covariance values");
      const bool other_from = ofOtherRobot(line, line.fields[2], "EDGE_SE2: from");
      const bool other_to = ofOtherRobot(line, line.fields[3], "EDGE_SE2: to");
      if (other_from || other_to) {  // another robot's odometry or loop closure, or one between robots
        checkNumbers(line, 4, 13, 3);
        (other_from && other_to ? other_robots : inter_robot).add(line.number);
        continue;
      }
      RawEdge edge;
      edge.line = line.number;
      edge.from = poseIndex(line, line.fields[2], "EDGE_SE2: from");
      edge.to = poseIndex(line, line.fields[3], "EDGE_SE2: to");
      if (edge.to != edge.from + 1) {  // a loop closure
        checkNumbers(line, 4, 13, 3);
        loop_closures.add(line.number);
        continue;
      }
      pyfg::readEdgeNumbers(line, &edge);
      edges.push_back(edge);
    } else if (type == "EDGE_RANGE") {
      line.expectFields(6, "time a b range variance");
      const int b1 = beaconIndex(line, line.fields[2]), b2 = beaconIndex(line, line.fields[3]);
      if (b1 >= 0 && b2 >= 0) line.fail("EDGE_RANGE between two beacons is not supported");
      const bool other_a = b1 < 0 && ofOtherRobot(line, line.fields[2], "EDGE_RANGE: a");
      const bool other_b = b2 < 0 && ofOtherRobot(line, line.fields[3], "EDGE_RANGE: b");
      if (other_a || other_b) {  // another robot's range, or one between two robots
        checkNumbers(line, 4, 6, 1);
        (b1 < 0 && b2 < 0 && !(other_a && other_b) ? inter_robot : other_robots).add(line.number);
        if (b1 < 0 && b2 < 0 && other_a != other_b) ++ranges_to_robots;
        continue;
      }
      if (b1 < 0 && b2 < 0) {
        line.fail("EDGE_RANGE " + line.fields[2] + " " + line.fields[3] +
                  ": ranges between poses (inter-robot ranges) are not supported");
      }
      RawRange range;
      range.line = line.number;
      range.beacon = b1 >= 0 ? b1 : b2;
      range.pose = poseIndex(line, b1 >= 0 ? line.fields[3] : line.fields[2], "EDGE_RANGE: pose");
      pyfg::readRangeNumbers(line, &range);
      ranges.push_back(range);
    } else if (type.find("SE3") != std::string::npos || type.find("XYZ") != std::string::npos) {
      line.fail(type + ": 3-D data is not supported (roam is 2-D)");
    } else if (type == "VERTEX_SE2:PRIOR") {
      line.expectFields(12, "time name x y theta and 6 covariance values");
      if (setAsideIfOtherRobot(line, line.fields[2], "VERTEX_SE2:PRIOR: pose", 3, 12, 3)) continue;
      poseIndex(line, line.fields[2], "VERTEX_SE2:PRIOR: pose");
      checkNumbers(line, 3, 12, 3);
      pose_priors.add(line.number);
    } else if (type == "EDGE_SE2_XY") {
      line.expectFields(9, "time pose beacon dx dy and 3 covariance values");
      if (setAsideIfOtherRobot(line, line.fields[2], "EDGE_SE2_XY: pose", 4, 9, 2)) continue;
      RawSighting sighting;
      sighting.line = line.number;
      sighting.pose = poseIndex(line, line.fields[2], "EDGE_SE2_XY: pose");
      sighting.beacon = beaconIndex(line, line.fields[3]);
      if (sighting.beacon < 0) line.fail("EDGE_SE2_XY: '" + line.fields[3] + "' is not a beacon name (e.g. L3)");
      pyfg::readSightingNumbers(line, &sighting);
      sightings.push_back(sighting);
    } else {
      line.fail("unknown type '" + type + "'");
    }
  }
  if (poses.empty() && options.robot != 0 && !robots_seen.empty()) {
    throw std::runtime_error(path + ": no VERTEX_SE2 of robot '" + options.robot + "' (--robot); the file's robots: " +
                             robotLetters(0));
  }
  if (poses.empty()) throw std::runtime_error(path + ": no VERTEX_SE2 (a pyfg run needs poses)");
  // Poses must be A<first>, A<first+1>, ... with one edge into each but the first.
  pyfg::checkNumbering(path, *robot, raw);
  double latest = 0.0;
  for (const auto& [index, time] : raw.time) latest = std::max(latest, std::abs(time));
  const double unit_s = pyfg::resolveTimeUnit(path, options, latest);
  pyfg::stampPoses(path, options, unit_s, &raw);
  const std::map<int, const RawEdge*> edge_into = pyfg::edgesInto(path, *robot, raw);

  PyfgImport result;
  result.robot_letter = *robot;
  result.time_unit_s = unit_s;
  const std::string unit_note = pyfg::timeUnitNote(path, options, unit_s, latest);
  if (!unit_note.empty()) result.notes.push_back(unit_note);
  auto note = [&](const LineTally& set_aside, const std::string& what, const std::string& why) {
    if (std::string text = pyfg::setAsideNote(path, set_aside, what, why); !text.empty()) result.notes.push_back(text);
  };
  note(pose_priors, "pose prior(s) (VERTEX_SE2:PRIOR)",
       "the first VERTEX_SE2 is the start pose, and roam's estimators take no absolute fix");
  note(loop_closures, "loop closure(s) (EDGE_SE2 between poses that are not consecutive)",
       "roam's estimators take odometry and ranges");
  note(other_robots, "line(s) of other robots (" + robotLetters(*robot) + ")",
       std::string("--robot ") + static_cast<char>(*robot) + " reads robot " + static_cast<char>(*robot) + " alone");
  note(inter_robot, "measurement(s) between two robots (EDGE_RANGE, EDGE_SE2)",
       "roam's estimators take ranges to fixed beacons");
  if (options.pose_interval_s > 0.0) {
    char interval_s[32];
    std::snprintf(interval_s, sizeof interval_s, "%.6g", options.pose_interval_s);
    result.notes.push_back(path + ": pose i is at i x " + interval_s + " s (--pose-interval-s); the file's pose times are set aside");
  }
  result.forward_axis = pyfg::resolveForwardAxis(options.forward_axis, edges);
  const bool y_forward = result.forward_axis == ForwardAxis::kY;
  Dataset& d = result.dataset;
  d = pyfg::robotRun(raw, edge_into, ranges, sightings, y_forward, 0);
  for (const auto& [index, beacon] : beacons) d.beacons.push_back(beacon);
  if (d.ranges.empty()) {
    std::string why = ranges_to_robots > 0 ? ": its " + std::to_string(ranges_to_robots) +
                                                 " range(s) are all to other robots (set aside)"
                                           : ": the file has none";
    result.notes.push_back(path + ": robot " + static_cast<char>(*robot) + " has no range to a fixed beacon" + why +
                           "; an estimator run on this log has odometry alone (dead reckoning)");
  }
  return result;
}

namespace {

std::string number(double value) {
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%.17g", value);
  return buffer;
}

// utime as seconds with exactly six decimals: reads back to the same utime.
std::string seconds(int64_t utime) {
  char buffer[40];
  const int64_t whole = utime / 1000000, micro = utime % 1000000;
  if (utime < 0 && micro != 0) {
    std::snprintf(buffer, sizeof buffer, "-%lld.%06lld", static_cast<long long>(-(utime / 1000000)),
                  static_cast<long long>(-micro));
  } else {
    std::snprintf(buffer, sizeof buffer, "%lld.%06lld", static_cast<long long>(whole),
                  static_cast<long long>(micro < 0 ? -micro : micro));
  }
  return buffer;
}

}  // namespace

void writePyfg(const std::string& path, const Dataset& dataset, const PyfgWriteOptions& options) {
  const Path& poses = dataset.ground_truth;
  if (poses.size() != dataset.odometry.size() + 1) {
    throw std::runtime_error(path + ": pyfg needs one pose per odometry step plus the start (" +
                             std::to_string(poses.size()) + " poses, " +
                             std::to_string(dataset.odometry.size()) + " steps)");
  }
  std::ofstream out(path);
  if (!out) throw std::runtime_error(path + ": cannot open for writing");
  const bool y_forward = options.forward_axis == ForwardAxis::kY;
  const double heading_offset = y_forward ? -M_PI / 2 : 0.0;
  for (size_t i = 0; i < poses.size(); ++i) {
    const Pose& p = poses[i];
    out << "VERTEX_SE2 " << seconds(p.utime) << " A" << i << " " << number(p.x_m) << " " << number(p.y_m)
        << " " << number(p.heading_rad + heading_offset) << "\n";
  }
  for (const Beacon& b : dataset.beacons) {
    out << "VERTEX_XY L" << b.id << " " << number(b.x_m) << " " << number(b.y_m) << "\n";
  }
  for (const Beacon& b : dataset.beacons) {
    const bool known = std::isfinite(b.covariance[0]) && std::isfinite(b.covariance[1]) && std::isfinite(b.covariance[3]);
    if (!known) continue;
    out << "VERTEX_XY:PRIOR " << seconds(poses.front().utime) << " L" << b.id << " " << number(b.x_m) << " "
        << number(b.y_m) << " " << number(b.covariance[0]) << " " << number(b.covariance[1]) << " "
        << number(b.covariance[3]) << "\n";
  }
  for (size_t k = 0; k < dataset.odometry.size(); ++k) {
    const Odometry& o = dataset.odometry[k];
    double cov[9];
    if (o.hasCovariance()) {
      for (int i = 0; i < 9; ++i) cov[i] = o.covariance[i];
    } else {
      const double s = options.unknown_odometry_sigma_m, h = options.unknown_heading_sigma_rad;
      const double diag[9] = {s * s, 0, 0, 0, s * s, 0, 0, 0, h * h};
      for (int i = 0; i < 9; ++i) cov[i] = diag[i];
    }
    // File (dx, dy, dtheta) from roam's (forward, lateral, heading).
    double dx = o.forward_m, dy = o.lateral_m;
    int from[3] = {0, 1, 2};
    double sign[3] = {1.0, 1.0, 1.0};
    if (y_forward) {
      dx = -o.lateral_m;
      dy = o.forward_m;
      from[0] = 1;  // dx = -lateral
      from[1] = 0;  // dy = forward
      sign[0] = -1.0;
    }
    auto c = [&](int i, int j) { return sign[i] * sign[j] * cov[3 * from[i] + from[j]]; };
    out << "EDGE_SE2 0.000000 A" << k << " A" << k + 1 << " " << number(dx) << " " << number(dy) << " "
        << number(o.delta_heading_rad) << " " << number(c(0, 0)) << " " << number(c(0, 1)) << " "
        << number(c(0, 2)) << " " << number(c(1, 1)) << " " << number(c(1, 2)) << " " << number(c(2, 2)) << "\n";
  }
  for (const Range& r : dataset.ranges) {
    // The pose at or before the range's time.
    auto after = std::upper_bound(poses.begin(), poses.end(), r.utime,
                                  [](int64_t t, const Pose& p) { return t < p.utime; });
    const size_t index = after == poses.begin() ? 0 : static_cast<size_t>(after - poses.begin()) - 1;
    const double sigma = r.sigma_m > 0.0 ? r.sigma_m : options.unknown_range_sigma_m;
    if (r.has_bearing) {  // the beacon's position in the robot's frame, sigma in every direction
      const double forward = r.range_m * std::cos(r.bearing_rad), lateral = r.range_m * std::sin(r.bearing_rad);
      const double dx = y_forward ? -lateral : forward, dy = y_forward ? forward : lateral;
      out << "EDGE_SE2_XY 0.000000 A" << index << " L" << r.beacon_id << " " << number(dx) << " " << number(dy) << " "
          << number(sigma * sigma) << " 0 " << number(sigma * sigma) << "\n";
      continue;
    }
    out << "EDGE_RANGE 0.000000 A" << index << " L" << r.beacon_id << " " << number(r.range_m) << " "
        << number(sigma * sigma) << "\n";
  }
  out.flush();
  if (!out) throw std::runtime_error(path + ": write failed");
}

}  // namespace roam
