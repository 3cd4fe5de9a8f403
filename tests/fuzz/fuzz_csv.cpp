// Fuzz target: the CSV import of roam-import (utilities/dataset) on arbitrary bytes.
//
// The bytes are read as each kind of file alone (path, landmarks, odometry, ranges, and a
// path to derive odometry from); if they hold lines "===" they are also cut into a run folder
// (groundtruth.csv, landmarks.csv, odometry.csv, ranges.csv, in that order) for
// loadCsvDataset. Expected: a std::runtime_error naming the file and line, or data that keeps
// the promises of csv_dataset.hpp (finite numbers, times in order, ranges sorted, none between
// two listed beacons, whose notes are one line each). Anything else is a finding.
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "csv_dataset.hpp"
#include "csv_table.hpp"
#include "fuzz_util.hpp"

namespace {

using roam::fuzz::scratchDir;
using roam::fuzz::writeScratch;

void checkError(const std::runtime_error& error, const std::string& path) {
  const std::string message = error.what();
  ROAM_FUZZ_CHECK(message.rfind(path, 0) == 0, "an error that does not name the file: " + message);
  ROAM_FUZZ_CHECK(message.find('\n') == std::string::npos, "a multi-line error: " + message);
}

void checkPath(const roam::Path& path) {
  for (size_t k = 0; k < path.size(); ++k) {
    ROAM_FUZZ_CHECK(std::isfinite(path[k].x_m) && std::isfinite(path[k].y_m) &&
                        std::isfinite(path[k].heading_rad),
                    "a non-finite pose was imported");
    ROAM_FUZZ_CHECK(k == 0 || path[k].utime >= path[k - 1].utime, "path times go backwards");
  }
}

void checkOdometry(const std::vector<roam::Odometry>& odometry) {
  for (size_t k = 0; k < odometry.size(); ++k) {
    ROAM_FUZZ_CHECK(std::isfinite(odometry[k].forward_m) && std::isfinite(odometry[k].delta_heading_rad),
                    "non-finite odometry was imported");
    ROAM_FUZZ_CHECK(k == 0 || odometry[k].utime >= odometry[k - 1].utime, "odometry times go backwards");
  }
}

void checkRanges(const std::vector<roam::Range>& ranges, const std::vector<std::string>& notes) {
  for (size_t k = 0; k < ranges.size(); ++k) {
    ROAM_FUZZ_CHECK(std::isfinite(ranges[k].range_m), "a non-finite range was imported");
    ROAM_FUZZ_CHECK(k == 0 || ranges[k].utime >= ranges[k - 1].utime, "ranges are not sorted by time");
  }
  for (const std::string& note : notes) ROAM_FUZZ_CHECK(note.find('\n') == std::string::npos, "a note of several lines");
}

template <typename Body>
void expectDataOrError(const std::string& path, Body&& body) {
  try {
    body();
  } catch (const std::runtime_error& error) {
    checkError(error, path);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string file = writeScratch("table.csv", data, size);
  expectDataOrError(file, [&] {
    const roam::CsvTable table(file);
    for (size_t r = 0; r < table.rows(); ++r) ROAM_FUZZ_CHECK(table.line(static_cast<size_t>(r)) >= 2, "a data row on line 1");
  });
  expectDataOrError(file, [&] { checkPath(roam::loadPathCsv(file, 0.5)); });
  expectDataOrError(file, [&] { checkOdometry(roam::loadOdometryCsv(file)); });
  expectDataOrError(file, [&] { checkOdometry(roam::odometryFromPathCsv(file, roam::Pose{}, 0.25)); });
  roam::Map beacons;
  expectDataOrError(file, [&] { beacons = roam::loadLandmarksCsv(file); });
  if (beacons.empty()) {
    for (int id = 0; id < 8; ++id) beacons.push_back(roam::Beacon{id, 1.0 * id, -1.0 * id, {}});
  }
  expectDataOrError(file, [&] {
    std::vector<std::string> notes;
    const std::vector<roam::Range> ranges = roam::loadRangesCsv(file, beacons, &notes);
    checkRanges(ranges, notes);
  });

  // A whole run folder, when the bytes are cut into four files by "===" lines.
  const std::string text(reinterpret_cast<const char*>(data), size);
  const char* names[] = {"groundtruth.csv", "landmarks.csv", "odometry.csv", "ranges.csv"};
  std::vector<std::string> parts;
  size_t begin = 0;
  while (parts.size() < 3) {
    const auto cut = text.find("\n===\n", begin);
    if (cut == std::string::npos) break;
    parts.push_back(text.substr(begin, cut + 1 - begin));
    begin = cut + 5;
  }
  if (parts.size() < 3) return 0;
  parts.push_back(text.substr(begin));
  const auto dir = scratchDir() / "run";
  std::filesystem::create_directories(dir);
  for (size_t i = 0; i < 4; ++i) {
    writeScratch("run/" + std::string(names[i]), reinterpret_cast<const uint8_t*>(parts[i].data()), parts[i].size());
  }
  expectDataOrError(dir.string(), [&] {
    std::vector<std::string> notes;
    const roam::Dataset run = roam::loadCsvDataset(dir.string(), {}, &notes);
    ROAM_FUZZ_CHECK(!run.ground_truth.empty(), "a run without a start pose was imported");
    checkPath(run.ground_truth);
    checkOdometry(run.odometry);
    checkRanges(run.ranges, notes);
  });
  return 0;
}
