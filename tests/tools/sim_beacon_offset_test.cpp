// roam-sim's per-beacon range offsets (--beacon-offset-min / --beacon-offset-max): every range to
// beacon b is the same seed's range without offsets plus b's own o_b, |o_b| within the bounds,
// and nothing else in the run changes. And sim::goatsLikeWorld is the seed sweep's auv-goats kind.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <string>

#include "dataset_log.hpp"
#include "sim.hpp"
#include "tool_test_util.hpp"

namespace {

roam::sim::SimConfig auvWorld(uint64_t seed) { return roam::sim::auvLikeWorld(seed, 300); }

TEST(SimBeaconOffset, EachBeaconsRangesMoveByItsOwnOffsetAndNothingElseChanges) {
  int positive = 0, negative = 0;
  for (uint64_t seed = 1; seed <= 5; ++seed) {
    roam::sim::SimConfig config = auvWorld(seed);
    const roam::sim::SimRun plain = roam::sim::simulate(config);
    config.beacon_offset_min_m = 1.0;
    config.beacon_offset_max_m = 2.0;
    const roam::sim::SimRun offset = roam::sim::simulate(config);
    const std::map<int, double> o_m = roam::sim::beaconOffsets(config, offset.beacons);

    ASSERT_EQ(o_m.size(), plain.beacons.size());
    for (const auto& [id, o] : o_m) {
      EXPECT_GE(std::abs(o), 1.0) << "beacon " << id;
      EXPECT_LE(std::abs(o), 2.0) << "beacon " << id;
      (o > 0 ? positive : negative) += 1;
    }
    ASSERT_EQ(offset.ranges.size(), plain.ranges.size());
    for (size_t k = 0; k < plain.ranges.size(); ++k) {
      const roam::Range& a = plain.ranges[k];
      const roam::Range& b = offset.ranges[k];
      EXPECT_EQ(b.utime, a.utime);
      EXPECT_EQ(b.beacon_id, a.beacon_id);
      EXPECT_EQ(b.range_m, std::max(a.range_m + o_m.at(a.beacon_id), 1e-3)) << "range " << k;
    }
    ASSERT_EQ(offset.odometry.size(), plain.odometry.size());
    for (size_t k = 0; k < plain.odometry.size(); ++k) {
      EXPECT_EQ(offset.odometry[k].forward_m, plain.odometry[k].forward_m);
      EXPECT_EQ(offset.odometry[k].delta_heading_rad, plain.odometry[k].delta_heading_rad);
    }
    for (size_t n = 0; n < plain.beacons.size(); ++n) EXPECT_EQ(offset.beacons[n].x_m, plain.beacons[n].x_m);
  }
  // 20 independent signs: both occur (all one sign has probability 2^-19).
  EXPECT_GT(positive, 0);
  EXPECT_GT(negative, 0);
}

TEST(SimBeaconOffset, OwnStreamApartFromTheRunsAndAnExplicitSeedReproduces) {
  roam::sim::SimConfig config = auvWorld(4);
  config.beacon_offset_min_m = 1.0;
  config.beacon_offset_max_m = 2.0;
  const roam::Map beacons = roam::sim::simulate(config).beacons;
  const std::map<int, double> derived = roam::sim::beaconOffsets(config, beacons);
  config.beacon_offset_seed = config.seed;  // the run's own seed: the stream the run draws from
  const std::map<int, double> run_stream = roam::sim::beaconOffsets(config, beacons);
  EXPECT_NE(derived, run_stream);
  EXPECT_EQ(roam::sim::beaconOffsets(config, beacons), run_stream);
}

TEST(SimBeaconOffset, NoneByDefault) {
  roam::sim::SimConfig config = auvWorld(3);
  EXPECT_TRUE(roam::sim::beaconOffsets(config, roam::sim::simulate(config).beacons).empty());
}

TEST(SimBeaconOffset, CommandLine) {
  roam_test::ScratchDir dir;
  const std::string sim = roam_test::tool("roam-sim");
  const roam_test::ToolResult help = roam_test::runTool(sim + " --help");
  EXPECT_NE(help.out.find("--beacon-offset-max"), std::string::npos);
  const roam_test::ToolResult bad =
      roam_test::runTool(sim + " -o " + dir.file("x.lcmlog") + " --beacon-offset-min 2 --beacon-offset-max 1");
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.out.find("--beacon-offset-min: expected 0 <= --beacon-offset-min <= --beacon-offset-max"), std::string::npos)
      << bad.out;
  const roam_test::ToolResult ok =
      roam_test::runTool(sim + " -o " + dir.file("x.lcmlog") + " --steps 50 --beacon-offset-min 1 --beacon-offset-max 2");
  EXPECT_EQ(ok.status, 0) << ok.out;
}

