// writeDatasetLog's event order, and the committed Plaza 1 logs: they are what roam-import
// writes today, and their odometry integrates to the data README's dead-reckoning figures.
#include <cmath>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include "csv_dataset.hpp"
#include "dataset_log.hpp"
#include "roam/map_t.hpp"
#include "roam/odometry_t.hpp"
#include "roam/pose_t.hpp"
#include "roam/range_t.hpp"
#include "tool_test_util.hpp"

namespace {

const std::string kSource = ROAM_SOURCE_DIR;
const std::string kPlaza1 = kSource + "/data/plaza1";

struct Event {
  std::string channel;
  int64_t timestamp;
  std::vector<uint8_t> data;
};

std::vector<Event> readEvents(const std::string& path) {
  std::vector<Event> events;
  lcm::LogFile log(path, "r");
  EXPECT_TRUE(log.good()) << path;
  while (const lcm::LogEvent* e = log.readNextEvent()) {
    const auto* bytes = static_cast<const uint8_t*>(e->data);
    events.push_back({e->channel, e->timestamp, std::vector<uint8_t>(bytes, bytes + e->datalen)});
  }
  return events;
}

template <typename Message>
Message decode(const Event& event) {
  Message message;
  EXPECT_EQ(message.decode(event.data.data(), 0, static_cast<int>(event.data.size())),
            static_cast<int>(event.data.size()));
  return message;
}

TEST(DatasetLog, EventOrder) {
  roam::Dataset d;
  d.start.utime = 100;
  d.start.x_m = 1.0;
  d.ground_truth = {d.start, {}};
  d.ground_truth[1].utime = 300;
  d.odometry.resize(1);
  d.odometry[0].utime = 300;
  d.odometry[0].forward_m = 0.5;
  d.ranges.resize(3);
  d.ranges[0].utime = 50;  // before the start: still after INITIAL_POSE and BEACONS
  d.ranges[1].utime = 300;
  d.ranges[1].beacon_id = 7;
  d.ranges[2].utime = 300;
  d.ranges[2].beacon_id = 8;
  d.beacons.resize(2);
  d.beacons[0].id = 7;
  d.beacons[1].id = 8;
  roam_test::ScratchDir dir;
  const roam::LogWriteSummary s = roam::writeDatasetLog(dir.file("run.lcmlog"), d);
  EXPECT_EQ(s.events, 8);
  const std::vector<Event> events = readEvents(dir.file("run.lcmlog"));
  const std::vector<std::string> channels{"INITIAL_POSE", "BEACONS", "RANGE", "GROUND_TRUTH",
                                          "GROUND_TRUTH", "ODOMETRY", "RANGE", "RANGE"};
  const std::vector<int64_t> times{100, 100, 50, 100, 300, 300, 300, 300};
  ASSERT_EQ(events.size(), channels.size());
  for (size_t i = 0; i < events.size(); ++i) {
    EXPECT_EQ(events[i].channel, channels[i]) << i;
    EXPECT_EQ(events[i].timestamp, times[i]) << i;
  }
  EXPECT_EQ(decode<roam::pose_t>(events[0]).x, 1.0);
  EXPECT_EQ(decode<roam::map_t>(events[1]).num_beacons, 2);
  EXPECT_EQ(decode<roam::odometry_t>(events[5]).delta_distance, 0.5);
  EXPECT_EQ(decode<roam::range_t>(events[6]).beacon_id, 7);
  EXPECT_EQ(decode<roam::range_t>(events[7]).beacon_id, 8);
}

TEST(DatasetLog, RangesLoggedWithALatencyKeepTheirStamps) {
  // range_latency_us (roam-sim --range-latency-s): each RANGE merged and stamped as an event that
  // much after its message's utime, behind odometry stamped later; the message keeps its utime.
  roam::Dataset d;
  d.start.utime = 0;
  d.odometry.resize(3);
  for (int k = 0; k < 3; ++k) d.odometry[k].utime = 200 * (k + 1);  // 200, 400, 600
  d.ranges.resize(2);
  d.ranges[0].utime = 200;
  d.ranges[1].utime = 300;
  roam_test::ScratchDir dir;
  roam::writeDatasetLog(dir.file("late.lcmlog"), d, 250);
  const std::vector<Event> events = readEvents(dir.file("late.lcmlog"));
  const std::vector<std::string> channels{"INITIAL_POSE", "BEACONS", "ODOMETRY", "ODOMETRY", "RANGE", "RANGE", "ODOMETRY"};
  const std::vector<int64_t> times{0, 0, 200, 400, 450, 550, 600};
  ASSERT_EQ(events.size(), channels.size());
  for (size_t i = 0; i < events.size(); ++i) {
    EXPECT_EQ(events[i].channel, channels[i]) << i;
    EXPECT_EQ(events[i].timestamp, times[i]) << i;
  }
  EXPECT_EQ(decode<roam::range_t>(events[4]).utime, 200);
  EXPECT_EQ(decode<roam::range_t>(events[5]).utime, 300);
  // From the command line; a negative latency is refused with the option's name.
  const std::string sim = roam_test::tool("roam-sim");
  const roam_test::ToolResult ok =
      roam_test::runTool(sim + " -o " + dir.file("sim.lcmlog") + " --steps 50 --schedule round_robin --range-latency-s 0.5");
  EXPECT_EQ(ok.status, 0) << ok.out;
  const std::vector<Event> simulated = readEvents(dir.file("sim.lcmlog"));
  int ranges = 0;
  for (const Event& e : simulated)
    if (e.channel == "RANGE") {
      ++ranges;
      EXPECT_EQ(e.timestamp, decode<roam::range_t>(e).utime + 500000);
    }
  EXPECT_EQ(ranges, 20);  // 10 s at 2 Hz
  const roam_test::ToolResult bad = roam_test::runTool(sim + " -o " + dir.file("x.lcmlog") + " --range-latency-s -1");
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.out.find("--range-latency-s: expected in [0, 3600]"), std::string::npos) << bad.out;
}

