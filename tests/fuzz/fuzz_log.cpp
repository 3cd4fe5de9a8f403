// Fuzz target: reading LCM logs — roam-run's replay and roam-eval's readResultLog.
//
// The bytes are an input log. As roam-run does, it is replayed through a Host running the
// deadreckoning plugin, with the input events and the outputs written to a result log
// (LogSink); then readResultLog reads the input and the result log.
// Expected: the replay ends (corrupt bytes skipped, a cut tail reported), and the result log
// roam wrote is always whole: every event written (the input events the replay delivered, as
// they came, plus the outputs) reads back. Anything else (a crash, a hang, a sanitizer report, an
// exception other than readResultLog's std::runtime_error for an unreadable file) is a finding.
#include <atomic>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>

#include "fuzz_util.hpp"
#include "host.hpp"
#include "log_sink.hpp"
#include "plugin_library.hpp"
#include "replay.hpp"
#include "result_log.hpp"

using namespace roam::runtime;

namespace {

// Counts what the host writes, so the result log can be checked against it.
class CountingSink : public Sink {
 public:
  explicit CountingSink(Sink* next) : next_(next) {}
  void write(const std::string& channel, int64_t utime, const void* data, int size) override {
    ++events;
    next_->write(channel, utime, data, size);
  }
  long events = 0;

 private:
  Sink* next_;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  roam::fuzz::pinPlugins();
  static const auto library = PluginLibrary::open(roam::fuzz::pluginDir(), "deadreckoning");
  const std::string input = roam::fuzz::writeScratch("input.lcmlog", data, size);
  const std::string output = (roam::fuzz::scratchDir() / "result.lcmlog").string();

  RunConfig config;
  config.input = input;
  config.output = output;
  EstimatorSection section;
  section.name = "dr";
  section.plugin = "deadreckoning";
  section.pose_channel = "POSE_DR";
  section.map_channel = "MAP_DR";
  section.trajectory_channel = "TRAJECTORY_DR";
  section.status_channel = "STATUS_DR";
  config.estimators.push_back(section);
  std::vector<EstimatorSlot> slots(1);
  slots[0].section = section;
  slots[0].instance = std::make_unique<PluginInstance>(library, "dr", roam::KeyValues{});

  ReplayReport report;
  long written = 0;
  {
    LogSink log(output);
    CountingSink counting(&log);
    Host host(config, std::move(slots), &counting, &counting);
    const std::atomic<bool> stop{false};
    report = replayLog(input, host, stop, /*progress=*/false);
    host.finish();
    (void)host.summary();
    (void)report.damage();
    written = counting.events;
    ROAM_FUZZ_CHECK(report.events == host.counters().events, "the host saw a different number of events");
    ROAM_FUZZ_CHECK(!host.anyFailed(), "deadreckoning failed on a replayed log: " +
                                           host.estimators()[0].instance->error());
  }

  const roam::ResultLog result = roam::readResultLog(output);
  // Every event written reads back (input events are copied as they came, so an undecodable
  // input event is still undecodable there: readResultLog's `skipped` may count those).
  ROAM_FUZZ_CHECK(result.events == written, "the result log lost events");
  ROAM_FUZZ_CHECK(result.find("dr") != nullptr, "no dr outputs in the result log");
  try {
    const roam::ResultLog read = roam::readResultLog(input);
    ROAM_FUZZ_CHECK(read.events <= report.events + 1, "readResultLog found more events than the replay");
  } catch (const std::runtime_error&) {
    // an input that is not a log at all: readResultLog says so
  }
  return 0;
}
