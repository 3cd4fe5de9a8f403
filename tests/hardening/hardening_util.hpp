// Helpers for the bad-input tests: a clean input log as a list of events to damage, a
// roam-run over it with every plugin of the build, and what came out.
//
// Every test runs roam-run as a user would, with one [estimator.<plugin>] per plugin found in
// <build>/lib/roam/plugins (default config), so the tests grow as plugins land.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "roam/types.hpp"

namespace roam {
namespace hardening {

namespace fs = std::filesystem;

struct Event {
  std::string channel;
  int64_t utime = 0;
  std::string bytes;  // the LCM-encoded message (or garbage)
};
using Events = std::vector<Event>;

// roam::sim, seed 7: 300 odometry steps (0.2 m, 0.2 s each; lawn mower), 4 beacons ranged
// round robin at 2 Hz, in writeDatasetLog's event order (INITIAL_POSE, BEACONS, then
// GROUND_TRUTH / ODOMETRY / RANGE by time).
Events cleanEvents();
void writeLog(const fs::path& path, const Events& events);
// Indices of the events on `channel`, in log order.
std::vector<size_t> indicesOf(const Events& events, const std::string& channel);

// Decodes an event as Message, lets `change` modify it, re-encodes it.
template <typename Message, typename Change>
void modify(Event* event, Change&& change) {
  Message message{};  // value-initialised: a decode that fails leaves zeros, not garbage
  message.decode(event->bytes.data(), 0, static_cast<int>(event->bytes.size()));
  change(message);
  event->bytes.assign(static_cast<size_t>(message.getEncodedSize()), '\0');
  message.encode(&event->bytes[0], 0, static_cast<int>(event->bytes.size()));
}

// Plugin names (libroam_<name>.so) in the build's plugin folder, sorted.
std::vector<std::string> pluginsInBuild();

// The last STATUS_<NAME> of an estimator.
struct Status {
  std::string state;  // initializing | tracking | finished | failed
  int64_t odometry_accepted = 0, odometry_rejected = 0, ranges_accepted = 0, ranges_rejected = 0;
  std::string last_rejection, last_error;
  std::map<std::string, double> values;  // "rejected range: not finite" -> 3, ...
  double value(const std::string& key) const {
    const auto it = values.find(key);
    return it == values.end() ? 0.0 : it->second;
  }
};

struct RunResult {
  int exit_status = -1;
  std::string output;                        // roam-run's stdout and stderr
  std::map<std::string, Status> status;      // by estimator name
  std::map<std::string, Path> poses;         // POSE_<NAME>, by estimator name
  std::map<std::string, Path> trajectory;    // the last TRAJECTORY_<NAME>
  std::map<std::string, long> events;        // events per channel in the result log
  bool result_log_whole = false;             // every event of the result log decodes
  // The end-summary line of an estimator ("" if none).
  std::string summaryLine(const std::string& estimator) const;
};

// Writes `events` as <dir>/input.lcmlog (unless `raw_log` is given: then those bytes are the
// log), a config with every plugin (plus `plugin_keys` in each section, e.g. "max_range_m = 50\n",
// and `runtime_keys` under [runtime]) and runs roam-run on it, the output in <dir>/result.lcmlog.
RunResult runEveryPlugin(const std::string& test_name, const Events& events,
                         const std::string& plugin_keys = "", const std::string& runtime_keys = "",
                         const std::string* raw_log = nullptr);

// The checks every bad-input run must pass, for every plugin: roam-run exits 0, no estimator
// failed, every published pose and path is finite, and the result log reads back whole with
// every input event copied into it (`input` events per input channel).
void expectSafeRun(const RunResult& result, const std::map<std::string, long>& input_events);
std::map<std::string, long> countByChannel(const Events& events);

}  // namespace hardening
}  // namespace roam
