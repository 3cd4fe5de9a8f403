// roam::loadCsvDataset: the CSV layout of data/plaza1, its errors, and the real data.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "csv_dataset.hpp"
#include "tool_test_util.hpp"

namespace {

constexpr double kTolerance = 1e-12;
const std::string kPlaza1 = std::string(ROAM_SOURCE_DIR) + "/data/plaza1";

// A small, valid run: columns in unusual orders, an extra column, CRLF line endings in one file.
void writeValidRun(const roam_test::ScratchDir& dir) {
  dir.write("groundtruth.csv", "heading_rad,time_s,y_m,x_m\n0.5,10.0,2.0,1.0\n0.6,10.2,2.1,1.1\n0.7,10.4,2.2,1.2\n");
  dir.write("odometry.csv", "time_s,delta_heading_rad,delta_distance_m,note\r\n10.2,0.1,0.15,a\r\n10.4,0.1,0.14,b\r\n");
  dir.write("landmarks.csv", "beacon_id,x_m,y_m\n0,5.0,6.0\n1,-5.0,7.5\n");
  // Out of time order; two rows at 10.3 s keep their file order (beacon 1 before beacon 0).
  dir.write("ranges.csv", "time_s,beacon_id,range_m\n10.3,1,8.5\n10.1,0,4.25\n10.3,0,4.5\n");
}

std::string loadError(const std::string& dir, const roam::CsvImportOptions& options = {}) {
  try {
    roam::loadCsvDataset(dir, options);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(CsvImport, ReadsColumnsByNameSortsRangesStably) {
  roam_test::ScratchDir dir;
  writeValidRun(dir);
  const roam::Dataset d = roam::loadCsvDataset(dir.path());
  ASSERT_EQ(d.ground_truth.size(), 3u);
  EXPECT_EQ(d.start.utime, 10000000);
  EXPECT_EQ(d.start.x_m, 1.0);
  EXPECT_EQ(d.start.y_m, 2.0);
  EXPECT_EQ(d.start.heading_rad, 0.5);
  ASSERT_EQ(d.odometry.size(), 2u);
  EXPECT_EQ(d.odometry[0].utime, 10200000);
  EXPECT_EQ(d.odometry[0].forward_m, 0.15);
  EXPECT_EQ(d.odometry[0].delta_heading_rad, 0.1);
  ASSERT_EQ(d.beacons.size(), 2u);
  EXPECT_EQ(d.beacons[1].id, 1);
  EXPECT_EQ(d.beacons[1].y_m, 7.5);
  ASSERT_EQ(d.ranges.size(), 3u);
  EXPECT_EQ(d.ranges[0].utime, 10100000);
  EXPECT_EQ(d.ranges[0].range_m, 4.25);
  EXPECT_EQ(d.ranges[1].beacon_id, 1);  // stable: file order at equal times
  EXPECT_EQ(d.ranges[2].beacon_id, 0);
  EXPECT_EQ(d.ranges[2].range_m, 4.5);
  EXPECT_FALSE(d.ranges[0].has_bearing);
}

TEST(CsvImport, HeadingOffsetIsAddedToGroundTruth) {
  roam_test::ScratchDir dir;
  writeValidRun(dir);
  roam::CsvImportOptions options;
  options.heading_offset_rad = M_PI;
  const roam::Dataset d = roam::loadCsvDataset(dir.path(), options);
  EXPECT_NEAR(d.start.heading_rad, 0.5 + M_PI, kTolerance);
  EXPECT_NEAR(d.ground_truth[2].heading_rad, 0.7 + M_PI, kTolerance);
}

TEST(CsvImport, MissingColumnNamesFileAndHeader) {
  roam_test::ScratchDir dir;
  writeValidRun(dir);
  dir.write("ranges.csv", "time_s,beacon_id,distance\n10.1,0,4.25\n");
  EXPECT_EQ(loadError(dir.path()),
            dir.file("ranges.csv") + ":1: missing column 'range_m' (header: time_s, beacon_id, distance)");
}

TEST(CsvImport, BadNumberNamesFileLineAndColumn) {
  roam_test::ScratchDir dir;
  writeValidRun(dir);
  dir.write("odometry.csv", "time_s,delta_distance_m,delta_heading_rad\n10.2,0.15,0.1\n10.4,0.1x4,0.1\n");
  EXPECT_EQ(loadError(dir.path()),
            dir.file("odometry.csv") + ":3: column 'delta_distance_m': expected a number, got '0.1x4'");
  dir.write("odometry.csv", "time_s,delta_distance_m,delta_heading_rad\n10.2,0.15,0.1\n10.4,,0.1\n");
  EXPECT_EQ(loadError(dir.path()),
            dir.file("odometry.csv") + ":3: column 'delta_distance_m': expected a number, got ''");
  writeValidRun(dir);
  dir.write("ranges.csv", "time_s,beacon_id,range_m\n10.1,zero,4.25\n");
  EXPECT_EQ(loadError(dir.path()),
            dir.file("ranges.csv") + ":2: column 'beacon_id': expected an integer, got 'zero'");
}

TEST(CsvImport, ShortRowNamesLine) {
  roam_test::ScratchDir dir;
  writeValidRun(dir);
  dir.write("landmarks.csv", "beacon_id,x_m,y_m\n0,5.0,6.0\n1,-5.0\n");
  EXPECT_EQ(loadError(dir.path()), dir.file("landmarks.csv") + ":3: expected 3 fields as in the header, got 2");
}

TEST(CsvImport, RangesToABeaconLandmarksDoesNotHoldAreKeptWithANote) {
  // From the start pose a beacon needs no survey: its ranges are the run's, and the import keeps
  // them (it used to refuse the whole run). The note names the ids, the count and the first line.
  roam_test::ScratchDir dir;
  writeValidRun(dir);
  dir.write("ranges.csv", "time_s,beacon_id,range_m\n10.1,0,4.25\n10.3,9,8.5\n10.35,7,3.0\n10.4,9,8.0\n");
  std::vector<std::string> notes;
  const roam::Dataset d = roam::loadCsvDataset(dir.path(), {}, &notes);
  ASSERT_EQ(d.ranges.size(), 4u);
  EXPECT_EQ(d.ranges[1].beacon_id, 9);
  EXPECT_EQ(d.ranges[1].range_m, 8.5);
  EXPECT_EQ(d.ranges[2].beacon_id, 7);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_EQ(notes[0], dir.file("ranges.csv") + ":3: kept 3 range(s) to beacon(s) 7, 9, which landmarks.csv does not "
                                               "hold: from the start pose the estimators place them from their "
                                               "ranges, with surveyed beacons they count them as rejected or map them");
  // Listed beacons only: no note.
  writeValidRun(dir);
  notes.clear();
  roam::loadCsvDataset(dir.path(), {}, &notes);
  EXPECT_TRUE(notes.empty());
}

TEST(CsvImport, SenderIdTellsRangesBetweenBeaconsAndReversedOnes) {
  // Plaza's TD: sender_id is the radio that sent (the robot's, 2 on every row of Plaza 1),
  // beacon_id the one that answered. The robot's radio is the most frequent sender (here 2, three
  // of six rows): a range to it is from it to its sender; beacons ranging each other (0 -> 1, and
  // 1 -> the unlisted 9) are set aside.
  roam_test::ScratchDir dir;
  writeValidRun(dir);
  dir.write("ranges.csv",
            "time_s,beacon_id,range_m,sender_id\n10.1,0,4.25,2\n10.2,1,7.0,0\n10.3,2,8.5,1\n10.35,9,3.3,2\n"
            "10.4,0,4.5,2\n10.45,9,2.0,1\n");
  std::vector<std::string> notes;
  const roam::Dataset d = roam::loadCsvDataset(dir.path(), {}, &notes);
  ASSERT_EQ(d.ranges.size(), 4u);
  EXPECT_EQ(d.ranges[0].beacon_id, 0);
  EXPECT_EQ(d.ranges[1].beacon_id, 1);  // sent by beacon 1 to the robot's radio: a range to beacon 1
  EXPECT_EQ(d.ranges[1].range_m, 8.5);
  EXPECT_EQ(d.ranges[1].utime, 10300000);
  EXPECT_EQ(d.ranges[2].beacon_id, 9);  // from the robot to an unlisted beacon: kept
  EXPECT_EQ(d.ranges[3].range_m, 4.5);
  const std::string file = dir.file("ranges.csv");
  ASSERT_EQ(notes.size(), 3u);
  EXPECT_EQ(notes[0].rfind(file + ":5: kept 1 range(s) to beacon(s) 9, which landmarks.csv does not hold", 0), 0u) << notes[0];
  EXPECT_EQ(notes[1], file + ":4: read 1 range(s) to the robot's radio (2, the most frequent sender_id) as ranges from "
                             "it to their sender");
  EXPECT_EQ(notes[2], file + ":3: set aside 2 range(s) between two nodes neither of which is the robot's radio (2, the "
                             "most frequent sender_id): roam's estimators take ranges from the robot");
  const auto result = roam_test::runTool(roam_test::tool("roam-import") + " " + dir.path() + " -o " + dir.file("r.lcmlog"));
  EXPECT_EQ(result.status, 0) << result.out;
  EXPECT_NE(result.out.find("(2 odometry, 4 ranges, 3 ground truth, 2 beacons)"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("roam-import: note: " + notes[2] + "\n"), std::string::npos) << result.out;

  // A most frequent sender that is a listed beacon is not the robot's radio: the column is not
  // read, and every row is a range to its beacon_id.
  dir.write("ranges.csv", "time_s,beacon_id,range_m,sender_id\n10.1,0,4.25,1\n10.2,1,7.0,1\n10.3,0,8.5,2\n");
  notes.clear();
  const roam::Dataset unread = roam::loadCsvDataset(dir.path(), {}, &notes);
  ASSERT_EQ(unread.ranges.size(), 3u);
  EXPECT_EQ(unread.ranges[1].beacon_id, 1);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_EQ(notes[0], file + ":1: sender_id not read: its most frequent value, 1, is a beacon in landmarks.csv, not the "
                             "robot's radio");
}

TEST(CsvImport, MissingFileIsNamed) {
  roam_test::ScratchDir dir;
  writeValidRun(dir);
  std::remove(dir.file("ranges.csv").c_str());
  EXPECT_EQ(loadError(dir.path()), dir.file("ranges.csv") + ": cannot open (No such file or directory)");
  writeValidRun(dir);
  std::remove(dir.file("odometry.csv").c_str());
  EXPECT_EQ(loadError(dir.path()), dir.file("odometry.csv") + ": cannot open (No such file or directory)");
}

TEST(CsvImport, AFieldRunWithoutGroundTruthOrSurveyStartsAtTheOriginWithNotes) {
  // A robot's own run has odometry and ranges only: it starts at the origin, heading 0, one
  // odometry step (10.2 -> 10.4 s: 0.2 s) before the first step ends (10.0 s, before the first
  // range at 10.1 s), with no ground truth and no beacons, and each missing file is a note.
  roam_test::ScratchDir dir;
  writeValidRun(dir);
  const roam::Dataset full = roam::loadCsvDataset(dir.path());
  std::remove(dir.file("groundtruth.csv").c_str());
  std::remove(dir.file("landmarks.csv").c_str());
  std::vector<std::string> notes;
  const roam::Dataset d = roam::loadCsvDataset(dir.path(), {}, &notes);
  EXPECT_TRUE(d.ground_truth.empty());
  EXPECT_TRUE(d.beacons.empty());
  EXPECT_EQ(d.start.utime, 10000000);
  EXPECT_EQ(d.start.x_m, 0.0);
  EXPECT_EQ(d.start.y_m, 0.0);
  EXPECT_EQ(d.start.heading_rad, 0.0);
  ASSERT_EQ(d.odometry.size(), full.odometry.size());
  for (size_t k = 0; k < d.odometry.size(); ++k) {
    EXPECT_EQ(d.odometry[k].utime, full.odometry[k].utime);
    EXPECT_EQ(d.odometry[k].forward_m, full.odometry[k].forward_m);
    EXPECT_EQ(d.odometry[k].delta_heading_rad, full.odometry[k].delta_heading_rad);
  }
  ASSERT_EQ(d.ranges.size(), full.ranges.size());
  // roam-import says so, and the run lasts from that start to its last event (10.4 s).
  const auto result = roam_test::runTool(roam_test::tool("roam-import") + " " + dir.path() + " -o " + dir.file("r.lcmlog"));
  EXPECT_EQ(result.status, 0) << result.out;
  EXPECT_NE(result.out.find("(2 odometry, 3 ranges, 0 ground truth, 0 beacons), 0.400 s from utime 10000000\n"),
            std::string::npos) << result.out;
  ASSERT_EQ(notes.size(), 3u);
  EXPECT_EQ(notes[0], dir.file("landmarks.csv") + ": none: no surveyed beacons (BEACONS is empty): the estimators "
                      "place every beacon from its ranges, from the start pose; anchor = beacons has no survey to "
                      "hold (spectral refuses it)");
  EXPECT_EQ(notes[1].rfind(dir.file("ranges.csv") + ":2: kept 3 range(s) to beacon(s) 0, 1, which landmarks.csv", 0), 0u)
      << notes[1];
  EXPECT_EQ(notes[2], dir.file("groundtruth.csv") + ": none: the start pose is the origin, heading 0 (the estimates "
                      "are in the start pose's frame), one odometry step before the first ends; nothing for "
                      "roam-eval to score");
  // A first range earlier than that: the start moves back to it.
  dir.write("ranges.csv", "time_s,beacon_id,range_m\n9.5,1,8.5\n10.1,0,4.25\n");
  EXPECT_EQ(roam::loadCsvDataset(dir.path()).start.utime, 9500000);
  // Odometry derived from a dead-reckoned path: the path's first row is the start pose.
  dir.write("path.csv", "time_s,x_m,y_m,heading_rad\n9.8,3.0,4.0,0.25\n10.2,3.3,4.4,0.5\n");
  roam::CsvImportOptions options;
  options.odometry_from_path = dir.file("path.csv");
  notes.clear();
  const roam::Dataset from_path = roam::loadCsvDataset(dir.path(), options, &notes);
  EXPECT_EQ(from_path.start.utime, 9800000);
  EXPECT_EQ(from_path.start.x_m, 3.0);
  EXPECT_EQ(from_path.start.y_m, 4.0);
  EXPECT_EQ(from_path.start.heading_rad, 0.25);
  ASSERT_EQ(from_path.odometry.size(), 1u);
  EXPECT_NEAR(from_path.odometry[0].forward_m, 0.5, kTolerance);
  ASSERT_FALSE(notes.empty());
  EXPECT_EQ(notes.back(), dir.file("groundtruth.csv") + ": none: the start pose is the first row of " +
                              dir.file("path.csv") + " (--odometry-from-path); nothing for roam-eval to score");
}

TEST(CsvImport, OdometryFromPath) {
  roam_test::ScratchDir dir;
  writeValidRun(dir);
  // Steps: (3,4) east-north-east, a zero step, then (0,2) north, then (-1,0) west.
  dir.write("path.csv",
            "time_s,x_m,y_m,heading_rad\n"
            "9.9,0,0,0.25\n"
            "10.2,3,4,9\n"
            "10.4,3,4,9\n"
            "10.6,3,6,9\n"
            "10.8,2,6,9\n");
  roam::CsvImportOptions options;
  options.odometry_from_path = dir.file("path.csv");
  const roam::Dataset d = roam::loadCsvDataset(dir.path(), options);
  ASSERT_EQ(d.odometry.size(), 4u);
  // Directions of travel: step 1 = heading column at row 0 = 0.25; step 2 has length 0 and
  // keeps 0.25; step 3 = atan2(2, 0) = pi/2; step 4 = atan2(0, -1) = pi.
  // delta_heading of step k = dir(k+1) - dir(k): 0, pi/2 - 0.25, pi/2, 0 (last step).
  EXPECT_EQ(d.odometry[0].utime, 10200000);
  EXPECT_NEAR(d.odometry[0].forward_m, 5.0, kTolerance);
  EXPECT_NEAR(d.odometry[0].delta_heading_rad, 0.0, kTolerance);
  EXPECT_NEAR(d.odometry[1].forward_m, 0.0, kTolerance);
  EXPECT_NEAR(d.odometry[1].delta_heading_rad, M_PI / 2 - 0.25, kTolerance);
  EXPECT_NEAR(d.odometry[2].forward_m, 2.0, kTolerance);
  EXPECT_NEAR(d.odometry[2].delta_heading_rad, M_PI / 2, kTolerance);
  EXPECT_EQ(d.odometry[3].utime, 10800000);
  EXPECT_NEAR(d.odometry[3].forward_m, 1.0, kTolerance);
  EXPECT_NEAR(d.odometry[3].delta_heading_rad, 0.0, kTolerance);
}

TEST(CsvImport, OdometryFromPathWithoutHeadingStartsAlongTheStartPose) {
  roam_test::ScratchDir dir;
  writeValidRun(dir);  // start heading 0.5
  dir.write("path.csv", "time_s,x_m,y_m\n10.0,0,0\n10.2,1,0\n10.4,1,1\n");
  roam::CsvImportOptions options;
  options.odometry_from_path = dir.file("path.csv");
  const roam::Dataset d = roam::loadCsvDataset(dir.path(), options);
  ASSERT_EQ(d.odometry.size(), 2u);
  // dir(1) = start heading 0.5, dir(2) = atan2(1, 0) = pi/2.
  EXPECT_NEAR(d.odometry[0].delta_heading_rad, M_PI / 2 - 0.5, kTolerance);
  EXPECT_NEAR(d.odometry[1].delta_heading_rad, 0.0, kTolerance);
}

// A 100 m run along a sine (0.5 m steps) whose heading column is `heading(k, direction of travel
// of the step leaving row k)`: what --heading-offset auto measures.
template <typename Heading>
void writeRunWithHeadings(const roam_test::ScratchDir& dir, Heading heading) {
  std::string gt = "time_s,x_m,y_m,heading_rad\n";
  const int rows = 201;
  auto x = [](int k) { return 0.5 * k; };
  auto y = [](int k) { return 5.0 * std::sin(0.5 * k / 8.0); };
  for (int k = 0; k < rows; ++k) {
    const int from = std::min(k, rows - 2);  // the last row keeps the last step's direction
    const double travel = std::atan2(y(from + 1) - y(from), x(from + 1) - x(from));
    char row[128];
    std::snprintf(row, sizeof row, "%.17g,%.17g,%.17g,%.17g\n", 10.0 + 0.5 * k, x(k), y(k), heading(k, travel));
    gt += row;
  }
  dir.write("groundtruth.csv", gt);
  dir.write("odometry.csv", "time_s,delta_distance_m,delta_heading_rad\n10.5,0.5,0.0\n11.0,0.5,0.0\n");
  dir.write("landmarks.csv", "beacon_id,x_m,y_m\n0,5.0,6.0\n");
  dir.write("ranges.csv", "time_s,beacon_id,range_m\n10.1,0,7.0\n");
}

double travelAtStart() { return std::atan2(5.0 * std::sin(0.5 / 8.0), 0.5); }

TEST(CsvImport, AGroundTruthHeadingOffsetFromTheDirectionOfTravelIsMeasuredAndTakenOut) {
  roam_test::ScratchDir dir;
  writeRunWithHeadings(dir, [](int, double travel) { return travel + 1.0; });
  std::vector<std::string> notes;
  const roam::Dataset d = roam::loadCsvDataset(dir.path(), {}, &notes);
  EXPECT_NEAR(d.start.heading_rad, travelAtStart(), 1e-9);
  EXPECT_NEAR(d.ground_truth[100].heading_rad - d.ground_truth[0].heading_rad,
              std::atan2(5.0 * (std::sin(50.5 / 8.0) - std::sin(50.0 / 8.0)), 0.5) - travelAtStart(), 1e-9);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_EQ(notes[0], dir.file("groundtruth.csv") + ": heading_rad is the direction of travel +1.0000 rad (+57.3 deg; "
                      "median of 200 steps of 0.1 m or more, 100 % within 20 deg): -1.0000 rad added to every "
                      "ground-truth heading, so the start pose faces the way the odometry moves (--heading-offset 0 "
                      "keeps the file's headings)");

  // A given offset is used as given, and nothing is measured.
  roam::CsvImportOptions keep;
  keep.heading_offset_rad = 0.0;
  notes.clear();
  EXPECT_NEAR(roam::loadCsvDataset(dir.path(), keep, &notes).start.heading_rad, travelAtStart() + 1.0, 1e-15);
  EXPECT_TRUE(notes.empty());

  const auto result = roam_test::runTool(roam_test::tool("roam-import") + " " + dir.path() + " -o " + dir.file("r.lcmlog"));
  EXPECT_EQ(result.status, 0) << result.out;
  EXPECT_NE(result.out.find("roam-import: note: " + dir.file("groundtruth.csv") + ": heading_rad is the direction of travel +1.0000 rad"),
            std::string::npos) << result.out;
  const auto kept = roam_test::runTool(roam_test::tool("roam-import") + " " + dir.path() + " -o " + dir.file("r.lcmlog") +
                                       " --heading-offset 0");
  EXPECT_EQ(kept.status, 0) << kept.out;
  EXPECT_EQ(kept.out.find("note"), std::string::npos) << kept.out;
  const auto bad = roam_test::runTool(roam_test::tool("roam-import") + " " + dir.path() + " -o " + dir.file("r.lcmlog") +
                                      " --heading-offset east");
  EXPECT_EQ(bad.status, 2);
  EXPECT_EQ(bad.out, "roam-import: error: --heading-offset: expected radians or auto, got 'east'\n");
}

TEST(CsvImport, AHeadingNearOrFarFromAnySteadyOffsetIsKept) {
  roam_test::ScratchDir dir;
  // 0.05 rad off the direction of travel: within what a navigation solution's heading scatters
  // by (Plaza 1: 0.017 rad); kept as it is, without a note.
  writeRunWithHeadings(dir, [](int, double travel) { return travel + 0.05; });
  std::vector<std::string> notes;
  EXPECT_EQ(roam::loadCsvDataset(dir.path(), {}, &notes).start.heading_rad, travelAtStart() + 0.05);
  EXPECT_TRUE(notes.empty());
  // A heading that no offset turns into the direction of travel (seven directions in turn): kept,
  // with a note naming the key.
  writeRunWithHeadings(dir, [](int k, double travel) { return travel + 2.0 * M_PI * (k % 7) / 7.0; });
  const roam::Dataset d = roam::loadCsvDataset(dir.path(), {}, &notes);
  EXPECT_EQ(d.start.heading_rad, travelAtStart());
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_EQ(notes[0].rfind(dir.file("groundtruth.csv") + ": heading kept, but it is not the direction of travel: only 14 % "
                           "of 200 steps of 0.1 m or more agree within 20 deg on one offset", 0), 0u) << notes[0];
  EXPECT_NE(notes[0].find("--heading-offset RAD"), std::string::npos) << notes[0];
}

// Plaza 1 with its ground-truth headings turned by 1.2 rad, as a run whose heading column has
// another zero (Plaza 1's README: Plaza 2's is offset): imported facing the way it moves, within
// Plaza 1's own scatter (median 0.017 rad) of its own start heading.
TEST(CsvImport, Plaza1WithItsHeadingsTurnedStartsFacingTheWayItMoves) {
  ROAM_REQUIRE_DATA(kPlaza1);
  roam_test::ScratchDir dir;
  for (const char* name : {"odometry.csv", "ranges.csv", "landmarks.csv"}) {
    std::filesystem::copy_file(kPlaza1 + "/" + name, dir.file(name));
  }
  const roam::Path truth = roam::loadPathCsv(kPlaza1 + "/groundtruth.csv");
  std::string gt = "time_s,x_m,y_m,heading_rad\n";
  for (const roam::Pose& p : truth) {
    char row[160];
    std::snprintf(row, sizeof row, "%.17g,%.17g,%.17g,%.17g\n", p.utime * 1e-6, p.x_m, p.y_m, p.heading_rad + 1.2);
    gt += row;
  }
  dir.write("groundtruth.csv", gt);
  std::vector<std::string> notes;
  const roam::Dataset d = roam::loadCsvDataset(dir.path(), {}, &notes);
  EXPECT_NEAR(d.start.heading_rad, truth.front().heading_rad, 0.02);
  EXPECT_GT(std::abs(d.start.heading_rad - truth.front().heading_rad), 0.01);  // the scatter is measured too
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("heading_rad is the direction of travel +1.2166 rad"), std::string::npos) << notes[0];
  // Plaza 1 as it is: nothing measured to take out, the start heading the file's to the bit.
  notes.clear();
  EXPECT_EQ(roam::loadCsvDataset(kPlaza1, {}, &notes).start.heading_rad, truth.front().heading_rad);
  EXPECT_TRUE(notes.empty());
}

TEST(CsvImport, RealPlaza1HasTheCountsOfTheReadme) {
  ROAM_REQUIRE_DATA(kPlaza1);
  const roam::Dataset d = roam::loadCsvDataset(kPlaza1);
  EXPECT_EQ(d.odometry.size(), 9657u);
  EXPECT_EQ(d.ranges.size(), 3529u);
  EXPECT_EQ(d.ground_truth.size(), 9658u);
  ASSERT_EQ(d.beacons.size(), 4u);
  EXPECT_EQ(d.beacons[0].id, 0);
  EXPECT_EQ(d.beacons[1].id, 1);
  EXPECT_EQ(d.beacons[2].id, 5);
  EXPECT_EQ(d.beacons[3].id, 6);
  for (size_t i = 1; i < d.ranges.size(); ++i) ASSERT_LE(d.ranges[i - 1].utime, d.ranges[i].utime) << i;
  EXPECT_EQ(d.ranges.front().utime, std::llround(3858.0620000362396 * 1e6));
  EXPECT_EQ(d.start.utime, std::llround(3856.857346057892 * 1e6));
  EXPECT_EQ(d.start.heading_rad, 4.222432);
  // README: odometry.time_s[k] == groundtruth.time_s[k+1].
  for (size_t k = 0; k < d.odometry.size(); ++k) ASSERT_EQ(d.odometry[k].utime, d.ground_truth[k + 1].utime);
}

}  // namespace
