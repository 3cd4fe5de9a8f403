#include "pyfg_dataset.hpp"

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
namespace {

struct Line {
  std::string file;
  long number = 0;
  std::vector<std::string> fields;

  [[noreturn]] void fail(const std::string& what) const {
    throw std::runtime_error(file + ":" + std::to_string(number) + ": " + printable(what));
  }
  // Bytes that are not printable ASCII as \xNN, so a binary line cannot garble a terminal.
  static std::string printable(const std::string& text) {
    std::string out;
    for (unsigned char c : text) {
      if (c >= 0x20 && c < 0x7f) {
        out += static_cast<char>(c);
      } else {
        char hex[5];
        std::snprintf(hex, sizeof hex, "\\x%02X", c);
        out += hex;
      }
    }
    return out;
  }
  void expectFields(size_t count, const char* layout) const {
    if (fields.size() != count) {
      fail(fields[0] + ": expected " + std::to_string(count - 1) + " fields (" + layout + "), got " +
           std::to_string(fields.size() - 1));
    }
  }
  double number_at(size_t i, const char* what) const {
    const std::string& text = fields[i];
    errno = 0;
    char* end = nullptr;
    const double value = std::strtod(text.c_str(), &end);
    if (end == text.c_str() || *end != '\0' || errno == ERANGE || !std::isfinite(value)) {
      fail(fields[0] + ": " + what + ": expected a number, got '" + text + "'");
    }
    return value;
  }
};

// "A12" -> ('A', 12); "L3" -> ('L', 3); false if not a letter followed by digits.
bool splitName(const std::string& name, int* letter, int* index) {
  if (name.size() < 2 || !std::isalpha(static_cast<unsigned char>(name[0]))) return false;
  for (size_t i = 1; i < name.size(); ++i) {
    if (!std::isdigit(static_cast<unsigned char>(name[i]))) return false;
  }
  if (name.size() > 10) return false;
  *letter = name[0];
  *index = std::atoi(name.c_str() + 1);
  return true;
}

int64_t secondsToUtime(double seconds) { return static_cast<int64_t>(std::llround(seconds * 1e6)); }

// The unit of the file's time stamps: `given` (seconds per unit) or, given 0, the largest of s,
// ms, us and ns that puts the latest time within 1e11 s.
double timeUnit(double given, double latest) {
  if (given > 0.0) return given;
  for (double unit : {1.0, 1e-3, 1e-6, 1e-9}) {
    if (std::abs(latest) * unit <= 1e11) return unit;
  }
  return 1e-9;
}

const char* unitName(double unit_s) {
  if (unit_s == 1.0) return "seconds";
  if (unit_s == 1e-3) return "milliseconds";
  if (unit_s == 1e-6) return "microseconds";
  if (unit_s == 1e-9) return "nanoseconds";
  return "the given unit";
}

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return values[values.size() / 2];
}

struct RawEdge {
  long line;
  int from, to;
  double dx, dy, dtheta;
  double cov[6];
};

struct RawRange {
  long line;
  int pose;
  int beacon;
  double range_m, variance;
};

