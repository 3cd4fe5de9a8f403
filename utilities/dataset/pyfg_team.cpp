// loadPyfgTeam: every robot of a pyfg file as a TeamDataset (see pyfg_team.hpp).
#include "pyfg_team.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "pyfg_parse.hpp"

namespace roam {
namespace {

using pyfg::Line;

// One robot as read: its poses and edges, its ranges to beacons and its sightings.
struct RawMember {
  pyfg::RawPoses raw;
  std::vector<pyfg::RawRange> ranges;
  std::vector<pyfg::RawSighting> sightings;
};

// EDGE_RANGE between two robots' poses (a: the first name on the line).
struct RawRobotRange {
  int letter_a, pose_a, letter_b, pose_b;
  pyfg::RawRange numbers;
};

}  // namespace

std::vector<char> pyfgRobotLetters(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open for reading");
  std::vector<char> letters;
  std::string text, type, time, name;
  while (std::getline(in, text)) {
    std::istringstream words(text);
    if (!(words >> type) || type != "VERTEX_SE2" || !(words >> time >> name)) continue;
    int letter = 0, index = 0;
    if (!pyfg::splitName(name, &letter, &index) || letter == 'L') continue;
    if (std::find(letters.begin(), letters.end(), static_cast<char>(letter)) == letters.end())
      letters.push_back(static_cast<char>(letter));
  }
  std::sort(letters.begin(), letters.end());
  return letters;
}

TeamImport loadPyfgTeam(const std::string& path, const PyfgImportOptions& options) {
  if (options.robot != 0) throw std::invalid_argument("loadPyfgTeam reads every robot: options.robot must be 0");
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open for reading");
  std::map<int, RawMember> members;  // robot letter -> its lines, in letter order
  std::map<int, Beacon> beacons;
  std::vector<RawRobotRange> robot_ranges;
  LineTally pose_priors, loop_closures, robot_edges;
  Line line;
  line.file = path;
  // A pose name's robot letter and index; the pose must have its VERTEX_SE2 already.
  auto pose = [&](const Line& l, const std::string& name, const char* role) {
    int letter = 0, index = 0;
    if (!pyfg::splitName(name, &letter, &index) || letter == 'L')
      l.fail(std::string(role) + " '" + name + "' is not a pose name (a robot letter and an index, e.g. A12)");
    const auto member = members.find(letter);
    if (member == members.end() || !member->second.raw.poses.count(index))
      l.fail(std::string(role) + " '" + name + "' has no VERTEX_SE2");
    return std::make_pair(letter, index);
  };
  auto beaconIndex = [&](const Line& l, const std::string& name) {
    int letter = 0, index = 0;
    if (!pyfg::splitName(name, &letter, &index) || letter != 'L') return -1;
    if (!beacons.count(index)) l.fail("beacon '" + name + "' has no VERTEX_XY");
    return index;
  };
  while (pyfg::nextFields(in, &line)) {
    const std::string& type = line.fields[0];
    if (type == "VERTEX_SE2") {
      line.expectFields(6, "time name x y theta");
      int letter = 0, index = 0;
      if (!pyfg::splitName(line.fields[2], &letter, &index) || letter == 'L')
        line.fail("VERTEX_SE2: '" + line.fields[2] + "' is not a pose name (e.g. A12)");
      pyfg::RawPoses& raw = members[letter].raw;
      if (raw.poses.count(index))
        line.fail("VERTEX_SE2: pose '" + line.fields[2] + "' given twice (first on line " + std::to_string(raw.line[index]) + ")");
      raw.poses[index] = pyfg::readPose(line, &raw.time[index]);
      raw.line[index] = line.number;
    } else if (type == "VERTEX_XY") {
      pyfg::readBeacon(line, &beacons);
    } else if (type == "VERTEX_XY:PRIOR") {
      pyfg::readBeaconPrior(line, &beacons);
    } else if (type == "EDGE_SE2") {
      line.expectFields(13, "time from to dx dy dtheta and 6 covariance values");
      const auto [from_letter, from] = pose(line, line.fields[2], "EDGE_SE2: from");
      const auto [to_letter, to] = pose(line, line.fields[3], "EDGE_SE2: to");
      if (from_letter != to_letter || to != from + 1) {  // between robots, or a loop closure
        line.checkNumbers(4, 13, 3);
        (from_letter != to_letter ? robot_edges : loop_closures).add(line.number);
        continue;
      }
      pyfg::RawEdge edge;
      edge.line = line.number;
      edge.from = from;
      edge.to = to;
      pyfg::readEdgeNumbers(line, &edge);
      members[from_letter].raw.edges.push_back(edge);
    } else if (type == "EDGE_RANGE") {
      line.expectFields(6, "time a b range variance");
      const int b1 = beaconIndex(line, line.fields[2]), b2 = beaconIndex(line, line.fields[3]);
      if (b1 >= 0 && b2 >= 0) line.fail("EDGE_RANGE between two beacons is not supported");
      pyfg::RawRange range;
      range.line = line.number;
      if (b1 >= 0 || b2 >= 0) {  // a robot's range to a beacon
        const auto [letter, index] = pose(line, b1 >= 0 ? line.fields[3] : line.fields[2], "EDGE_RANGE: pose");
        range.beacon = b1 >= 0 ? b1 : b2;
        range.pose = index;
        pyfg::readRangeNumbers(line, &range);
        members[letter].ranges.push_back(range);
        continue;
      }
      const auto [letter_a, pose_a] = pose(line, line.fields[2], "EDGE_RANGE: a");
      const auto [letter_b, pose_b] = pose(line, line.fields[3], "EDGE_RANGE: b");
      if (letter_a == letter_b) {
        line.fail("EDGE_RANGE " + line.fields[2] + " " + line.fields[3] +
                  ": a range between two poses of one robot is not supported");
      }
      pyfg::readRangeNumbers(line, &range);
      robot_ranges.push_back({letter_a, pose_a, letter_b, pose_b, range});
    } else if (type.find("SE3") != std::string::npos || type.find("XYZ") != std::string::npos) {
      line.fail(type + ": 3-D data is not supported (roam is 2-D)");
    } else if (type == "VERTEX_SE2:PRIOR") {
      line.expectFields(12, "time name x y theta and 6 covariance values");
      pose(line, line.fields[2], "VERTEX_SE2:PRIOR: pose");
      line.checkNumbers(3, 12, 3);
      pose_priors.add(line.number);
    } else if (type == "EDGE_SE2_XY") {
      line.expectFields(9, "time pose beacon dx dy and 3 covariance values");
      pyfg::RawSighting sighting;
      sighting.line = line.number;
      const auto [letter, index] = pose(line, line.fields[2], "EDGE_SE2_XY: pose");
      sighting.pose = index;
      sighting.beacon = beaconIndex(line, line.fields[3]);
      if (sighting.beacon < 0) line.fail("EDGE_SE2_XY: '" + line.fields[3] + "' is not a beacon name (e.g. L3)");
      pyfg::readSightingNumbers(line, &sighting);
      members[letter].sightings.push_back(sighting);
    } else {
      line.fail("unknown type '" + type + "'");
    }
  }
  if (members.empty()) throw std::runtime_error(path + ": no VERTEX_SE2 (a pyfg run needs poses)");

  // One time unit and one forward axis for the team, from every robot's times and edges.
  double latest = 0.0;
  std::vector<pyfg::RawEdge> all_edges;
  for (auto& [letter, member] : members) {
    pyfg::checkNumbering(path, letter, member.raw);
    for (const auto& [index, time] : member.raw.time) latest = std::max(latest, std::abs(time));
    all_edges.insert(all_edges.end(), member.raw.edges.begin(), member.raw.edges.end());
  }
  TeamImport result;
  result.time_unit_s = pyfg::resolveTimeUnit(path, options, latest);
  result.forward_axis = pyfg::resolveForwardAxis(options.forward_axis, all_edges);
  const std::string unit_note = pyfg::timeUnitNote(path, options, result.time_unit_s, latest);
  if (!unit_note.empty()) result.notes.push_back(unit_note);

  TeamDataset& team = result.team;
  std::map<int, int> robot_of;  // letter -> index in team.robots
  for (auto& [letter, member] : members) {
    pyfg::stampPoses(path, options, result.time_unit_s, &member.raw);
    const auto edge_into = pyfg::edgesInto(path, letter, member.raw);
    robot_of[letter] = static_cast<int>(team.robots.size());
    team.robots.push_back(std::string(1, static_cast<char>(letter)));
    team.members.push_back(pyfg::robotRun(member.raw, edge_into, member.ranges, member.sightings,
                                          result.forward_axis == ForwardAxis::kY, robot_of[letter]));
  }
  for (const auto& [index, beacon] : beacons) team.beacons.push_back(beacon);
  for (const RawRobotRange& r : robot_ranges) {
    Range range;
    range.utime = members.at(r.letter_a).raw.poses.at(r.pose_a).utime;
    range.range_m = r.numbers.range_m;
    range.sigma_m = std::sqrt(r.numbers.variance);
    range.robot = robot_of.at(r.letter_a);
    range.other_robot = robot_of.at(r.letter_b);
    team.robot_ranges.push_back(range);
  }
  std::stable_sort(team.robot_ranges.begin(), team.robot_ranges.end(),
                   [](const Range& a, const Range& b) { return a.utime < b.utime; });

  auto note = [&](const LineTally& set_aside, const std::string& what, const std::string& why) {
    if (std::string text = pyfg::setAsideNote(path, set_aside, what, why); !text.empty()) result.notes.push_back(text);
  };
  note(pose_priors, "pose prior(s) (VERTEX_SE2:PRIOR)",
       "each robot's first VERTEX_SE2 is its start pose, and roam's estimators take no absolute fix");
  note(loop_closures, "loop closure(s) (EDGE_SE2 between poses that are not consecutive)",
       "roam's estimators take odometry and ranges");
  note(robot_edges, "relative pose(s) between two robots (EDGE_SE2)",
       "roam's estimators take ranges between robots, not relative poses");
  if (options.pose_interval_s > 0.0) {
    char interval_s[32];
    std::snprintf(interval_s, sizeof interval_s, "%.6g", options.pose_interval_s);
    result.notes.push_back(path + ": each robot's pose i is at i x " + interval_s +
                           " s (--pose-interval-s); the file's pose times are set aside");
  }
  return result;
}

}  // namespace roam
