// roam-run's reorder window (reorder_window_s): odometry and ranges are fed in utime order even
// where the log holds them in arrival order, a range after odometry stamped later than it (a
// radio's or a modem's latency).
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "log_compare.hpp"
#include "roam/self_check.hpp"
#include "path_score.hpp"
#include "result_log.hpp"
#include "small_world.hpp"
#include "test_util.hpp"

namespace roam {
namespace {

using testing_util::run;
using testing_util::roamRun;
using testing_util::scratchDir;
using testing_util::writeFile;
namespace fs = std::filesystem;

// The estimators' outputs of a result log (the input copies, written on arrival, left out).
std::vector<testing_util::LoggedEvent> outputs(const fs::path& log) {
  std::vector<testing_util::LoggedEvent> events = testing_util::readEvents(log.string());
  events.erase(std::remove_if(events.begin(), events.end(),
                              [](const testing_util::LoggedEvent& e) {
                                for (const char* prefix : {"POSE_", "MAP_", "TRAJECTORY_", "STATUS_"})
                                  if (e.channel.rfind(prefix, 0) == 0) return false;
                                return true;
                              }),
               events.end());
  return events;
}

struct Replay {
  testing_util::CommandResult result;
  fs::path log;
};

Replay replay(const fs::path& dir, const fs::path& input, const std::string& runtime_keys, const std::string& name) {
  const std::string estimators = "[estimator.ekf]\nplugin = ekf\n[estimator.em]\nplugin = online_em\nnum_particles = 20\n";
  const fs::path config = writeFile(dir / (name + ".ini"), "[runtime]\ninput = " + input.string() + "\noutput = " +
                                                               name + ".lcmlog\n" + runtime_keys + estimators);
  return {run(roamRun() + " " + config.string() + " --no-progress"), dir / (name + ".lcmlog")};
}

void expectSameOutputs(const fs::path& a, const fs::path& b) {
  const auto first = outputs(a), second = outputs(b);
  ASSERT_GT(first.size(), 600u);  // poses of both estimators, maps, statuses, trajectories
  ASSERT_EQ(first.size(), second.size());
  for (size_t k = 0; k < first.size(); ++k) {
    ASSERT_EQ(first[k].channel, second[k].channel) << k;
    ASSERT_EQ(first[k].utime, second[k].utime) << k;
    ASSERT_EQ(first[k].data, second[k].data) << first[k].channel << " " << k;  // bit-identical
  }
}

// The small world (0.2 s steps at 1 m/s, 2 ranges a second) in time order, and with every range
// logged 0.5 s after its stamp: behind two or three odometry steps.
struct LateWorld {
  sim::SimRun world;
  fs::path in_order, late;
  int moved = 0;  // ranges logged behind later odometry
};

LateWorld makeLateWorld(const fs::path& dir) {
  LateWorld w{sim::simulate(testing_util::smallWorld()), dir / "in_order.lcmlog", dir / "late.lcmlog"};
  writeDatasetLog(w.in_order.string(), w.world);
  writeDatasetLog(w.late.string(), w.world, 500000);  // roam-sim --range-latency-s 0.5
  // Every range but the last, which is stamped at the last step: logged after it, but not behind
  // a later stamp.
  w.moved = static_cast<int>(w.world.ranges.size()) - 1;
  return w;
}


TEST(Reorder, RangesArrivingWithinTheWindowGiveTheInOrderEstimates) {
  // With the default window (1 s) the EKF and online EM publish from the late world exactly what
  // they publish from the log in time order, and nothing is said.
  const fs::path dir = scratchDir("reorder_within");
  const LateWorld w = makeLateWorld(dir);
  ASSERT_EQ(w.moved, 119);  // of its 120 ranges
  const Replay reference = replay(dir, w.in_order, "", "reference");
  const Replay delayed = replay(dir, w.late, "", "delayed");
  ASSERT_EQ(reference.result.status, 0) << reference.result.output;
  ASSERT_EQ(delayed.result.status, 0) << delayed.result.output;
  EXPECT_EQ(delayed.result.output.find("reorder_window_s"), std::string::npos) << delayed.result.output;
  expectSameOutputs(reference.log, delayed.log);
}

TEST(Reorder, WithoutTheWindowLateRangesAreFedLateCountedAndNamed) {
  // reorder_window_s = 0: arrival order, as before the window existed. Each late range meets a
  // later pose, the EKF's path fits the ranges worse (so much that the SDK's self-check publishes
  // dead reckoning in its place), and the run ends with a warning that
  // counts them, says how late the latest was and names the key.
  const fs::path dir = scratchDir("reorder_off");
  const LateWorld w = makeLateWorld(dir);
  const int moved = w.moved;
  const Replay reference = replay(dir, w.in_order, "", "reference");
  const Replay off = replay(dir, w.late, "reorder_window_s = 0\n", "off");
  ASSERT_EQ(reference.result.status, 0) << reference.result.output;
  ASSERT_EQ(off.result.status, 0) << off.result.output;
  EXPECT_NE(off.result.output.find(", " + std::to_string(moved) + " fed late (beyond reorder_window_s)"),
            std::string::npos)
      << off.result.output;
  // The ranges are 0.5 s late; odometry comes every 0.2 s, so each arrives 0.4 s behind the newest.
  EXPECT_NE(off.result.output.find("roam-run: warning: " + std::to_string(moved) +
                                   " odometry and range messages arrived up to 0.400 s (data time) behind the newest "
                                   "input, beyond reorder_window_s (0 s)"),
            std::string::npos)
      << off.result.output;
  EXPECT_NE(off.result.output.find("look at key reorder_window_s\n"), std::string::npos) << off.result.output;
  // The EKF's own path fits the ranges worse (the SDK's self-check figure, in its STATUS); here
  // worse than dead reckoning does, so the self-check publishes dead reckoning in its place.
  const ResultLog result = readResultLog(off.log.string());
  const EstimatorOutputs* ekf = result.find("ekf");
  ASSERT_NE(ekf, nullptr);
  const ResultLog in_order = readResultLog(reference.log.string());
  const EstimatorOutputs* ekf_in_order = in_order.find("ekf");
  ASSERT_NE(ekf_in_order, nullptr);
  auto diagnostic = [](const EstimatorOutputs& e, const std::string& key) {
    for (const auto& [k, v] : e.diagnostics)
      if (k == key) return v;
    return kNaN;
  };
  const double in_order_fit_m = diagnostic(*ekf_in_order, SelfCheck::kPathFit);
  const double late_fit_m = diagnostic(*ekf, SelfCheck::kPathFit);
  std::printf("EKF with ranges 0.5 s late: mean |range residual| in time order %.3f m, in arrival order %.3f m "
              "(dead reckoning %.3f m)\n", in_order_fit_m, late_fit_m, diagnostic(*ekf, SelfCheck::kDeadReckoningFit));
  EXPECT_GT(late_fit_m, in_order_fit_m + 0.01);
  EXPECT_NE(off.result.output.find("ekf self-check: its path explained the ranges worse"), std::string::npos)
      << off.result.output;
  // And counted in every STATUS: the final one of the EKF says how many were fed late.
  double fed_late = -1.0;
  for (const auto& [key, value] : ekf->diagnostics)
    if (key == "input fed late: beyond reorder_window_s") fed_late = value;
  EXPECT_EQ(fed_late, moved);
}

TEST(Reorder, AnInOrderLogIsFedAsItArrives) {
  // A log in time order (every log roam writes, Plaza 1, every simulated run) gives the same
  // outputs with the window as without it, bit for bit.
  const fs::path dir = scratchDir("reorder_in_order");
  const fs::path log = testing_util::writeSmallWorldLog(dir);
  const Replay held = replay(dir, log, "", "held");
  const Replay direct = replay(dir, log, "reorder_window_s = 0\n", "direct");
  ASSERT_EQ(held.result.status, 0) << held.result.output;
  ASSERT_EQ(direct.result.status, 0) << direct.result.output;
  EXPECT_EQ(direct.result.output.find("fed late"), std::string::npos) << direct.result.output;
  expectSameOutputs(held.log, direct.log);
}

TEST(Reorder, LogcheckSaysHowFarBehindTheLatestInputWasLogged) {
  // roam-logcheck tells a user whether a log needs the window, and how long a one.
  const LateWorld w = makeLateWorld(scratchDir("reorder_logcheck"));
  const std::string logcheck = std::string(ROAM_BINARY_DIR) + "/bin/roam-logcheck ";
  const auto checked = run(logcheck + w.late.string());
  EXPECT_EQ(checked.status, 0) << checked.output;
  EXPECT_NE(checked.output.find(std::to_string(w.moved) +
                                " ODOMETRY and RANGE events logged behind an input stamped later, by up to 0.400 s: "
                                "roam-run feeds them in time order if its reorder_window_s (default 1 s) is longer\n"),
            std::string::npos)
      << checked.output;
  const auto clean = run(logcheck + w.in_order.string());
  EXPECT_EQ(clean.status, 0) << clean.output;
  EXPECT_EQ(clean.output.find("behind"), std::string::npos) << clean.output;
}

TEST(Reorder, ANegativeWindowIsRefusedWithItsKey) {
  const fs::path dir = scratchDir("reorder_negative");
  const fs::path log = testing_util::writeSmallWorldLog(dir);
  const Replay bad = replay(dir, log, "reorder_window_s = -1\n", "bad");
  EXPECT_EQ(bad.result.status, 2) << bad.result.output;
  EXPECT_NE(bad.result.output.find("[runtime] reorder_window_s"), std::string::npos) << bad.result.output;
}

}  // namespace
}  // namespace roam