// EDGE_SE2_XY: a beacon's position (dx, dy) in the robot's frame at a pose, and its covariance.
struct RawSighting {
  long line;
  int pose;
  int beacon;
  double dx, dy, c11, c12, c22;
};

}  // namespace

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
  std::map<int, Pose> poses;  // index -> reference pose (heading as in the file)
  std::map<int, long> pose_line;
  std::map<int, double> pose_time;  // index -> the file's time stamp, in the file's unit
  std::map<int, Beacon> beacons;
  std::vector<RawEdge> edges;
  std::vector<RawRange> ranges;
  std::vector<RawSighting> sightings;
  // What PyFactorGraph writes beside odometry and ranges, which roam's estimators do not take:
  // set aside and reported in PyfgImport::notes.
  LineTally pose_priors, loop_closures, other_robots, inter_robot;
  long ranges_to_robots = 0;  // of the robot read: ranges whose other end is another robot
  Line line;
  line.file = path;
  std::string text;
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
  // A set-aside line's numbers are checked like the rest.
  auto checkNumbers = [&](const Line& l, size_t first, size_t end, size_t measurements) {
    for (size_t i = first; i < end; ++i) l.number_at(i, i < first + measurements ? "measurement" : "covariance");
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
  while (std::getline(in, text)) {
    ++line.number;
    if (!text.empty() && text.back() == '\r') text.pop_back();
    std::istringstream words(text);
    line.fields.clear();
    for (std::string word; words >> word;) line.fields.push_back(word);
    if (line.fields.empty() || line.fields[0][0] == '#') continue;
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
      Pose pose;
      pose_time[index] = line.number_at(1, "time");
      pose.x_m = line.number_at(3, "x");
      pose.y_m = line.number_at(4, "y");
      pose.heading_rad = line.number_at(5, "theta");
      poses[index] = pose;
      pose_line[index] = line.number;
    } else if (type == "VERTEX_XY") {
      line.expectFields(4, "name x y");
      int letter = 0, index = 0;
      if (!splitName(line.fields[1], &letter, &index) || letter != 'L') line.fail("VERTEX_XY: '" + line.fields[1] + "' is not a beacon name (L and an index, e.g. L3)");
      if (beacons.count(index)) line.fail("VERTEX_XY: beacon '" + line.fields[1] + "' given twice");
      Beacon beacon;
      beacon.id = index;
      beacon.x_m = line.number_at(2, "x");
      beacon.y_m = line.number_at(3, "y");
      beacons[index] = beacon;
    } else if (type == "VERTEX_XY:PRIOR") {
      line.expectFields(8, "time name x y c11 c12 c22");
      int letter = 0, index = 0;
      if (!splitName(line.fields[2], &letter, &index) || letter != 'L' || !beacons.count(index))
        line.fail("VERTEX_XY:PRIOR: '" + line.fields[2] + "' is not a beacon given by an earlier VERTEX_XY");
      Beacon& beacon = beacons[index];
      const double c11 = line.number_at(5, "c11"), c12 = line.number_at(6, "c12"), c22 = line.number_at(7, "c22");
      if (!(c11 > 0.0 && c22 > 0.0 && c11 * c22 - c12 * c12 > 0.0)) line.fail("VERTEX_XY:PRIOR: covariance is not positive definite");
      beacon.covariance = {c11, c12, c12, c22};
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
      edge.dx = line.number_at(4, "dx");
      edge.dy = line.number_at(5, "dy");
      edge.dtheta = line.number_at(6, "dtheta");
      for (int i = 0; i < 6; ++i) edge.cov[i] = line.number_at(7 + i, "covariance");
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
      range.range_m = line.number_at(4, "range");
      range.variance = line.number_at(5, "variance");
      if (!(range.range_m > 0.0)) line.fail("EDGE_RANGE: range must be > 0, got '" + line.fields[4] + "'");
      if (range.variance < 0.0) line.fail("EDGE_RANGE: variance must be >= 0, got '" + line.fields[5] + "'");
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
      sighting.dx = line.number_at(4, "dx");
      sighting.dy = line.number_at(5, "dy");
      sighting.c11 = line.number_at(6, "covariance");
      sighting.c12 = line.number_at(7, "covariance");
      sighting.c22 = line.number_at(8, "covariance");
      if (!(std::hypot(sighting.dx, sighting.dy) > 0.0)) line.fail("EDGE_SE2_XY: the beacon is at the pose (dx = dy = 0): no range");
      if (sighting.c11 < 0.0 || sighting.c22 < 0.0 || sighting.c11 * sighting.c22 < sighting.c12 * sighting.c12)
        line.fail("EDGE_SE2_XY: covariance is not positive semi-definite");
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
  const int first = poses.begin()->first;
  int expected = first;
  for (const auto& [index, pose] : poses) {
    if (index != expected) {
      throw std::runtime_error(path + ":" + std::to_string(pose_line.at(index)) + ": pose " +
                               static_cast<char>(*robot) + std::to_string(index) + " follows " +
                               static_cast<char>(*robot) + std::to_string(expected - 1) +
                               ": poses must be numbered without gaps");
    }
    ++expected;
  }
  double latest = 0.0;
  for (const auto& [index, time] : pose_time) latest = std::max(latest, std::abs(time));
  const double unit_s = timeUnit(options.time_unit_s, latest);
  if (options.pose_interval_s <= 0.0 && latest * unit_s > 9e12) {
    char text[64];
    std::snprintf(text, sizeof text, "%.17g", latest);
    throw std::runtime_error(path + ": a pose time of " + text + " is beyond 9e12 s in " + unitName(unit_s) +
                             " (roam's clock counts microseconds in 64 bits); choose the unit with --time-unit s|ms|us|ns");
  }
  for (auto& [index, pose] : poses) pose.utime = secondsToUtime(pose_time.at(index) * unit_s);
  if (options.pose_interval_s > 0.0) {
    for (auto& [index, pose] : poses) pose.utime = secondsToUtime(options.pose_interval_s * (index - first));
  } else if (poses.size() > 1 && poses.begin()->second.utime == poses.rbegin()->second.utime) {
    char at_s[32];
    std::snprintf(at_s, sizeof at_s, "%.6g", 1e-6 * static_cast<double>(poses.begin()->second.utime));
    throw std::runtime_error(path + ": every VERTEX_SE2 is at time " + at_s +
                             " s: the file carries no pose times, and the estimators need them (rates, speeds, a "
                             "gyro's drift); give the time between poses with --pose-interval-s SECONDS");
  }
  std::map<int, const RawEdge*> edge_into;
  for (const RawEdge& edge : edges) {
    if (edge_into.count(edge.to)) {
      throw std::runtime_error(path + ":" + std::to_string(edge.line) + ": a second odometry edge into " +
                               static_cast<char>(*robot) + std::to_string(edge.to));
    }
    edge_into[edge.to] = &edge;
  }
  for (const auto& [index, pose] : poses) {
    if (index == first) continue;
    if (!edge_into.count(index)) {
      throw std::runtime_error(path + ":" + std::to_string(pose_line.at(index)) + ": pose " +
                               static_cast<char>(*robot) + std::to_string(index) + " has no EDGE_SE2 from " +
                               static_cast<char>(*robot) + std::to_string(index - 1));
    }
    if (pose.utime < poses.at(index - 1).utime) {
      throw std::runtime_error(path + ":" + std::to_string(pose_line.at(index)) + ": pose time goes backwards");
    }
  }

  PyfgImport result;
  result.robot_letter = *robot;
  result.time_unit_s = unit_s;
  if (unit_s != 1.0 && options.time_unit_s == 0.0 && options.pose_interval_s <= 0.0) {
    char text[64];
    std::snprintf(text, sizeof text, "%.17g", latest);
    result.notes.push_back(path + ": pose times read as " + unitName(unit_s) + " (the latest, " + text +
                           ", is beyond 1e11 s); --time-unit s|ms|us|ns chooses another unit");
  }
  auto note = [&](const LineTally& set_aside, const std::string& what, const std::string& why) {
    if (set_aside.count == 0) return;
    result.notes.push_back(path + ":" + std::to_string(set_aside.first_line) + ": set aside " +
                           std::to_string(set_aside.count) + " " + what + (set_aside.count > 1 ? " (the first here)" : "") +
                           ": " + why);
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
  ForwardAxis axis = options.forward_axis;
  if (axis == ForwardAxis::kAuto) {
    std::vector<double> abs_dx, abs_dy;
    for (const RawEdge& edge : edges) {
      abs_dx.push_back(std::abs(edge.dx));
      abs_dy.push_back(std::abs(edge.dy));
    }
    axis = median(abs_dy) > 2.0 * median(abs_dx) ? ForwardAxis::kY : ForwardAxis::kX;
  }
  result.forward_axis = axis;
  const bool y_forward = axis == ForwardAxis::kY;
  const double heading_offset = y_forward ? M_PI / 2 : 0.0;

  Dataset& d = result.dataset;
  for (const auto& [index, pose] : poses) {
    Pose p = pose;
    p.heading_rad = pose.heading_rad + heading_offset;
    d.ground_truth.push_back(p);
  }
  d.start = d.ground_truth.front();
  for (const auto& [index, pose] : poses) {
    if (index == first) continue;
    const RawEdge& e = *edge_into.at(index);
    Odometry o;
    o.utime = pose.utime;
    o.delta_heading_rad = e.dtheta;
    // File covariance over (dx, dy, dtheta), upper triangle row by row.
    const double c[3][3] = {{e.cov[0], e.cov[1], e.cov[2]}, {e.cov[1], e.cov[3], e.cov[4]}, {e.cov[2], e.cov[4], e.cov[5]}};
    // roam's (forward, lateral, heading) = P (dx, dy, dtheta).
    int from[3] = {0, 1, 2};
    double sign[3] = {1.0, 1.0, 1.0};
    if (y_forward) {
      from[0] = 1;  // forward = dy
      from[1] = 0;  // lateral = -dx
      sign[1] = -1.0;
    }
    const double raw[3] = {e.dx, e.dy, e.dtheta};
    o.forward_m = sign[0] * raw[from[0]];
    o.lateral_m = sign[1] * raw[from[1]];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) o.covariance[3 * i + j] = sign[i] * sign[j] * c[from[i]][from[j]];
    d.odometry.push_back(o);
  }
  for (const auto& [index, beacon] : beacons) d.beacons.push_back(beacon);
  for (const RawRange& r : ranges) {
    Range range;
    range.utime = poses.at(r.pose).utime;
    range.beacon_id = r.beacon;
    range.range_m = r.range_m;
    range.sigma_m = std::sqrt(r.variance);
    d.ranges.push_back(range);
  }
  // A sighting is a range with a bearing: range |d|, bearing atan2(lateral, forward) in roam's
  // body frame, range sigma the covariance along d (u' C u, u = d / |d|).
  for (const RawSighting& s : sightings) {
    const double forward = y_forward ? s.dy : s.dx, lateral = y_forward ? -s.dx : s.dy;
    Range range;
    range.utime = poses.at(s.pose).utime;
    range.beacon_id = s.beacon;
    range.range_m = std::hypot(s.dx, s.dy);
    const double ux = s.dx / range.range_m, uy = s.dy / range.range_m;
    range.sigma_m = std::sqrt(ux * ux * s.c11 + 2.0 * ux * uy * s.c12 + uy * uy * s.c22);
    range.has_bearing = true;
    range.bearing_rad = std::atan2(lateral, forward);
    d.ranges.push_back(range);
  }
  std::stable_sort(d.ranges.begin(), d.ranges.end(),
                   [](const Range& a, const Range& b) { return a.utime < b.utime; });
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
