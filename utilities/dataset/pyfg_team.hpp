// loadPyfgTeam: every robot of a pyfg file (PyFactorGraph writes robots A, B, ... in one file)
// as a roam::TeamDataset. Each robot is read as loadPyfgDataset reads one (pyfg_dataset.hpp):
// its VERTEX_SE2 are its ground truth (the first its start pose), its EDGE_SE2 its odometry, its
// EDGE_RANGE to beacons and its EDGE_SE2_XY sightings (range + bearing) its ranges. Besides:
//
//   EDGE_RANGE t A<i> B<j> range variance   a range between two robots: a Range in
//                                           team.robot_ranges with robot = A's index,
//                                           other_robot = B's, at A<i>'s time, sigma =
//                                           sqrt(variance); sorted by time (stable)
//
// Robots are named by their letters, in letter order ("A", "B", ...); each item's `robot` is its
// index. Landmarks (VERTEX_XY, with :PRIOR covariances) are team.beacons. One time unit and one
// forward axis for the whole team (auto: from every robot's times and edges); pose_interval_s
// stamps each robot's poses from its first. A file of one robot is a team of one.
//
// Set aside with a note each (TeamImport::notes): pose priors, loop closures and EDGE_SE2 between
// two robots. Refused with "<file>:<line>: ..." as the one-robot reader refuses, and a range
// between two poses of one robot.
#pragma once

#include <string>
#include <vector>

#include "dataset.hpp"
#include "pyfg_dataset.hpp"

namespace roam {

struct TeamImport {
  TeamDataset team;
  std::vector<std::string> notes;              // "<file>:<line>: set aside N ...: why", one per kind
  double time_unit_s = 1.0;                    // the unit of the file's times (auto resolved)
  ForwardAxis forward_axis = ForwardAxis::kX;  // the axis used (auto resolved)
};

// options.robot must be 0 (a team is every robot). Throws std::runtime_error naming file and line.
TeamImport loadPyfgTeam(const std::string& path, const PyfgImportOptions& options = {});

// The letters of the robots with a VERTEX_SE2 in the file, in letter order (a quick scan: only
// the VERTEX_SE2 lines' names are looked at). Throws std::runtime_error if it cannot be read.
std::vector<char> pyfgRobotLetters(const std::string& path);

}  // namespace roam
