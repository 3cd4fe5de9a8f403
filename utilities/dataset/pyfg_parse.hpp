// The pyfg readers' shared parts (pyfg_dataset.cpp reads one robot, pyfg_team.cpp a team): a
// line and its checked fields, names (A12, L3), the numbers of each line type, the time unit, the
// pose chain's checks, and the conversions of an edge and a sighting into roam's body frame.
// Internal to roam_dataset; every refusal is "<file>:<line>: ..." as pyfg_dataset.hpp lists.
#pragma once

#include <cstdint>
#include <map>
#include <istream>
#include <string>
#include <vector>

#include "pyfg_dataset.hpp"

namespace roam {
namespace pyfg {

struct Line {
  std::string file;
  long number = 0;
  std::vector<std::string> fields;

  [[noreturn]] void fail(const std::string& what) const;
  // Bytes that are not printable ASCII as \xNN, so a binary line cannot garble a terminal.
  static std::string printable(const std::string& text);
  void expectFields(size_t count, const char* layout) const;
  double number_at(size_t i, const char* what) const;
  // A set-aside line's numbers are checked like the rest: fields [first, end), the first
  // `measurements` of them named "measurement", the rest "covariance".
  void checkNumbers(size_t first, size_t end, size_t measurements) const;
};

// The next line of `in` that holds a measurement: its number counted (blank and '#' comment lines
// too) and its whitespace-separated fields (a CR before the LF dropped). False at the end.
bool nextFields(std::istream& in, Line* line);

// "<file>:<first line>: set aside N <what> (the first here): <why>", or "" where none was.
std::string setAsideNote(const std::string& file, const LineTally& set_aside, const std::string& what,
                         const std::string& why);

// "A12" -> ('A', 12); "L3" -> ('L', 3); false if not a letter followed by digits.
bool splitName(const std::string& name, int* letter, int* index);

int64_t secondsToUtime(double seconds);
const char* unitName(double unit_s);

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

// One robot's poses as read: index -> pose (heading as in the file, utime unset), its line and
// its time in the file's unit; and its odometry edges (consecutive poses only).
struct RawPoses {
  std::map<int, Pose> poses;
  std::map<int, long> line;
  std::map<int, double> time;
  std::vector<RawEdge> edges;
};

// VERTEX_SE2 t A<i> x y theta: the pose's numbers (time, x, y, theta in that order).
Pose readPose(const Line& line, double* time);
// VERTEX_XY L<j> x y: a new beacon into `beacons`.
void readBeacon(const Line& line, std::map<int, Beacon>* beacons);
// VERTEX_XY:PRIOR: the covariance of a beacon of `beacons`.
void readBeaconPrior(const Line& line, std::map<int, Beacon>* beacons);
// The measurement numbers of EDGE_SE2 (dx dy dtheta, 6 covariances), EDGE_RANGE (range > 0,
// variance >= 0) and EDGE_SE2_XY (dx dy, a PSD covariance, not at the pose).
void readEdgeNumbers(const Line& line, RawEdge* edge);
void readRangeNumbers(const Line& line, RawRange* range);
void readSightingNumbers(const Line& line, RawSighting* sighting);

// The unit of the file's times (options.time_unit_s, or auto from the latest |time|); refuses a
// latest time beyond roam's clock. The note for an auto unit other than seconds, or "".
double resolveTimeUnit(const std::string& path, const PyfgImportOptions& options, double latest);
std::string timeUnitNote(const std::string& path, const PyfgImportOptions& options, double unit_s, double latest);

// Refuses a gap in robot `letter`'s pose numbers.
void checkNumbering(const std::string& path, int letter, const RawPoses& raw);
// Sets each pose's utime (the file's time in unit_s, or options.pose_interval_s apart); refuses
// poses that all carry one time.
void stampPoses(const std::string& path, const PyfgImportOptions& options, double unit_s, RawPoses* raw);
// The edge into each pose but the first; refuses a second edge into a pose, a pose without one,
// and a pose time that goes backwards.
std::map<int, const RawEdge*> edgesInto(const std::string& path, int letter, const RawPoses& raw);

// options.forward_axis, or auto from the edges (y when median |dy| > 2 median |dx|).
ForwardAxis resolveForwardAxis(ForwardAxis given, const std::vector<RawEdge>& edges);

// The run of one robot in roam's body frame: ground truth (headings turned for +y forward),
// start, odometry from the edges, ranges (and sightings as range + bearing) in time order
// (stable); every item's `robot` = robot. Beacons are not filled.
Dataset robotRun(const RawPoses& raw, const std::map<int, const RawEdge*>& edge_into,
                 const std::vector<RawRange>& ranges, const std::vector<RawSighting>& sightings, bool y_forward,
                 int robot);

}  // namespace pyfg
}  // namespace roam
