// roam::loadCsvDataset — a run in the CSV layout of ../shared/data/plaza1 as a roam::Dataset.
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
// Without landmarks.csv BEACONS is empty. Each missing optional file is a note.
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

#include <string>
#include <vector>

#include "dataset.hpp"

namespace roam {

struct CsvImportOptions {
  double heading_offset_rad = 0.0;   // added to every ground-truth (and path) heading
  std::string odometry_from_path;    // "" = use DIR/odometry.csv
};

// Steps shorter than this (m) have no direction of travel (see above).
constexpr double kMinStepForDirection_m = 1e-9;

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
