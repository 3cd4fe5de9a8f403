// The pyfg readers' shared parts (see pyfg_parse.hpp).
#include "pyfg_parse.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <istream>
#include <sstream>
#include <stdexcept>

namespace roam {
namespace pyfg {
namespace {

// The unit of the file's time stamps: `given` (seconds per unit) or, given 0, the largest of s,
// ms, us and ns that puts the latest time within 1e11 s.
double timeUnit(double given, double latest) {
  if (given > 0.0) return given;
  for (double unit : {1.0, 1e-3, 1e-6, 1e-9}) {
    if (std::abs(latest) * unit <= 1e11) return unit;
  }
  return 1e-9;
}

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return values[values.size() / 2];
}

std::string exact(double value) {
  char text[64];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

}  // namespace

void Line::fail(const std::string& what) const {
  throw std::runtime_error(file + ":" + std::to_string(number) + ": " + printable(what));
}

std::string Line::printable(const std::string& text) {
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

void Line::expectFields(size_t count, const char* layout) const {
  if (fields.size() != count) {
    fail(fields[0] + ": expected " + std::to_string(count - 1) + " fields (" + layout + "), got " +
         std::to_string(fields.size() - 1));
  }
}

double Line::number_at(size_t i, const char* what) const {
  const std::string& text = fields[i];
  errno = 0;
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (end == text.c_str() || *end != '\0' || errno == ERANGE || !std::isfinite(value)) {
    fail(fields[0] + ": " + what + ": expected a number, got '" + text + "'");
  }
  return value;
}

void Line::checkNumbers(size_t first, size_t end, size_t measurements) const {
  for (size_t i = first; i < end; ++i) number_at(i, i < first + measurements ? "measurement" : "covariance");
}

std::string setAsideNote(const std::string& file, const LineTally& set_aside, const std::string& what,
                         const std::string& why) {
  if (set_aside.count == 0) return "";
  return file + ":" + std::to_string(set_aside.first_line) + ": set aside " + std::to_string(set_aside.count) + " " +
         what + (set_aside.count > 1 ? " (the first here)" : "") + ": " + why;
}

bool nextFields(std::istream& in, Line* line) {
  for (std::string text; std::getline(in, text);) {
    ++line->number;
    if (!text.empty() && text.back() == '\r') text.pop_back();
    std::istringstream words(text);
    line->fields.clear();
    for (std::string word; words >> word;) line->fields.push_back(word);
    if (!line->fields.empty() && line->fields[0][0] != '#') return true;
  }
  return false;
}

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

const char* unitName(double unit_s) {
  if (unit_s == 1.0) return "seconds";
  if (unit_s == 1e-3) return "milliseconds";
  if (unit_s == 1e-6) return "microseconds";
  if (unit_s == 1e-9) return "nanoseconds";
  return "the given unit";
}

Pose readPose(const Line& line, double* time) {
  Pose pose;
  *time = line.number_at(1, "time");
  pose.x_m = line.number_at(3, "x");
  pose.y_m = line.number_at(4, "y");
  pose.heading_rad = line.number_at(5, "theta");
  return pose;
}

void readBeacon(const Line& line, std::map<int, Beacon>* beacons) {
  line.expectFields(4, "name x y");
  int letter = 0, index = 0;
  if (!splitName(line.fields[1], &letter, &index) || letter != 'L') line.fail("VERTEX_XY: '" + line.fields[1] + "' is not a beacon name (L and an index, e.g. L3)");
  if (beacons->count(index)) line.fail("VERTEX_XY: beacon '" + line.fields[1] + "' given twice");
  Beacon beacon;
  beacon.id = index;
  beacon.x_m = line.number_at(2, "x");
  beacon.y_m = line.number_at(3, "y");
  (*beacons)[index] = beacon;
}

void readBeaconPrior(const Line& line, std::map<int, Beacon>* beacons) {
  line.expectFields(8, "time name x y c11 c12 c22");
  int letter = 0, index = 0;
  if (!splitName(line.fields[2], &letter, &index) || letter != 'L' || !beacons->count(index))
    line.fail("VERTEX_XY:PRIOR: '" + line.fields[2] + "' is not a beacon given by an earlier VERTEX_XY");
  Beacon& beacon = (*beacons)[index];
  const double c11 = line.number_at(5, "c11"), c12 = line.number_at(6, "c12"), c22 = line.number_at(7, "c22");
  if (!(c11 > 0.0 && c22 > 0.0 && c11 * c22 - c12 * c12 > 0.0)) line.fail("VERTEX_XY:PRIOR: covariance is not positive definite");
  beacon.covariance = {c11, c12, c12, c22};
}

void readEdgeNumbers(const Line& line, RawEdge* edge) {
  edge->dx = line.number_at(4, "dx");
  edge->dy = line.number_at(5, "dy");
  edge->dtheta = line.number_at(6, "dtheta");
  for (int i = 0; i < 6; ++i) edge->cov[i] = line.number_at(7 + i, "covariance");
}

void readRangeNumbers(const Line& line, RawRange* range) {
  range->range_m = line.number_at(4, "range");
  range->variance = line.number_at(5, "variance");
  if (!(range->range_m > 0.0)) line.fail("EDGE_RANGE: range must be > 0, got '" + line.fields[4] + "'");
  if (range->variance < 0.0) line.fail("EDGE_RANGE: variance must be >= 0, got '" + line.fields[5] + "'");
}

void readSightingNumbers(const Line& line, RawSighting* sighting) {
  sighting->dx = line.number_at(4, "dx");
  sighting->dy = line.number_at(5, "dy");
  sighting->c11 = line.number_at(6, "covariance");
  sighting->c12 = line.number_at(7, "covariance");
  sighting->c22 = line.number_at(8, "covariance");
  if (!(std::hypot(sighting->dx, sighting->dy) > 0.0)) line.fail("EDGE_SE2_XY: the beacon is at the pose (dx = dy = 0): no range");
  if (sighting->c11 < 0.0 || sighting->c22 < 0.0 || sighting->c11 * sighting->c22 < sighting->c12 * sighting->c12)
    line.fail("EDGE_SE2_XY: covariance is not positive semi-definite");
}

double resolveTimeUnit(const std::string& path, const PyfgImportOptions& options, double latest) {
  const double unit_s = timeUnit(options.time_unit_s, latest);
  if (options.pose_interval_s <= 0.0 && latest * unit_s > 9e12) {
    throw std::runtime_error(path + ": a pose time of " + exact(latest) + " is beyond 9e12 s in " + unitName(unit_s) +
                             " (roam's clock counts microseconds in 64 bits); choose the unit with --time-unit s|ms|us|ns");
  }
  return unit_s;
}

std::string timeUnitNote(const std::string& path, const PyfgImportOptions& options, double unit_s, double latest) {
  if (unit_s == 1.0 || options.time_unit_s != 0.0 || options.pose_interval_s > 0.0) return "";
  return path + ": pose times read as " + unitName(unit_s) + " (the latest, " + exact(latest) +
         ", is beyond 1e11 s); --time-unit s|ms|us|ns chooses another unit";
}

void checkNumbering(const std::string& path, int letter, const RawPoses& raw) {
  // Poses must be A<first>, A<first+1>, ...
  const char robot = static_cast<char>(letter);
  int expected = raw.poses.begin()->first;
  for (const auto& [index, pose] : raw.poses) {
    if (index != expected) {
      throw std::runtime_error(path + ":" + std::to_string(raw.line.at(index)) + ": pose " + robot +
                               std::to_string(index) + " follows " + robot + std::to_string(expected - 1) +
                               ": poses must be numbered without gaps");
    }
    ++expected;
  }
}

void stampPoses(const std::string& path, const PyfgImportOptions& options, double unit_s, RawPoses* raw) {
  auto& poses = raw->poses;
  const int first = poses.begin()->first;
  for (auto& [index, pose] : poses) pose.utime = secondsToUtime(raw->time.at(index) * unit_s);
  if (options.pose_interval_s > 0.0) {
    for (auto& [index, pose] : poses) pose.utime = secondsToUtime(options.pose_interval_s * (index - first));
  } else if (poses.size() > 1 && poses.begin()->second.utime == poses.rbegin()->second.utime) {
    char at_s[32];
    std::snprintf(at_s, sizeof at_s, "%.6g", 1e-6 * static_cast<double>(poses.begin()->second.utime));
    throw std::runtime_error(path + ": every VERTEX_SE2 is at time " + at_s +
                             " s: the file carries no pose times, and the estimators need them (rates, speeds, a "
                             "gyro's drift); give the time between poses with --pose-interval-s SECONDS");
  }
}

std::map<int, const RawEdge*> edgesInto(const std::string& path, int letter, const RawPoses& raw) {
  const char robot = static_cast<char>(letter);
  std::map<int, const RawEdge*> edge_into;
  for (const RawEdge& edge : raw.edges) {
    if (edge_into.count(edge.to)) {
      throw std::runtime_error(path + ":" + std::to_string(edge.line) + ": a second odometry edge into " + robot +
                               std::to_string(edge.to));
    }
    edge_into[edge.to] = &edge;
  }
  const int first = raw.poses.begin()->first;
  for (const auto& [index, pose] : raw.poses) {
    if (index == first) continue;
    if (!edge_into.count(index)) {
      throw std::runtime_error(path + ":" + std::to_string(raw.line.at(index)) + ": pose " + robot +
                               std::to_string(index) + " has no EDGE_SE2 from " + robot + std::to_string(index - 1));
    }
    if (pose.utime < raw.poses.at(index - 1).utime) {
      throw std::runtime_error(path + ":" + std::to_string(raw.line.at(index)) + ": pose time goes backwards");
    }
  }
  return edge_into;
}

ForwardAxis resolveForwardAxis(ForwardAxis given, const std::vector<RawEdge>& edges) {
  if (given != ForwardAxis::kAuto) return given;
  std::vector<double> abs_dx, abs_dy;
  for (const RawEdge& edge : edges) {
    abs_dx.push_back(std::abs(edge.dx));
    abs_dy.push_back(std::abs(edge.dy));
  }
  return median(abs_dy) > 2.0 * median(abs_dx) ? ForwardAxis::kY : ForwardAxis::kX;
}

Dataset robotRun(const RawPoses& raw, const std::map<int, const RawEdge*>& edge_into,
                 const std::vector<RawRange>& ranges, const std::vector<RawSighting>& sightings, bool y_forward,
                 int robot) {
  const double heading_offset = y_forward ? M_PI / 2 : 0.0;
  const int first = raw.poses.begin()->first;
  Dataset d;
  for (const auto& [index, pose] : raw.poses) {
    Pose p = pose;
    p.heading_rad = pose.heading_rad + heading_offset;
    p.robot = robot;
    d.ground_truth.push_back(p);
  }
  d.start = d.ground_truth.front();
  for (const auto& [index, pose] : raw.poses) {
    if (index == first) continue;
    const RawEdge& e = *edge_into.at(index);
    Odometry o;
    o.utime = pose.utime;
    o.robot = robot;
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
    const double values[3] = {e.dx, e.dy, e.dtheta};
    o.forward_m = sign[0] * values[from[0]];
    o.lateral_m = sign[1] * values[from[1]];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) o.covariance[3 * i + j] = sign[i] * sign[j] * c[from[i]][from[j]];
    d.odometry.push_back(o);
  }
  for (const RawRange& r : ranges) {
    Range range;
    range.utime = raw.poses.at(r.pose).utime;
    range.beacon_id = r.beacon;
    range.range_m = r.range_m;
    range.sigma_m = std::sqrt(r.variance);
    range.robot = robot;
    d.ranges.push_back(range);
  }
  // A sighting is a range with a bearing: range |d|, bearing atan2(lateral, forward) in roam's
  // body frame, range sigma the covariance along d (u' C u, u = d / |d|).
  for (const RawSighting& s : sightings) {
    const double forward = y_forward ? s.dy : s.dx, lateral = y_forward ? -s.dx : s.dy;
    Range range;
    range.utime = raw.poses.at(s.pose).utime;
    range.beacon_id = s.beacon;
    range.range_m = std::hypot(s.dx, s.dy);
    const double ux = s.dx / range.range_m, uy = s.dy / range.range_m;
    range.sigma_m = std::sqrt(ux * ux * s.c11 + 2.0 * ux * uy * s.c12 + uy * uy * s.c22);
    range.has_bearing = true;
    range.bearing_rad = std::atan2(lateral, forward);
    range.robot = robot;
    d.ranges.push_back(range);
  }
  std::stable_sort(d.ranges.begin(), d.ranges.end(),
                   [](const Range& a, const Range& b) { return a.utime < b.utime; });
  return d;
}

}  // namespace pyfg
}  // namespace roam
