// pyfg (PyFactorGraph's text format, read by CORA and GTSAM's range-aided examples) in and out
// of a roam::Dataset. 2-D, one robot a run, range-aided SLAM:
//
//   VERTEX_SE2 t A<i> x y theta               reference pose i (ground truth; the first is the
//                                             start pose); its time t (s) is the step's time
//   VERTEX_XY L<j> x y                        beacon j at its surveyed position
//   VERTEX_XY:PRIOR t L<j> x y c11 c12 c22    that beacon's position covariance
//   EDGE_SE2 t A<i> A<i+1> dx dy dtheta c11 c12 c13 c22 c23 c33
//                                             odometry from pose i to i+1 in the frame of pose
//                                             i, with its covariance (upper triangle, row by row)
//   EDGE_RANGE t A<i> L<j> range variance     a range from pose i to beacon j, taken at pose i's
//                                             time; sigma = sqrt(variance)
//
// Edge time stamps are ignored (the published files carry 0): an odometry edge ends at the
// time of its second pose, a range is stamped with its pose's time. Ranges are sorted by time
// (stable: equal times keep file order).
//
// The body frame: roam's robot moves along +x. forward_axis = y maps a file whose body frame
// moves along +y (GOATS' vehicle): heading = theta + pi/2, and an edge (dx, dy) is forward dy,
// lateral -dx, its covariance rotated the same way. auto picks y when the median |dy| of the
// edges is more than twice their median |dx|. Positions and every dead-reckoned position are
// the same whichever is chosen; only headings and the forward/lateral split differ.
//
// What PyFactorGraph also writes for one robot and roam's estimators do not take is checked
// like the rest and set aside, each kind with a note naming its first line (PyfgImport::notes):
// pose priors (VERTEX_SE2:PRIOR, commonly one on the first pose), loop closures (EDGE_SE2
// between poses that are not consecutive) and pose-landmark measurements (EDGE_SE2_XY).
//
// Several robots (A, B, ... in one file): one is read, chosen by PyfgImportOptions::robot; the
// other robots' lines and the measurements between robots are set aside with a note.
//
// Refused with "<file>:<line>: ..." (never skipped): 3-D types, several robots without a robot
// chosen, ranges between two poses of the robot read, unknown types, bad numbers, unknown or
// repeated names, a pose without its odometry edge, and poses that all carry one time (unless
// PyfgImportOptions::pose_interval_s stamps them).
#pragma once

#include <string>
#include <vector>

#include "dataset.hpp"

namespace roam {

enum class ForwardAxis { kX, kY, kAuto };

struct PyfgImportOptions {
  ForwardAxis forward_axis = ForwardAxis::kAuto;
  // > 0: pose i (counted from the first) is at i x pose_interval_s seconds, whatever the file
  // says; for files that carry no pose times (every VERTEX_SE2 at one time, which is refused
  // without it).
  double pose_interval_s = 0.0;
  // Seconds per unit of the file's time stamps; 0: auto, the largest of 1, 1e-3, 1e-6, 1e-9 (s,
  // ms, us, ns) that puts the file's latest time within 1e11 s (3,000 years: a Unix time in
  // seconds fits, one in nanoseconds does not). A unit other than seconds is said in a note.
  double time_unit_s = 0.0;
  // 0: the file's one robot (a second robot is refused, naming this option). A letter: that
  // robot's poses, odometry and ranges are read, and every line of the other robots, and every
  // measurement between two robots, is set aside with a note (a multi-robot file, one robot a run).
  char robot = 0;
};

struct PyfgImport {
  Dataset dataset;
  double time_unit_s = 1.0;                    // the unit of the file's times (auto resolved)
  ForwardAxis forward_axis = ForwardAxis::kX;  // the axis used (auto resolved)
  int robot_letter = 'A';
  std::vector<std::string> notes;  // "<file>:<line>: set aside N ...: why", one per kind
};

// Throws std::runtime_error naming the file and line.
PyfgImport loadPyfgDataset(const std::string& path, const PyfgImportOptions& options = {});

// Writes `dataset` as pyfg: dataset.ground_truth as the VERTEX_SE2 poses (one per odometry step
// plus the start, at the odometry times), beacons as VERTEX_XY (with :PRIOR where their
// covariance is known), odometry as EDGE_SE2 and ranges as EDGE_RANGE (with a bearing: EDGE_SE2_XY) on the pose at or
// before their time. Odometry without a covariance gets `unknown_odometry_sigma` (forward and
// lateral, m) and `unknown_heading_sigma_rad`; ranges without a sigma `unknown_range_sigma_m`.
// Numbers are printed so that loadPyfgDataset reads back the same doubles.
struct PyfgWriteOptions {
  ForwardAxis forward_axis = ForwardAxis::kX;  // kY writes a +y-forward body frame
  double unknown_odometry_sigma_m = 0.1;
  double unknown_heading_sigma_rad = 0.01;
  double unknown_range_sigma_m = 1.0;
};
void writePyfg(const std::string& path, const Dataset& dataset, const PyfgWriteOptions& options = {});

}  // namespace roam
