// Live-mode faults. The quiet-bus warning: a channel with no message for idle_warning_s is
// reported once (which channel, since when), and again when it resumes. A slow in-process
// estimator: the backlog it causes is reported with its name, and max_update_s fails it. The bus
// is LCM's file provider playing a log in real time.
#include <gtest/gtest.h>

#include <lcm/lcm-cpp.hpp>

#include "live.hpp"
#include "sanitizer_skip.hpp"
#include "roam/odometry_t.hpp"
#include "test_util.hpp"

namespace roam {
namespace {

using testing_util::run;
using testing_util::roamRun;
using testing_util::scratchDir;
using testing_util::writeFile;
namespace fs = std::filesystem;

size_t count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// ODOMETRY messages at these times (ms after data time 1000 s); never a RANGE.
fs::path writeOdometryLog(const fs::path& path, const std::vector<int64_t>& times_ms) {
  lcm::LogFile log(path.string(), "w");
  const int64_t start_us = 1'000'000'000;
  for (const int64_t at_ms : times_ms) {
    roam::odometry_t message{};
    message.utime = start_us + at_ms * 1000;
    message.delta_distance = 0.1;
    std::vector<uint8_t> bytes(static_cast<size_t>(message.getEncodedSize()));
    message.encode(bytes.data(), 0, message.getEncodedSize());
    lcm::LogEvent event{};
    event.timestamp = message.utime;
    event.channel = "ODOMETRY";
    event.datalen = static_cast<int32_t>(bytes.size());
    event.data = bytes.data();
    log.writeEvent(&event);
  }
  return path;
}

TEST(QuietBus, AQuietChannelIsReportedOnceAndItsReturnToo) {
  ROAM_SKIP_UNDER_SANITIZERS("live mode's LCM C++ subscription trips UBSan inside LCM's header");
  const fs::path dir = scratchDir("quiet_bus");
  // Quiet from 0.2 s to 1.6 s.
  const fs::path log = writeOdometryLog(dir / "gappy.lcmlog", {0, 100, 200, 1600, 1700});
  const fs::path config = writeFile(dir / "run.ini", "[runtime]\ninput = file://" + log.string() +
                                                         "?speed=1\nidle_warning_s = 0.7\n"
                                                         "plugin_path = " ROAM_TEST_PLUGIN_DIR "\n"
                                                         "[estimator.dr]\nplugin = deadreckoning\n");
  const auto result = run(roamRun() + " " + config.string() + " --duration 2.5");
  EXPECT_EQ(result.status, 0) << result.output;
  // ODOMETRY: quiet from 0.2 s to 1.6 s, warned once at ~0.9 s; data time of the last: 1000.200 s.
  EXPECT_EQ(count(result.output, "roam-run: warning: no message on ODOMETRY for "), 1u) << result.output;
  EXPECT_NE(result.output.find("the last had data time 1000.200 s)"), std::string::npos) << result.output;
  EXPECT_EQ(count(result.output, "roam-run: ODOMETRY resumed after 1."), 1u) << result.output;
  // RANGE: never a message, one warning for the whole run.
  EXPECT_EQ(count(result.output, "roam-run: warning: no message on RANGE since the start (0."), 1u) << result.output;
  EXPECT_EQ(count(result.output, "RANGE resumed"), 0u) << result.output;
}

TEST(LiveFault, ASlowInProcessEstimatorIsReportedWithTheBacklogAndStoppedByMaxUpdate) {
  ROAM_SKIP_UNDER_SANITIZERS("live mode's LCM C++ subscription trips UBSan inside LCM's header");
  const fs::path dir = scratchDir("live_slow");
  std::vector<int64_t> times_ms;
  for (int64_t t = 0; t <= 3000; t += 100) times_ms.push_back(t);
  const fs::path log = writeOdometryLog(dir / "steady.lcmlog", times_ms);
  // The third step takes 1.5 s in process: that message is handled 1.5 s after it arrived.
  const fs::path config = writeFile(dir / "run.ini", "[runtime]\ninput = file://" + log.string() +
                                                         "?speed=1\nidle_warning_s = 0\n"
                                                         "plugin_path = " ROAM_TEST_PLUGIN_DIR "\n"
                                                         "[estimator.dr]\nplugin = deadreckoning\n"
                                                         "[estimator.slow]\nplugin = hangs\nfail_after = 2\n"
                                                         "hang_s = 1.5\nmax_update_s = 1\n");
  const auto result = run(roamRun() + " " + config.string() + " --duration 4");
  EXPECT_EQ(result.status, 1) << result.output;
  EXPECT_NE(result.output.find("roam-run: warning: live backlog: a message on ODOMETRY was handled 1."), std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("the slowest estimator on it: 'slow' (1.5"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("roam-run: estimator 'slow' failed: add_odometry: took 1.5"), std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("over max_update_s = 1 s"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("dr                     deadreckoning   ok     poses      31"), std::string::npos)
      << result.output;
}

TEST(LiveBus, AUdpmInputAsksForAFourMegabyteReceiveBuffer) {
  // Its own outputs (a final TRAJECTORY is ~200 datagrams) share the socket's buffer with the
  // inputs; the kernel's default 208 KB dropped inputs behind them on a loaded host.
  using runtime::liveBusUrl;
  EXPECT_EQ(liveBusUrl("udpm://239.255.76.67:7667?ttl=0"), "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304");
  EXPECT_EQ(liveBusUrl("udpm://239.255.76.67:7667"), "udpm://239.255.76.67:7667?recv_buf_size=4194304");
  // The user's own size stands; other providers have no such option.
  EXPECT_EQ(liveBusUrl("udpm://239.255.76.67:7667?recv_buf_size=65536"), "udpm://239.255.76.67:7667?recv_buf_size=65536");
  EXPECT_EQ(liveBusUrl("memq://"), "memq://");
  EXPECT_EQ(liveBusUrl("file:///tmp/x.lcmlog?speed=1"), "file:///tmp/x.lcmlog?speed=1");
}

}  // namespace
}  // namespace roam