std::string fileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// The run utilities/seed-sweep's KIND makes (its --list options, seed 7) is the one the tests'
// world makes: byte for byte the same log.
void expectSeedSweepKindIsWorld(const std::string& kind, const roam::sim::SimConfig& world_config,
                                const std::string& world_name) {
  roam_test::ScratchDir dir;
  const roam_test::ToolResult list = roam_test::runTool(std::string(ROAM_SOURCE_DIR) + "/utilities/seed-sweep --list");
  ASSERT_EQ(list.status, 0) << list.out;
  std::istringstream lines(list.out);
  std::string line, options;
  while (std::getline(lines, line))
    if (line.rfind(kind + ":", 0) == 0 && std::getline(lines, options)) break;
  const std::string prefix = "  roam-sim ", suffix = " --seed SEED";
  ASSERT_EQ(options.rfind(prefix, 0), 0u) << options;
  ASSERT_GT(options.size(), prefix.size() + suffix.size());
  options = options.substr(prefix.size(), options.size() - prefix.size() - suffix.size());
  const roam_test::ToolResult made =
      roam_test::runTool(roam_test::tool("roam-sim") + " -o " + dir.file("cli.lcmlog") + " --seed 7 " + options);
  ASSERT_EQ(made.status, 0) << made.out;
  roam::writeDatasetLog(dir.file("world.lcmlog"), roam::sim::simulate(world_config));
  const std::string cli = fileBytes(dir.file("cli.lcmlog")), world = fileBytes(dir.file("world.lcmlog"));
  EXPECT_GT(cli.size(), 10000u);
  EXPECT_TRUE(cli == world) << "roam-sim " << options << " differs from " << world_name;
}

TEST(SimWorlds, GoatsLikeWorldIsTheSeedSweepsAuvGoatsKind) {
  expectSeedSweepKindIsWorld("auv-goats", roam::sim::goatsLikeWorld(7, 210), "sim::goatsLikeWorld(7, 210)");
}

TEST(SimWorlds, AuvLikeWorldIsTheSeedSweepsAuvSparseKind) {
  expectSeedSweepKindIsWorld("auv-sparse", roam::sim::auvLikeWorld(7, 500), "sim::auvLikeWorld(7, 500)");
}

TEST(SimWorlds, LongLanesWorldIsTheSeedSweepsLongLanesKind) {
  expectSeedSweepKindIsWorld("long-lanes", roam::sim::longLanesWorld(7, 1500), "sim::longLanesWorld(7, 1500)");
}

TEST(SimWorlds, Nlos50WorldIsTheSeedSweepsNlos50Kind) {
  expectSeedSweepKindIsWorld("nlos50", roam::sim::nlos50LawnMowerWorld(7, 3000), "sim::nlos50LawnMowerWorld(7, 3000)");
}

TEST(SimWorlds, RacetrackWorldIsTheSeedSweepsDriftRacetrackKind) {
  expectSeedSweepKindIsWorld("drift-racetrack", roam::sim::racetrackWorld(7, 6500), "sim::racetrackWorld(7, 6500)");
}

}  // namespace
