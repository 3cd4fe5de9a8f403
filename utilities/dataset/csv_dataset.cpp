#include "csv_dataset.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>

#include "csv_table.hpp"

namespace roam {
namespace {

int64_t utimeFromSeconds(double time_s) { return std::llround(time_s * 1e6); }

std::string joinPath(const std::string& dir, const std::string& file) {
  if (dir.empty()) return file;
  return dir.back() == '/' ? dir + file : dir + "/" + file;
}

// Times must not go backwards in files that describe one motion in order.
void checkTimeOrder(const CsvTable& table, size_t row, size_t time_col, int64_t previous, int64_t current) {
  if (row > 0 && current < previous) {
    throw std::runtime_error(table.where(row, time_col) + "time goes backwards (" +
                             table.text(row, time_col) + " after " + table.text(row - 1, time_col) + ")");
  }
}

}  // namespace

Path loadPathCsv(const std::string& path, double heading_offset_rad) {
  const CsvTable table(path);
  const size_t t = table.column("time_s"), x = table.column("x_m"), y = table.column("y_m"),
               h = table.column("heading_rad");
  Path poses(table.rows());
  for (size_t r = 0; r < table.rows(); ++r) {
    poses[r].utime = utimeFromSeconds(table.number(r, t));
    poses[r].x_m = table.number(r, x);
    poses[r].y_m = table.number(r, y);
    poses[r].heading_rad = table.number(r, h) + heading_offset_rad;
    if (r > 0) checkTimeOrder(table, r, t, poses[r - 1].utime, poses[r].utime);
  }
  return poses;
}

Map loadLandmarksCsv(const std::string& path) {
  const CsvTable table(path);
  const size_t id = table.column("beacon_id"), x = table.column("x_m"), y = table.column("y_m");
  Map beacons(table.rows());
  std::set<int> seen;
  for (size_t r = 0; r < table.rows(); ++r) {
    beacons[r].id = table.integer(r, id);
    beacons[r].x_m = table.number(r, x);
    beacons[r].y_m = table.number(r, y);
    if (!seen.insert(beacons[r].id).second) {
      throw std::runtime_error(table.where(r, id) + "beacon " + std::to_string(beacons[r].id) +
                               " appears twice");
    }
  }
  return beacons;
}

std::vector<Odometry> loadOdometryCsv(const std::string& path) {
  const CsvTable table(path);
  const size_t t = table.column("time_s"), d = table.column("delta_distance_m"),
               h = table.column("delta_heading_rad");
  std::vector<Odometry> odometry(table.rows());
  for (size_t r = 0; r < table.rows(); ++r) {
    odometry[r].utime = utimeFromSeconds(table.number(r, t));
    odometry[r].forward_m = table.number(r, d);
    odometry[r].delta_heading_rad = table.number(r, h);
    if (r > 0) checkTimeOrder(table, r, t, odometry[r - 1].utime, odometry[r].utime);
  }
  return odometry;
}

namespace {

// The path's first row as a pose (heading 0 where the path has none): the start pose of a run
// without ground truth, and where odometryFromPath's first step begins.
Pose pathStart(const CsvTable& table, double heading_offset_rad) {
  if (table.rows() == 0) throw std::runtime_error(table.path() + ":2: no rows (expected a path)");
  Pose start;
  start.utime = utimeFromSeconds(table.number(0, table.column("time_s")));
  start.x_m = table.number(0, table.column("x_m"));
  start.y_m = table.number(0, table.column("y_m"));
  if (table.hasColumn("heading_rad")) start.heading_rad = table.number(0, table.column("heading_rad")) + heading_offset_rad;
  return start;
}

std::vector<Odometry> odometryFromPath(const CsvTable& table, const Pose& start, double heading_offset_rad) {
  const size_t t = table.column("time_s"), x = table.column("x_m"), y = table.column("y_m");
  const bool has_heading = table.hasColumn("heading_rad");
  const Pose first = pathStart(table, heading_offset_rad);

  // Steps 1..n (n = rows - 1): length and direction of travel.
  const size_t n = table.rows() - 1;
  std::vector<Odometry> odometry(n);
  std::vector<double> direction_rad(n);
  double prev_x = first.x_m, prev_y = first.y_m;
  int64_t prev_utime = first.utime;
  for (size_t k = 0; k < n; ++k) {
    const size_t r = k + 1;
    const int64_t utime = utimeFromSeconds(table.number(r, t));
    checkTimeOrder(table, r, t, prev_utime, utime);
    const double px = table.number(r, x), py = table.number(r, y);
    const double dx = px - prev_x, dy = py - prev_y;
    odometry[k].utime = utime;
    odometry[k].forward_m = std::hypot(dx, dy);
    if (k == 0) {
      direction_rad[k] = has_heading ? first.heading_rad : start.heading_rad;
    } else if (odometry[k].forward_m >= kMinStepForDirection_m) {
      direction_rad[k] = std::atan2(dy, dx);
    } else {
      direction_rad[k] = direction_rad[k - 1];  // no direction: carry the last one
    }
    prev_x = px;
    prev_y = py;
    prev_utime = utime;
  }
  for (size_t k = 0; k + 1 < n; ++k) {
    odometry[k].delta_heading_rad = wrapAngle(direction_rad[k + 1] - direction_rad[k]);
  }
  return odometry;
}

// A field run with neither ground truth nor a path: its start is one odometry step (the first two
// rows' interval) before the first step ends, and no later than the first range.
int64_t fieldRunStartUtime(const Dataset& dataset, const std::string& odometry_file) {
  if (dataset.odometry.empty() && dataset.ranges.empty()) {
    throw std::runtime_error(odometry_file + ":2: no rows, and no groundtruth.csv (nothing to start from)");
  }
  int64_t start_utime = std::numeric_limits<int64_t>::max();
  if (!dataset.odometry.empty()) {
    start_utime = dataset.odometry[0].utime;
    if (dataset.odometry.size() >= 2) start_utime -= dataset.odometry[1].utime - dataset.odometry[0].utime;
  }
  if (!dataset.ranges.empty()) start_utime = std::min(start_utime, dataset.ranges.front().utime);
  return start_utime;
}

// The offset to add to the ground truth's headings where none was given (--heading-offset auto):
// minus the measured one where the steps agree on it and it is at least kHeadingOffsetApply_rad,
// else 0; a note says what was measured where it is not the plain case.
double headingOffsetToApply(const std::string& gt_file, const HeadingOffsetCheck& check, std::vector<std::string>* notes) {
  if (check.steps == 0) return 0.0;
  const bool steady = check.steady_fraction >= kHeadingSteadyFraction;
  if (steady && std::abs(check.offset_rad) < kHeadingOffsetApply_rad) return 0.0;
  char text[512];
  if (!steady) {
    std::snprintf(text, sizeof text,
                  ": heading kept, but it is not the direction of travel: only %.0f %% of %d steps of %.1f m or more "
                  "agree within %.0f deg on one offset; the odometry moves along the start pose's heading, so "
                  "check the heading column's convention (--heading-offset RAD sets one)",
                  100.0 * check.steady_fraction, check.steps, kHeadingCheckStep_m, kHeadingCheckBand_rad * 180.0 / M_PI);
    if (notes) notes->push_back(gt_file + text);
    return 0.0;
  }
  std::snprintf(text, sizeof text,
                ": heading_rad is the direction of travel %+.4f rad (%+.1f deg; median of %d steps of %.1f m or more, "
                "%.0f %% within %.0f deg): %.4f rad added to every ground-truth heading, so the start pose faces the "
                "way the odometry moves (--heading-offset 0 keeps the file's headings)",
                check.offset_rad, check.offset_rad * 180.0 / M_PI, check.steps, kHeadingCheckStep_m,
                100.0 * check.steady_fraction, kHeadingCheckBand_rad * 180.0 / M_PI, -check.offset_rad);
  if (notes) notes->push_back(gt_file + text);
  return -check.offset_rad;
}

}  // namespace

HeadingOffsetCheck measureHeadingOffset(const Path& ground_truth) {
  std::vector<double> differences_rad;
  for (size_t k = 0; k + 1 < ground_truth.size(); ++k) {
    const double dx = ground_truth[k + 1].x_m - ground_truth[k].x_m, dy = ground_truth[k + 1].y_m - ground_truth[k].y_m;
    if (std::hypot(dx, dy) < kHeadingCheckStep_m) continue;
    differences_rad.push_back(wrapAngle(ground_truth[k].heading_rad - std::atan2(dy, dx)));
  }
  HeadingOffsetCheck check;
  if (static_cast<int>(differences_rad.size()) < kHeadingCheckMinSteps) return check;
  double sum_sin = 0.0, sum_cos = 0.0;
  for (double d : differences_rad) {
    sum_sin += std::sin(d);
    sum_cos += std::cos(d);
  }
  const double mean_rad = std::atan2(sum_sin, sum_cos);
  std::vector<double> about_mean(differences_rad.size());
  for (size_t i = 0; i < differences_rad.size(); ++i) about_mean[i] = wrapAngle(differences_rad[i] - mean_rad);
  std::vector<double> sorted = about_mean;
  const size_t middle = sorted.size() / 2;
  std::nth_element(sorted.begin(), sorted.begin() + middle, sorted.end());
  const double median_about_mean = sorted[middle];
  check.steps = static_cast<int>(differences_rad.size());
  check.offset_rad = wrapAngle(mean_rad + median_about_mean);
  const auto within = std::count_if(about_mean.begin(), about_mean.end(), [&](double d) {
    return std::abs(d - median_about_mean) <= kHeadingCheckBand_rad;
  });
  check.steady_fraction = static_cast<double>(within) / check.steps;
  return check;
}

std::vector<Odometry> odometryFromPathCsv(const std::string& path, const Pose& start, double heading_offset_rad) {
  return odometryFromPath(CsvTable(path), start, heading_offset_rad);
}

std::vector<Range> loadRangesCsv(const std::string& path, const Map& beacons, std::vector<std::string>* notes) {
  const CsvTable table(path);
  const size_t t = table.column("time_s"), id = table.column("beacon_id"), range = table.column("range_m");
  const bool has_sigma = table.hasColumn("sigma_m");
  const bool has_bearing = table.hasColumn("bearing_rad");
  const bool has_sender = table.hasColumn("sender_id");
  const size_t sigma = has_sigma ? table.column("sigma_m") : 0;
  const size_t bearing = has_bearing ? table.column("bearing_rad") : 0;
  const size_t sender = has_sender ? table.column("sender_id") : 0;
  std::set<int> known;
  for (const Beacon& b : beacons) known.insert(b.id);
  // sender_id: the robot's radio is the most frequent sender (Plaza 1: 2 on every row; ties: the
  // smallest). A range from it is to beacon_id, one to it is from the sender, and one between two
  // other nodes (beacons ranging each other) is set aside. A most frequent sender that is a
  // listed beacon cannot be the robot's radio: the column is not read.
  std::optional<int> robot_radio;
  std::string sender_note;
  if (has_sender && table.rows() > 0) {
    std::map<int, long> sent;
    for (size_t r = 0; r < table.rows(); ++r) ++sent[table.integer(r, sender)];
    const auto most = std::max_element(sent.begin(), sent.end(), [](const auto& a, const auto& b) { return a.second < b.second; });
    if (known.count(most->first)) {
      sender_note = path + ":1: sender_id not read: its most frequent value, " + std::to_string(most->first) +
                    ", is a beacon in landmarks.csv, not the robot's radio";
    } else {
      robot_radio = most->first;
    }
  }
  // Ranges kept to beacons landmarks.csv does not hold, read the other way round, and set aside.
  std::set<int> unlisted;
  LineTally unlisted_ranges, reversed, between_others;
  std::vector<Range> ranges;
  ranges.reserve(table.rows());
  for (size_t r = 0; r < table.rows(); ++r) {
    Range out;
    out.utime = utimeFromSeconds(table.number(r, t));
    out.beacon_id = table.integer(r, id);
    out.range_m = table.number(r, range);
    if (has_sigma) out.sigma_m = table.number(r, sigma);
    if (has_bearing) {
      out.has_bearing = true;
      out.bearing_rad = table.number(r, bearing);
    }
    if (robot_radio && table.integer(r, sender) != *robot_radio) {
      // Neither end is the robot's radio; or the range is to it but carries a bearing, which is
      // the robot's own measurement and cannot be turned round.
      if (out.beacon_id != *robot_radio || out.has_bearing) {
        between_others.add(table.line(r));
        continue;
      }
      reversed.add(table.line(r));
      out.beacon_id = table.integer(r, sender);
    }
    if (!known.count(out.beacon_id)) {
      unlisted_ranges.add(table.line(r));
      unlisted.insert(out.beacon_id);
    }
    ranges.push_back(out);
  }
  std::stable_sort(ranges.begin(), ranges.end(),
                   [](const Range& a, const Range& b) { return a.utime < b.utime; });
  if (notes) {
    auto lineOf = [&](const LineTally& tally) { return path + ":" + std::to_string(tally.first_line) + ": "; };
    if (unlisted_ranges.count > 0) {
      std::string ids;
      for (int unlisted_id : unlisted) ids += (ids.empty() ? "" : ", ") + std::to_string(unlisted_id);
      notes->push_back(lineOf(unlisted_ranges) + "kept " + std::to_string(unlisted_ranges.count) + " range(s) to beacon(s) " + ids +
                       ", which landmarks.csv does not hold: from the start pose the estimators place them from "
                       "their ranges, with surveyed beacons they count them as rejected or map them");
    }
    if (reversed.count > 0) {
      notes->push_back(lineOf(reversed) + "read " + std::to_string(reversed.count) + " range(s) to the robot's radio (" +
                       std::to_string(*robot_radio) + ", the most frequent sender_id) as ranges from it to their sender");
    }
    if (between_others.count > 0) {
      notes->push_back(lineOf(between_others) + "set aside " + std::to_string(between_others.count) +
                       " range(s) between two nodes neither of which is the robot's radio (" + std::to_string(*robot_radio) +
                       ", the most frequent sender_id): roam's estimators take ranges from the robot");
    }
    if (!sender_note.empty()) notes->push_back(sender_note);
  }
  return ranges;
}

Dataset loadCsvDataset(const std::string& dir, const CsvImportOptions& options, std::vector<std::string>* notes) {
  Dataset dataset;
  const std::string gt_file = joinPath(dir, "groundtruth.csv"), landmarks_file = joinPath(dir, "landmarks.csv"),
                    odometry_file = joinPath(dir, "odometry.csv");
  const bool has_ground_truth = std::filesystem::exists(gt_file);
  std::optional<CsvTable> path;  // --odometry-from-path, read once
  if (!options.odometry_from_path.empty()) path.emplace(options.odometry_from_path);
  double heading_offset_rad = options.heading_offset_rad.value_or(0.0);
  if (has_ground_truth) {
    dataset.ground_truth = loadPathCsv(gt_file, heading_offset_rad);
    if (dataset.ground_truth.empty()) {
      throw std::runtime_error(gt_file + ":2: no rows (the start pose is the first ground-truth row)");
    }
    if (!options.heading_offset_rad) {
      heading_offset_rad = headingOffsetToApply(gt_file, measureHeadingOffset(dataset.ground_truth), notes);
      if (heading_offset_rad != 0.0) {
        for (Pose& pose : dataset.ground_truth) pose.heading_rad += heading_offset_rad;
      }
    }
    dataset.start = dataset.ground_truth.front();
  } else if (path) {
    dataset.start = pathStart(*path, heading_offset_rad);
  }
  if (std::filesystem::exists(landmarks_file)) {
    dataset.beacons = loadLandmarksCsv(landmarks_file);
  } else if (notes) {
    notes->push_back(landmarks_file + ": none: no surveyed beacons (BEACONS is empty): the estimators place every "
                     "beacon from its ranges, from the start pose; anchor = beacons has no survey to hold "
                     "(spectral refuses it)");
  }
  dataset.odometry = path ? odometryFromPath(*path, dataset.start, heading_offset_rad)
                          : loadOdometryCsv(odometry_file);
  dataset.ranges = loadRangesCsv(joinPath(dir, "ranges.csv"), dataset.beacons, notes);
  if (!has_ground_truth) {
    // A field run: the frame is the start pose's own.
    if (!path) dataset.start.utime = fieldRunStartUtime(dataset, odometry_file);  // the origin, heading 0
    if (notes) {
      notes->push_back(gt_file + (path ? ": none: the start pose is the first row of " + options.odometry_from_path +
                                             " (--odometry-from-path); nothing for roam-eval to score"
                                       : std::string(": none: the start pose is the origin, heading 0 (the estimates "
                                                     "are in the start pose's frame), one odometry step before the "
                                                     "first ends; nothing for roam-eval to score")));
    }
  }
  return dataset;
}

}  // namespace roam
