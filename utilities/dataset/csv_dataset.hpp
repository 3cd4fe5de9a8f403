// roam::loadCsvDataset — a run in the CSV layout of data/plaza1 as a roam::Dataset.
//
// Files in DIR (columns found by header name, in any order; extra columns are ignored):
//   odometry.csv     time_s, delta_distance_m, delta_heading_rad   (end of each step)
//   ranges.csv       time_s, beacon_id, range_m [, sigma_m] [, bearing_rad] [, sender_id]
//   groundtruth.csv  time_s, x_m, y_m, heading_rad           (optional: a field run has none)
//   landmarks.csv    beacon_id, x_m, y_m                       (optional: no survey)
// Times become utime = llround(time_s * 1e6). Ranges are sorted by time (stable: equal times
// keep file order). The start pose is the first ground-truth row (utime = its time); without
// groundtruth.csv it is the origin, heading 0, one odometry step (the first two rows' interval)
// before the first step ends and no later than the first range (with --odometry-from-path: the
// path's first row, its heading 0 where the path has none), and GROUND_TRUTH is empty.
// Without landmarks.csv BEACONS is empty. Each missing optional file is a note. Where no heading
// offset is given, the ground truth's heading is checked against its direction of travel
// (measureHeadingOffset below): a steady offset of kHeadingOffsetApply_rad or more is taken out
// of every ground-truth heading, and a heading that is no steady offset from it is kept; each
// with a note.
//
// Ranges that a SLAM run can use but a surveyed map does not list are kept, with a note (the
// `notes` argument; roam-import prints them): ranges to a beacon id that landmarks.csv does not
// hold (from the start pose the estimators place it from its ranges). With a sender_id column
// (Plaza's TD: the radio that sent, and beacon_id the one that answered), the robot's radio is
// the most frequent sender (not a listed beacon, or the column is not read, with a note): a
// range to it is read as from it to its sender, and one between two other nodes is set aside,
// each with a note.
//
// Odometry from a path (CsvImportOptions::odometry_from_path, a CSV in the ground-truth
// layout; heading_rad optional): one odometry step k per path row k >= 1, stamped with row k's
// time. The data's own convention (README quirk 1; the move-then-turn dead reckoning
// x += d cos th; y += d sin th; th += dth) is that the heading at a row is the direction of
// travel of the step LEAVING it, and odometry k turns from step k's direction to step k+1's:
//   delta_distance_m  = |p_k - p_{k-1}|
//   delta_heading_rad = wrap(dir_{k+1} - dir_k)   (0 for the last step: nothing follows)
//   dir_k = atan2(p_k - p_{k-1}) for k >= 2; a step shorter than kMinStepForDirection_m has no
//           direction and carries dir_{k-1};
//   dir_1 = the path's heading_rad at row 0 (plus the heading offset) if the column exists,
//           else the start pose's heading (the known initial direction of travel).
// Integrated from the start pose this reproduces the path exactly when the start heading is
// the path's row-0 heading (Plaza 1: mean error vs GT 15.918 m, as the shipped path). Path row
// 0's time and position are not used; odometry k looks one row ahead (offline import).
//
// Errors: std::runtime_error naming file, line and column ("<file>:<line>: column 'x': ...").
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "dataset.hpp"

namespace roam {

struct CsvImportOptions {
  // Added to every ground-truth (and path) heading; none: measured from the ground truth
  // (measureHeadingOffset below, applied where it finds a steady offset).
  std::optional<double> heading_offset_rad;
  std::string odometry_from_path;    // "" = use DIR/odometry.csv
};

// Steps shorter than this (m) have no direction of travel (see above).
constexpr double kMinStepForDirection_m = 1e-9;

// The ground truth's heading against its own direction of travel. The layout's odometry moves
// along the heading (delta_distance_m forward), so the start pose's heading must be the direction
// of travel; a file whose heading column is offset from it (a compass mounted at an angle, another
// zero: Plaza 1's README says Plaza 2's is) would turn every start-pose estimate and dead
// reckoning by the offset. Over the steps of at least kHeadingCheckStep_m (a centimetre of
// position error turns such a step's direction by at most 0.1 rad), offset_rad is the median of
// wrap(heading - direction) about their circular mean, and steady_fraction the share within
// kHeadingCheckBand_rad of it. Plaza 1: 8,432 steps, median 0.017 rad, 99.7 % within the band.
constexpr double kHeadingCheckStep_m = 0.1;
constexpr double kHeadingCheckBand_rad = 0.35;   // 20 degrees: a skid or a GPS heading's scatter
constexpr int kHeadingCheckMinSteps = 50;        // fewer: nothing measured
constexpr double kHeadingOffsetApply_rad = 0.1;  // under this the heading is the direction of travel
constexpr double kHeadingSteadyFraction = 0.5;   // at least half the steps agree on one offset
struct HeadingOffsetCheck {
  int steps = 0;                 // steps measured (0: too few, nothing measured)
  double offset_rad = 0.0;       // heading - direction of travel
  double steady_fraction = 0.0;  // share of the steps within kHeadingCheckBand_rad of it
};
HeadingOffsetCheck measureHeadingOffset(const Path& ground_truth);

Dataset loadCsvDataset(const std::string& dir, const CsvImportOptions& options = {},
                       std::vector<std::string>* notes = nullptr);

// The pieces, for tools and tests that read one file alone.
Path loadPathCsv(const std::string& path, double heading_offset_rad = 0.0);
Map loadLandmarksCsv(const std::string& path);
std::vector<Odometry> loadOdometryCsv(const std::string& path);
std::vector<Odometry> odometryFromPathCsv(const std::string& path, const Pose& start,
                                          double heading_offset_rad = 0.0);
// Sorted by time (stable); `beacons` (landmarks.csv) decides the notes and sender_id above.
std::vector<Range> loadRangesCsv(const std::string& path, const Map& beacons, std::vector<std::string>* notes = nullptr);

}  // namespace roam
