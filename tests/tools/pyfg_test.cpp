// pyfg in and out (utilities/dataset/pyfg_dataset.hpp): the real GOATS 16 file, dead reckoning
// against the file's own edges, a write/read round trip, and every refusal naming file and line.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "pyfg_dataset.hpp"
#include "roam/estimation/motion_model.hpp"
#include "tool_test_util.hpp"

namespace {

const std::string kGoats = std::string(ROAM_SOURCE_DIR) + "/data/goats16/goats_16.pyfg";
constexpr double kTolerance_m = 1e-9;

TEST(Pyfg, ReadsGoats16) {
  ROAM_REQUIRE_DATA(kGoats);
  const roam::PyfgImport imported = roam::loadPyfgDataset(kGoats);
  const roam::Dataset& d = imported.dataset;
  // README of the data: 201 poses, 200 odometry edges, 572 ranges, 4 beacons, 1,473 s.
  EXPECT_EQ(d.ground_truth.size(), 201u);
  EXPECT_EQ(d.odometry.size(), 200u);
  EXPECT_EQ(d.ranges.size(), 572u);
  ASSERT_EQ(d.beacons.size(), 4u);
  EXPECT_EQ(d.beacons[0].id, 0);
  EXPECT_EQ(d.beacons[0].x_m, 730.9);  // VERTEX_XY L0 730.900000000 82.000000000
  EXPECT_EQ(d.ground_truth.back().utime - d.start.utime, 1473000000);
  // The vehicle moves along its body +y: auto picks y, headings turn by +pi/2.
  EXPECT_EQ(imported.forward_axis, roam::ForwardAxis::kY);
  EXPECT_NEAR(d.start.heading_rad, 2.8835235 + M_PI / 2, 1e-12);
  // A2's time (8 s) on the edge A1 -> A2; the first range line "A7 L0 322.07508 0.5625" at A7's time, sigma 0.75.
  EXPECT_EQ(d.odometry[1].utime, 8000000);
  for (size_t i = 1; i < d.ranges.size(); ++i) EXPECT_LE(d.ranges[i - 1].utime, d.ranges[i].utime);
  bool found = false;
  for (const roam::Range& r : d.ranges) {
    if (r.beacon_id == 0 && r.range_m == 322.07508) {
      EXPECT_EQ(r.utime, d.ground_truth[7].utime);
      EXPECT_EQ(r.sigma_m, 0.75);
      found = true;
    }
  }
  EXPECT_TRUE(found);
  // Edge covariance diag(0.0004, 0.0004, 0.000004) in the file's (dx, dy): forward takes dy's.
  EXPECT_EQ(d.odometry[0].covariance[0], 0.0004);
  EXPECT_EQ(d.odometry[0].covariance[8], 0.000004);
}

TEST(Pyfg, DeadReckoningIsTheCompositionOfTheFilesOwnEdges) {
  ROAM_REQUIRE_DATA(kGoats);
  // Compose the file's edges by hand in the file's own frame (x' = x + cos(t) dx - sin(t) dy),
  // from its first pose, and compare with roam's motion model over the imported odometry, with
  // either body axis: the positions must agree to 1e-9 m.
  std::ifstream in(kGoats);
  std::string line;
  double x = 0, y = 0, t = 0;
  bool have_start = false;
  std::vector<std::pair<double, double>> by_hand;
  while (std::getline(in, line)) {
    std::istringstream w(line);
    std::string type;
    w >> type;
    if (type == "VERTEX_SE2" && !have_start) {
      std::string time, name;
      w >> time >> name >> x >> y >> t;
      have_start = true;
      by_hand.push_back({x, y});
    } else if (type == "EDGE_SE2") {
      std::string time, from, to;
      double dx, dy, dt;
      w >> time >> from >> to >> dx >> dy >> dt;
      x += std::cos(t) * dx - std::sin(t) * dy;
      y += std::sin(t) * dx + std::cos(t) * dy;
      t += dt;
      by_hand.push_back({x, y});
    }
  }
  ASSERT_EQ(by_hand.size(), 201u);
  for (roam::ForwardAxis axis : {roam::ForwardAxis::kX, roam::ForwardAxis::kY}) {
    roam::PyfgImportOptions options;
    options.forward_axis = axis;
    const roam::Dataset d = roam::loadPyfgDataset(kGoats, options).dataset;
    roam::Pose pose = d.start;
    double worst = 0.0;
    for (size_t k = 0; k < d.odometry.size(); ++k) {
      pose = roam::estimation::step(pose, d.odometry[k]);
      worst = std::max(worst, std::hypot(pose.x_m - by_hand[k + 1].first, pose.y_m - by_hand[k + 1].second));
    }
    EXPECT_LT(worst, kTolerance_m);
  }
}

TEST(Pyfg, WritingAndReadingBackReproducesEveryPoseBeaconAndRange) {
  ROAM_REQUIRE_DATA(kGoats);
  roam_test::ScratchDir dir;
  for (roam::ForwardAxis axis : {roam::ForwardAxis::kX, roam::ForwardAxis::kY}) {
    roam::PyfgImportOptions read_options;
    read_options.forward_axis = axis;
    const roam::Dataset original = roam::loadPyfgDataset(kGoats, read_options).dataset;
    roam::PyfgWriteOptions write_options;
    write_options.forward_axis = axis;
    roam::writePyfg(dir.file("copy.pyfg"), original, write_options);
    const roam::Dataset copy = roam::loadPyfgDataset(dir.file("copy.pyfg"), read_options).dataset;
    ASSERT_EQ(copy.ground_truth.size(), original.ground_truth.size());
    for (size_t i = 0; i < copy.ground_truth.size(); ++i) {
      EXPECT_EQ(copy.ground_truth[i].utime, original.ground_truth[i].utime);
      EXPECT_EQ(copy.ground_truth[i].x_m, original.ground_truth[i].x_m);
      EXPECT_EQ(copy.ground_truth[i].y_m, original.ground_truth[i].y_m);
      EXPECT_NEAR(copy.ground_truth[i].heading_rad, original.ground_truth[i].heading_rad, 1e-15);
    }
    ASSERT_EQ(copy.odometry.size(), original.odometry.size());
    for (size_t k = 0; k < copy.odometry.size(); ++k) {
      EXPECT_EQ(copy.odometry[k].utime, original.odometry[k].utime);
      EXPECT_EQ(copy.odometry[k].forward_m, original.odometry[k].forward_m);
      EXPECT_EQ(copy.odometry[k].lateral_m, original.odometry[k].lateral_m);
      EXPECT_EQ(copy.odometry[k].delta_heading_rad, original.odometry[k].delta_heading_rad);
      for (int i = 0; i < 9; ++i) EXPECT_EQ(copy.odometry[k].covariance[i], original.odometry[k].covariance[i]);
    }
    ASSERT_EQ(copy.ranges.size(), original.ranges.size());
    for (size_t k = 0; k < copy.ranges.size(); ++k) {
      EXPECT_EQ(copy.ranges[k].utime, original.ranges[k].utime);
      EXPECT_EQ(copy.ranges[k].beacon_id, original.ranges[k].beacon_id);
      EXPECT_EQ(copy.ranges[k].range_m, original.ranges[k].range_m);
      EXPECT_EQ(copy.ranges[k].sigma_m, original.ranges[k].sigma_m);
    }
    ASSERT_EQ(copy.beacons.size(), original.beacons.size());
    for (size_t k = 0; k < copy.beacons.size(); ++k) {
      EXPECT_EQ(copy.beacons[k].id, original.beacons[k].id);
      EXPECT_EQ(copy.beacons[k].x_m, original.beacons[k].x_m);
      EXPECT_EQ(copy.beacons[k].y_m, original.beacons[k].y_m);
    }
  }
}

TEST(Pyfg, BeaconPriorsBecomeBeaconCovariances) {
  roam_test::ScratchDir dir;
  dir.write("p.pyfg",
            "VERTEX_SE2 0.0 A0 0 0 0\nVERTEX_SE2 1.5 A1 1 0 0\nVERTEX_XY L2 5 6\n"
            "VERTEX_XY:PRIOR 0.0 L2 5 6 0.25 0.01 0.36\n"
            "EDGE_SE2 0 A0 A1 1 0 0 0.01 0 0 0.01 0 0.0001\nEDGE_RANGE 0 A1 L2 7.2 0.09\n");
  const roam::Dataset d = roam::loadPyfgDataset(dir.file("p.pyfg")).dataset;
  ASSERT_EQ(d.beacons.size(), 1u);
  EXPECT_EQ(d.beacons[0].id, 2);
  EXPECT_EQ(d.beacons[0].covariance[0], 0.25);
  EXPECT_EQ(d.beacons[0].covariance[2], 0.01);
  EXPECT_EQ(d.beacons[0].covariance[3], 0.36);
  ASSERT_EQ(d.ranges.size(), 1u);
  EXPECT_EQ(d.ranges[0].utime, 1500000);
  EXPECT_NEAR(d.ranges[0].sigma_m, 0.3, 1e-15);
}

TEST(Pyfg, WhatIsNotSupportedIsRefusedNamingTheLine) {
  roam_test::ScratchDir dir;
  const std::string head = "VERTEX_SE2 0.0 A0 0 0 0\nVERTEX_SE2 1.0 A1 1 0 0\nVERTEX_XY L0 5 5\n";
  const std::string edge = "EDGE_SE2 0 A0 A1 1 0 0 0.01 0 0 0.01 0 0.0001\n";
  struct Case {
    std::string body, expected;
  };
  const Case cases[] = {
      {head + edge + "VERTEX_SE3:QUAT 0 A2 0 0 0 0 0 0 1\n", ":5: VERTEX_SE3:QUAT: 3-D data is not supported (roam is 2-D)"},
      {head + edge + "VERTEX_SE2 2.0 B0 0 0 0\n", ":5: several robots ('A' and 'B'): roam runs one robot per log; choose one with --robot A (the other robots' lines are then set aside)"},
      {head + edge + "EDGE_RANGE 0 A0 A1 3.0 0.01\n", ":5: EDGE_RANGE A0 A1: ranges between poses (inter-robot ranges) are not supported"},
      {head + edge + "EDGE_SE2 0 A1 A0 -1 0 0 0.01 0 0 0.01 0 x\n", ":5: EDGE_SE2: covariance: expected a number, got 'x'"},
      {head + edge + "EDGE_SE2 0 A1 A9 -1 0 0 0.01 0 0 0.01 0 0.0001\n", ":5: EDGE_SE2: to 'A9' has no VERTEX_SE2"},
      {head + edge + "EDGE_RANGE 0 A1 L0 4.x 0.01\n", ":5: EDGE_RANGE: range: expected a number, got '4.x'"},
      {head + edge + "EDGE_RANGE 0 A1 L7 4.0 0.01\n", ":5: beacon 'L7' has no VERTEX_XY"},
      {head + edge + "EDGE_RANGE 0 A1 L0 4.0\n", ":5: EDGE_RANGE: expected 5 fields (time a b range variance), got 4"},
      {head + edge + "EDGE_SE2_XY 0 A1 L0 1 2 0.1 0\n", ":5: EDGE_SE2_XY: expected 8 fields (time pose beacon dx dy and 3 covariance values), got 7"},
      {head + edge + "EDGE_SE2_XY 0 A1 L4 1 2 0.1 0 0.1\n", ":5: beacon 'L4' has no VERTEX_XY"},
      {head + edge + "VERTEX_SE2:PRIOR 0 A0 0 0 zero 1 0 0 1 0 1\n", ":5: VERTEX_SE2:PRIOR: measurement: expected a number, got 'zero'"},
      {head + edge + "VERTEX_SE2:PRIOR 0 A5 0 0 0 1 0 0 1 0 1\n", ":5: VERTEX_SE2:PRIOR: pose 'A5' has no VERTEX_SE2"},
      {head + edge + "FOO 1 2\n", ":5: unknown type 'FOO'"},
      {head, ":2: pose A1 has no EDGE_SE2 from A0"},
  };
  for (const Case& c : cases) {
    dir.write("bad.pyfg", c.body);
    try {
      roam::loadPyfgDataset(dir.file("bad.pyfg"));
      ADD_FAILURE() << "accepted: " << c.body;
    } catch (const std::runtime_error& error) {
      EXPECT_EQ(std::string(error.what()).rfind(dir.file("bad.pyfg") + c.expected, 0), 0u)
          << error.what() << "\nexpected: " << c.expected;
    }
  }
}

TEST(Pyfg, WhatPyFactorGraphWritesBesideOdometryAndRangesIsSetAsideWithANote) {
  // PyFactorGraph's writer puts a prior on the first pose, loop closures and pose-landmark
  // measurements in the same file; roam's estimators take none of them. The file reads as the
  // same file without them, and a note per kind names its first line and count.
  roam_test::ScratchDir dir;
  const std::string poses =
      "VERTEX_SE2 0.0 A0 0 0 0\nVERTEX_SE2 1.0 A1 1 0 0.1\nVERTEX_SE2 2.0 A2 2 0.1 0.2\nVERTEX_XY L0 5 5\n";
  const std::string prior = "VERTEX_SE2:PRIOR 0.0 A0 0 0 0 0.01 0 0 0.01 0 0.04\n";
  const std::string odometry =
      "EDGE_SE2 1.0 A0 A1 1 0 0.1 0.01 0 0 0.01 0 0.0001\nEDGE_SE2 2.0 A1 A2 1 0.05 0.1 0.01 0 0 0.01 0 0.0001\n";
  const std::string closures =
      "EDGE_SE2 3.0 A2 A0 -2 0 -0.2 0.01 0 0 0.01 0 0.04\nEDGE_SE2 4.0 A0 A2 2 0.1 0.2 0.01 0 0 0.01 0 0.04\n"
      "EDGE_SE2 3.5 A1 A0 -1 0 -0.1 0.01 0 0 0.01 0 0.04\n";
  const std::string ranges = "EDGE_RANGE 1.0 A1 L0 6.4 0.09\nEDGE_RANGE 2.0 A2 L0 5.8 0.09\n";
  dir.write("plain.pyfg", poses + odometry + ranges);
  dir.write("full.pyfg", poses + prior + odometry + closures + ranges);
  const roam::PyfgImport plain = roam::loadPyfgDataset(dir.file("plain.pyfg"));
  const roam::PyfgImport full = roam::loadPyfgDataset(dir.file("full.pyfg"));
  EXPECT_TRUE(plain.notes.empty());
  ASSERT_EQ(full.dataset.odometry.size(), plain.dataset.odometry.size());
  for (size_t k = 0; k < plain.dataset.odometry.size(); ++k) {
    EXPECT_EQ(full.dataset.odometry[k].utime, plain.dataset.odometry[k].utime);
    EXPECT_EQ(full.dataset.odometry[k].forward_m, plain.dataset.odometry[k].forward_m);
    EXPECT_EQ(full.dataset.odometry[k].lateral_m, plain.dataset.odometry[k].lateral_m);
    EXPECT_EQ(full.dataset.odometry[k].delta_heading_rad, plain.dataset.odometry[k].delta_heading_rad);
  }
  ASSERT_EQ(full.dataset.ranges.size(), 2u);
  EXPECT_EQ(full.dataset.ranges[1].range_m, plain.dataset.ranges[1].range_m);
  ASSERT_EQ(full.notes.size(), 2u);
  const std::string file = dir.file("full.pyfg");
  EXPECT_EQ(full.notes[0], file + ":5: set aside 1 pose prior(s) (VERTEX_SE2:PRIOR): the first VERTEX_SE2 is the start "
                                  "pose, and roam's estimators take no absolute fix");
  EXPECT_EQ(full.notes[1], file + ":8: set aside 3 loop closure(s) (EDGE_SE2 between poses that are not consecutive) "
                                  "(the first here): roam's estimators take odometry and ranges");
  const auto result = roam_test::runTool(roam_test::tool("roam-import") + " " + file + " -o " + dir.file("f.lcmlog"));
  EXPECT_EQ(result.status, 0) << result.out;
  EXPECT_NE(result.out.find("(2 odometry, 2 ranges, 3 ground truth, 1 beacons)"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("roam-import: note: " + full.notes[1] + "\n"), std::string::npos) << result.out;
}

TEST(Pyfg, OneRobotOfSeveralIsReadWithTheOthersSetAside) {
  // A multi-robot file (PyFactorGraph writes robots A, B, ...; inter-robot ranges between their
  // poses): loadPyfgDataset refuses it without a robot chosen, naming the option; with one chosen, that robot's
  // run is read exactly as from a file of its own, and the rest is set aside with a note per kind.
  roam_test::ScratchDir dir;
  const std::string robot_b =
      "VERTEX_SE2 0.0 B0 0 0 0\nVERTEX_SE2 1.0 B1 1 0 0.1\nVERTEX_SE2 2.0 B2 2 0.1 0.2\n"
      "EDGE_SE2 1.0 B0 B1 1 0 0.1 0.01 0 0 0.01 0 0.0001\nEDGE_SE2 2.0 B1 B2 1 0.05 0.1 0.01 0 0 0.01 0 0.0001\n"
      "EDGE_RANGE 1.0 B1 L0 6.4 0.09\nEDGE_RANGE 2.0 L0 B2 5.8 0.09\n";
  const std::string beacon = "VERTEX_XY L0 5 5\n";
  const std::string robot_a = "VERTEX_SE2 0.0 A0 9 9 0\nVERTEX_SE2 1.5 A1 9 10 1.57\nVERTEX_SE2:PRIOR 0.0 A0 9 9 0 0.01 0 0 0.01 0 0.04\n"
                              "EDGE_SE2 1.5 A0 A1 1 0 1.57 0.01 0 0 0.01 0 0.0001\nEDGE_RANGE 1.5 A1 L0 6.4 0.09\n";
  const std::string between = "EDGE_RANGE 1.0 A1 B1 8.5 0.09\nEDGE_SE2 2.0 A1 B2 -7 -8 0 0.1 0 0 0.1 0 0.01\n";
  dir.write("b.pyfg", beacon + robot_b);
  dir.write("ab.pyfg", beacon + robot_a + robot_b + between);
  const std::string file = dir.file("ab.pyfg");
  try {
    roam::loadPyfgDataset(file);
    ADD_FAILURE() << "read a file of two robots without one chosen";
  } catch (const std::runtime_error& error) {
    EXPECT_EQ(std::string(error.what()), file + ":7: several robots ('A' and 'B'): roam runs one robot per log; choose "
                                                "one with --robot A (the other robots' lines are then set aside)");
  }
  roam::PyfgImportOptions options;
  options.robot = 'B';
  const roam::PyfgImport alone = roam::loadPyfgDataset(dir.file("b.pyfg"));
  const roam::PyfgImport chosen = roam::loadPyfgDataset(file, options);
  EXPECT_EQ(chosen.robot_letter, 'B');
  ASSERT_EQ(chosen.dataset.ground_truth.size(), 3u);
  ASSERT_EQ(chosen.dataset.odometry.size(), alone.dataset.odometry.size());
  for (size_t k = 0; k < alone.dataset.odometry.size(); ++k) {
    EXPECT_EQ(chosen.dataset.odometry[k].utime, alone.dataset.odometry[k].utime);
    EXPECT_EQ(chosen.dataset.odometry[k].forward_m, alone.dataset.odometry[k].forward_m);
    EXPECT_EQ(chosen.dataset.odometry[k].delta_heading_rad, alone.dataset.odometry[k].delta_heading_rad);
  }
  ASSERT_EQ(chosen.dataset.ranges.size(), 2u);
  EXPECT_EQ(chosen.dataset.ranges[1].range_m, 5.8);
  EXPECT_EQ(chosen.dataset.ranges[1].utime, 2000000);
  EXPECT_EQ(chosen.dataset.start.x_m, 0.0);
  EXPECT_TRUE(alone.notes.empty());
  ASSERT_EQ(chosen.notes.size(), 2u);
  EXPECT_EQ(chosen.notes[0], file + ":2: set aside 5 line(s) of other robots (A) (the first here): --robot B reads robot B alone");
  EXPECT_EQ(chosen.notes[1], file + ":14: set aside 2 measurement(s) between two robots (EDGE_RANGE, EDGE_SE2) (the first "
                                    "here): roam's estimators take ranges to fixed beacons");
  // A set-aside line is still checked; a robot the file lacks, or a beacon's letter, is refused.
  dir.write("bad.pyfg", beacon + robot_b + "VERTEX_SE2 0.0 A0 9 nine 0\n");
  try {
    roam::loadPyfgDataset(dir.file("bad.pyfg"), options);
    ADD_FAILURE() << "a bad number on a set-aside line passed";
  } catch (const std::runtime_error& error) {
    EXPECT_EQ(std::string(error.what()), dir.file("bad.pyfg") + ":9: VERTEX_SE2: measurement: expected a number, got 'nine'");
  }
  options.robot = 'C';
  try {
    roam::loadPyfgDataset(file, options);
    ADD_FAILURE() << "read robot C from a file without it";
  } catch (const std::runtime_error& error) {
    EXPECT_EQ(std::string(error.what()), file + ": no VERTEX_SE2 of robot 'C' (--robot); the file's robots: A, B");
  }
  options.robot = 'L';
  EXPECT_THROW(roam::loadPyfgDataset(file, options), std::runtime_error);
  const auto result = roam_test::runTool(roam_test::tool("roam-import") + " " + file + " -o " + dir.file("b.lcmlog") + " --robot B");
  EXPECT_EQ(result.status, 0) << result.out;
  EXPECT_NE(result.out.find("(2 odometry, 2 ranges, 3 ground truth, 1 beacons)"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("roam-import: note: " + chosen.notes[1] + "\n"), std::string::npos) << result.out;
  // Without --robot, roam-import reads the whole team (team_test.cpp); the library call refuses.
  const auto team = roam_test::runTool(roam_test::tool("roam-import") + " " + file + " -o " + dir.file("ab.lcmlog"));
  EXPECT_EQ(team.status, 0) << team.out;
  EXPECT_NE(team.out.find("roam-import: config: [team] robots = A B\n"), std::string::npos) << team.out;
  const auto two_letters = roam_test::runTool(roam_test::tool("roam-import") + " " + file + " -o " + dir.file("b.lcmlog") + " --robot AB");
  EXPECT_EQ(two_letters.status, 2);
  EXPECT_NE(two_letters.out.find("--robot: expected one robot letter (A, B, ...), got 'AB'"), std::string::npos) << two_letters.out;
}

TEST(Pyfg, AFileWithoutPoseTimesIsRefusedUnlessTheIntervalIsGiven) {
  // Every pose at one time: each odometry step would take no time, and every estimator rejects
  // it ('time did not advance'). Refused with the option that fixes it; with it, pose i is at
  // i x the interval.
  roam_test::ScratchDir dir;
  dir.write("untimed.pyfg",
            "VERTEX_SE2 0 A3 0 0 0\nVERTEX_SE2 0 A4 1 0 0\nVERTEX_SE2 0 A5 2 0 0\nVERTEX_XY L0 5 5\n"
            "EDGE_SE2 0 A3 A4 1 0 0 0.01 0 0 0.01 0 0.0001\nEDGE_SE2 0 A4 A5 1 0 0 0.01 0 0 0.01 0 0.0001\n"
            "EDGE_RANGE 0 A5 L0 5.8 0.09\n");
  const std::string file = dir.file("untimed.pyfg");
  try {
    roam::loadPyfgDataset(file);
    ADD_FAILURE() << "accepted a file without pose times";
  } catch (const std::runtime_error& error) {
    EXPECT_EQ(std::string(error.what()), file + ": every VERTEX_SE2 is at time 0 s: the file carries no pose times, and the "
                                                "estimators need them (rates, speeds, a gyro's drift); give the time "
                                                "between poses with --pose-interval-s SECONDS");
  }
  roam::PyfgImportOptions options;
  options.pose_interval_s = 2.5;
  const roam::PyfgImport imported = roam::loadPyfgDataset(file, options);
  ASSERT_EQ(imported.dataset.ground_truth.size(), 3u);
  EXPECT_EQ(imported.dataset.start.utime, 0);
  EXPECT_EQ(imported.dataset.odometry[0].utime, 2500000);
  EXPECT_EQ(imported.dataset.odometry[1].utime, 5000000);
  EXPECT_EQ(imported.dataset.ranges[0].utime, 5000000);
  ASSERT_EQ(imported.notes.size(), 1u);
  EXPECT_EQ(imported.notes[0], file + ": pose i is at i x 2.5 s (--pose-interval-s); the file's pose times are set aside");
  const auto refused = roam_test::runTool(roam_test::tool("roam-import") + " " + file + " -o " + dir.file("u.lcmlog"));
  EXPECT_EQ(refused.status, 2);
  EXPECT_NE(refused.out.find("give the time between poses with --pose-interval-s SECONDS"), std::string::npos) << refused.out;
  const auto timed = roam_test::runTool(roam_test::tool("roam-import") + " " + file + " -o " + dir.file("u.lcmlog") +
                                        " --pose-interval-s 2.5");
  EXPECT_EQ(timed.status, 0) << timed.out;
  EXPECT_NE(timed.out.find("5.000 s from utime 0"), std::string::npos) << timed.out;
  const auto negative = roam_test::runTool(roam_test::tool("roam-import") + " " + file + " -o " + dir.file("u.lcmlog") +
                                           " --pose-interval-s -1");
  EXPECT_EQ(negative.status, 2);
  EXPECT_NE(negative.out.find("--pose-interval-s: expected seconds >= 0"), std::string::npos) << negative.out;
}

TEST(Pyfg, PoseTimesInNanosecondsAreReadAsSuchWithANote) {
  // Published team runs stamp poses in nanoseconds since 1970 (1.73e18): read as seconds that
  // overflowed roam's microsecond clock. auto takes the largest unit that puts the latest time
  // within 1e11 s, says so, and --time-unit chooses another.
  roam_test::ScratchDir dir;
  dir.write("ns.pyfg",
            "VERTEX_SE2 1730477379787663104.000 A0 0 0 0\nVERTEX_SE2 1730477380287663104.000 A1 1 0 0\n"
            "VERTEX_SE2 1730477380787663104.000 A2 2 0 0\nVERTEX_XY L0 5 5\n"
            "EDGE_SE2 0 A0 A1 1 0 0 0.01 0 0 0.01 0 0.0001\nEDGE_SE2 0 A1 A2 1 0 0 0.01 0 0 0.01 0 0.0001\n"
            "EDGE_RANGE 0 A2 L0 5.8 0.09\n");
  const std::string file = dir.file("ns.pyfg");
  const roam::PyfgImport imported = roam::loadPyfgDataset(file);
  EXPECT_EQ(imported.time_unit_s, 1e-9);
  ASSERT_EQ(imported.dataset.odometry.size(), 2u);
  // 1730477379.787663104 s: the double holds it to 256 ns, the microsecond is exact.
  EXPECT_EQ(imported.dataset.start.utime, 1730477379787663);
  EXPECT_EQ(imported.dataset.odometry[0].utime - imported.dataset.start.utime, 500000);
  EXPECT_EQ(imported.dataset.odometry[1].utime - imported.dataset.start.utime, 1000000);
  ASSERT_EQ(imported.notes.size(), 1u);
  EXPECT_EQ(imported.notes[0], file + ": pose times read as nanoseconds (the latest, 1.7304773807876631e+18, is beyond "
                                      "1e11 s); --time-unit s|ms|us|ns chooses another unit");
  // Said as seconds on purpose: refused by name, never overflowed.
  roam::PyfgImportOptions seconds;
  seconds.time_unit_s = 1.0;
  try {
    roam::loadPyfgDataset(file, seconds);
    ADD_FAILURE() << "accepted 1.7e18 s";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("beyond 9e12 s in seconds"), std::string::npos) << error.what();
  }
  const auto cli = roam_test::runTool(roam_test::tool("roam-import") + " " + file + " -o " + dir.file("ns.lcmlog"));
  EXPECT_EQ(cli.status, 0) << cli.out;
  EXPECT_NE(cli.out.find("1.000 s from utime 1730477379787663"), std::string::npos) << cli.out;
  EXPECT_NE(cli.out.find("pose times read as nanoseconds"), std::string::npos) << cli.out;
  const auto bad = roam_test::runTool(roam_test::tool("roam-import") + " " + file + " -o " + dir.file("ns.lcmlog") +
                                      " --time-unit hours");
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.out.find("--time-unit: expected s | ms | us | ns | auto, got 'hours'"), std::string::npos) << bad.out;
}

TEST(Pyfg, ARobotWhoseEveryRangeIsToAnotherRobotIsSaidToHaveNone) {
  roam_test::ScratchDir dir;
  dir.write("team.pyfg",
            "VERTEX_SE2 0 A0 0 0 0\nVERTEX_SE2 1 A1 1 0 0\nVERTEX_SE2 0 B0 0 5 0\nVERTEX_SE2 1 B1 1 5 0\n"
            "EDGE_SE2 0 A0 A1 1 0 0 0.01 0 0 0.01 0 0.0001\nEDGE_SE2 0 B0 B1 1 0 0 0.01 0 0 0.01 0 0.0001\n"
            "EDGE_RANGE 0 A0 B0 5.0 0.01\nEDGE_RANGE 0 A1 B1 5.0 0.01\n");
  roam::PyfgImportOptions options;
  options.robot = 'A';
  const roam::PyfgImport imported = roam::loadPyfgDataset(dir.file("team.pyfg"), options);
  EXPECT_TRUE(imported.dataset.ranges.empty());
  ASSERT_FALSE(imported.notes.empty());
  EXPECT_EQ(imported.notes.back(), dir.file("team.pyfg") + ": robot A has no range to a fixed beacon: its 2 range(s) are "
                                                           "all to other robots (set aside); an estimator run on this "
                                                           "log has odometry alone (dead reckoning)");
}

// A landmark seen from a pose (EDGE_SE2_XY: its position in the robot's frame, as MR.CLAM's
// camera sightings are published) is a range with a bearing to that beacon: range |d|, bearing
// atan2(lateral, forward) in roam's body frame, sigma the covariance along d.
TEST(Pyfg, ALandmarkSightingIsARangeWithABearing) {
  roam_test::ScratchDir dir;
  const std::string head = "VERTEX_XY L3 5 5\nVERTEX_SE2 0 A0 0 0 0\nVERTEX_SE2 1 A1 1 0 0.5\n"
                           "EDGE_SE2 1 A0 A1 1 0 0.5 0.01 0 0 0.01 0 0.0001\n";
  dir.write("x.pyfg", head + "EDGE_SE2_XY 1 A1 L3 3 4 0.25 0 0.25\nEDGE_SE2_XY 0 A0 L3 0 2 0.09 0 0.25\n");
  const roam::PyfgImport x = roam::loadPyfgDataset(dir.file("x.pyfg"));
  EXPECT_TRUE(x.notes.empty());
  ASSERT_EQ(x.dataset.ranges.size(), 2u);
  const roam::Range& first = x.dataset.ranges[0];  // the A0 one, by time
  EXPECT_EQ(first.utime, 0);
  EXPECT_EQ(first.beacon_id, 3);
  EXPECT_DOUBLE_EQ(first.range_m, 2.0);
  EXPECT_TRUE(first.has_bearing);
  EXPECT_DOUBLE_EQ(first.bearing_rad, M_PI / 2);  // straight to the left
  EXPECT_DOUBLE_EQ(first.sigma_m, 0.5);           // along d = +y: c22
  const roam::Range& second = x.dataset.ranges[1];
  EXPECT_EQ(second.utime, 1000000);
  EXPECT_DOUBLE_EQ(second.range_m, 5.0);
  EXPECT_DOUBLE_EQ(second.bearing_rad, std::atan2(4.0, 3.0));
  EXPECT_DOUBLE_EQ(second.sigma_m, 0.5);
  // A +y-forward body frame: forward = dy, lateral = -dx.
  roam::PyfgImportOptions y_forward;
  y_forward.forward_axis = roam::ForwardAxis::kY;
  const roam::PyfgImport y = roam::loadPyfgDataset(dir.file("x.pyfg"), y_forward);
  EXPECT_DOUBLE_EQ(y.dataset.ranges[0].bearing_rad, 0.0);
  EXPECT_DOUBLE_EQ(y.dataset.ranges[1].bearing_rad, std::atan2(-3.0, 4.0));
  // Written back as sightings, read back as the same ranges and bearings.
  for (const auto& [axis, imported] : {std::make_pair(roam::ForwardAxis::kX, x), std::make_pair(roam::ForwardAxis::kY, y)}) {
    roam::PyfgWriteOptions write_options;
    write_options.forward_axis = axis;
    roam::writePyfg(dir.file("copy.pyfg"), imported.dataset, write_options);
    roam::PyfgImportOptions read_options;
    read_options.forward_axis = axis;
    const roam::PyfgImport copy = roam::loadPyfgDataset(dir.file("copy.pyfg"), read_options);
    ASSERT_EQ(copy.dataset.ranges.size(), 2u);
    for (size_t k = 0; k < 2; ++k) {
      EXPECT_TRUE(copy.dataset.ranges[k].has_bearing);
      EXPECT_NEAR(copy.dataset.ranges[k].range_m, imported.dataset.ranges[k].range_m, 1e-12);
      EXPECT_NEAR(copy.dataset.ranges[k].bearing_rad, imported.dataset.ranges[k].bearing_rad, 1e-12);
      EXPECT_NEAR(copy.dataset.ranges[k].sigma_m, imported.dataset.ranges[k].sigma_m, 1e-12);
    }
  }
  // What cannot be a range is refused by line.
  dir.write("zero.pyfg", head + "EDGE_SE2_XY 1 A1 L3 0 0 0.25 0 0.25\n");
  dir.write("cov.pyfg", head + "EDGE_SE2_XY 1 A1 L3 3 4 0.25 1 0.25\n");
  for (const auto& [name, message] : {std::make_pair(std::string("zero.pyfg"), std::string(":5: EDGE_SE2_XY: the beacon is at the pose")),
                                      std::make_pair(std::string("cov.pyfg"), std::string(":5: EDGE_SE2_XY: covariance is not positive semi-definite"))}) {
    try {
      roam::loadPyfgDataset(dir.file(name));
      ADD_FAILURE() << name << " was read";
    } catch (const std::runtime_error& error) {
      EXPECT_NE(std::string(error.what()).find(dir.file(name) + message), std::string::npos) << error.what();
    }
  }
}

TEST(Pyfg, BinaryJunkInALineIsPrintedEscaped) {
  roam_test::ScratchDir dir;
  dir.write("junk.pyfg", std::string("VERTEX_SE2 0 A0 0 0 0\nVERTEX_SE2 1 A1 \x01\xff\x1b[2J 0 0\n"));
  try {
    roam::loadPyfgDataset(dir.file("junk.pyfg"));
    ADD_FAILURE() << "accepted junk";
  } catch (const std::runtime_error& error) {
    EXPECT_EQ(std::string(error.what()), dir.file("junk.pyfg") +
                                             ":2: VERTEX_SE2: x: expected a number, got '\\x01\\xFF\\x1B[2J'");
  }
}

TEST(Pyfg, RoamImportTakesAPyfgFile) {
  ROAM_REQUIRE_DATA(kGoats);
  roam_test::ScratchDir dir;
  const auto result = roam_test::runTool(roam_test::tool("roam-import") + " " + kGoats + " -o " + dir.file("g.lcmlog"));
  EXPECT_EQ(result.status, 0) << result.out;
  EXPECT_NE(result.out.find("975 events (200 odometry, 572 ranges, 201 ground truth, 4 beacons)"), std::string::npos)
      << result.out;
  EXPECT_NE(result.out.find("forward axis +y (headings + pi/2) (auto)"), std::string::npos) << result.out;
  const auto bad = roam_test::runTool(roam_test::tool("roam-import") + " " + kGoats + " -o " + dir.file("g.lcmlog") +
                                      " --forward-axis z");
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.out.find("--forward-axis: expected x | y | auto, got 'z'"), std::string::npos) << bad.out;
}

}  // namespace