TEST(DatasetLog, UnwritablePathIsNamed) {
  try {
    roam::writeDatasetLog("/nonexistent-folder/x.lcmlog", roam::Dataset{});
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "/nonexistent-folder/x.lcmlog: cannot open for writing");
  }
}

std::string bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(Plaza1Logs, AreWhatTheImportWritesToday) {
  ROAM_REQUIRE_DATA(kPlaza1);
  roam_test::ScratchDir dir;
  roam::writeDatasetLog(dir.file("a.lcmlog"), roam::loadCsvDataset(kPlaza1));
  roam::CsvImportOptions drpath;
  drpath.odometry_from_path = kPlaza1 + "/dead_reckoning_path.csv";
  roam::writeDatasetLog(dir.file("b.lcmlog"), roam::loadCsvDataset(kPlaza1, drpath));
  EXPECT_TRUE(bytes(dir.file("a.lcmlog")) == bytes(kSource + "/logs/plaza1.lcmlog"));
  EXPECT_TRUE(bytes(dir.file("b.lcmlog")) == bytes(kSource + "/logs/plaza1-drpath.lcmlog"));
}

// Dead reckoning by hand from the log's own INITIAL_POSE and ODOMETRY, each pose compared with the
// GROUND_TRUTH event of the same time stamp (the README's "GT row nearest in time").
struct DeadReckoningErrors {
  double mean_m = 0, rmse_m = 0, final_m = 0;
  size_t compared = 0;
};

DeadReckoningErrors deadReckoning(const std::string& log_path) {
  double x = 0, y = 0, heading = 0;
  std::vector<std::pair<int64_t, std::pair<double, double>>> estimate, truth;
  for (const Event& e : readEvents(log_path)) {
    if (e.channel == "INITIAL_POSE") {
      const auto p = decode<roam::pose_t>(e);
      x = p.x;
      y = p.y;
      heading = p.heading;
      estimate.push_back({p.utime, {x, y}});
    } else if (e.channel == "ODOMETRY") {
      const auto o = decode<roam::odometry_t>(e);
      x += o.delta_distance * std::cos(heading);
      y += o.delta_distance * std::sin(heading);
      heading += o.delta_heading;
      estimate.push_back({o.utime, {x, y}});
    } else if (e.channel == "GROUND_TRUTH") {
      const auto p = decode<roam::pose_t>(e);
      truth.push_back({p.utime, {p.x, p.y}});
    }
  }
  DeadReckoningErrors r;
  EXPECT_EQ(estimate.size(), truth.size());
  double sum = 0, sum_sq = 0, last = 0;
  for (size_t i = 0; i < std::min(estimate.size(), truth.size()); ++i) {
    EXPECT_EQ(estimate[i].first, truth[i].first) << i;
    last = std::hypot(estimate[i].second.first - truth[i].second.first,
                      estimate[i].second.second - truth[i].second.second);
    sum += last;
    sum_sq += last * last;
    ++r.compared;
  }
  r.mean_m = sum / r.compared;
  r.rmse_m = std::sqrt(sum_sq / r.compared);
  r.final_m = last;
  return r;
}

TEST(Plaza1Logs, DeadReckoningGivesTheReadmeFigures) {
  // Data README, "Dead reckoning vs the paper": odometry 1.61 / 1.97 / 4.39 m (mean, RMSE,
  // final); the shipped DRp path 15.92 / 20.29 / 36.89 m.
  constexpr double kRounding = 0.005;
  const DeadReckoningErrors given = deadReckoning(kSource + "/logs/plaza1.lcmlog");
  EXPECT_EQ(given.compared, 9658u);
  EXPECT_NEAR(given.mean_m, 1.61, kRounding);
  EXPECT_NEAR(given.rmse_m, 1.97, kRounding);
  EXPECT_NEAR(given.final_m, 4.39, kRounding);
  const DeadReckoningErrors drpath = deadReckoning(kSource + "/logs/plaza1-drpath.lcmlog");
  EXPECT_NEAR(drpath.mean_m, 15.92, kRounding);
  EXPECT_NEAR(drpath.rmse_m, 20.29, kRounding);
  EXPECT_NEAR(drpath.final_m, 36.89, kRounding);
}

}  // namespace
