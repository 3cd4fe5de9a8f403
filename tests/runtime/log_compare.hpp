// Comparing result logs event by event: channel, event time and payload bytes, with the only
// fields that differ between two runs of the same replay zeroed: the times measured on the clock
// in STATUS_* (cpu_total_s, cpu_last_update_s, and plugin diagnostics named *_time_s, such as
// spectral_batch's solver_time_s).
#pragma once

#include <lcm/lcm-cpp.hpp>
#include <string>
#include <vector>

#include "roam/estimator_status_t.hpp"

namespace roam {
namespace testing_util {

struct LoggedEvent {
  std::string channel;
  int64_t utime = 0;
  std::string data;
};

inline bool endsWith(const std::string& text, const std::string& suffix) {
  return text.size() >= suffix.size() && text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// Every event of `path` in order, STATUS_* CPU times zeroed; channels ending in `_<skip_suffix>`
// (one estimator's outputs) left out when skip_suffix is not empty.
inline std::vector<LoggedEvent> readEvents(const std::string& path, const std::string& skip_suffix = "") {
  std::vector<LoggedEvent> events;
  lcm::LogFile log(path, "r");
  if (!log.good()) return events;
  for (const lcm::LogEvent* event = log.readNextEvent(); event != nullptr; event = log.readNextEvent()) {
    if (!skip_suffix.empty() && endsWith(event->channel, "_" + skip_suffix)) continue;
    LoggedEvent out{event->channel, event->timestamp,
                    std::string(static_cast<const char*>(event->data), static_cast<size_t>(event->datalen))};
    if (event->channel.rfind("STATUS_", 0) == 0) {
      roam::estimator_status_t status;
      if (status.decode(event->data, 0, event->datalen) == event->datalen) {
        status.cpu_total_s = 0.0;
        status.cpu_last_update_s = 0.0;
        for (size_t k = 0; k < status.keys.size() && k < status.values.size(); ++k) {
          if (endsWith(status.keys[k], "_time_s")) status.values[k] = 0.0;
        }
        out.data.resize(static_cast<size_t>(status.getEncodedSize()));
        status.encode(&out.data[0], 0, status.getEncodedSize());
      }
    }
    events.push_back(std::move(out));
  }
  return events;
}

// Copies the events of `source` within `seconds` of its first event's time to `target` (a cut of a
// real log: the same channels, rates and messages, in less replay time). True if it wrote any.
inline bool writeLogPrefix(const std::string& source, const std::string& target, double seconds) {
  lcm::LogFile in(source, "r");
  lcm::LogFile out(target, "w");
  if (!in.good() || !out.good()) return false;
  int64_t first = 0;
  bool any = false;
  for (const lcm::LogEvent* event = in.readNextEvent(); event != nullptr; event = in.readNextEvent()) {
    if (!any) first = event->timestamp;
    if (static_cast<double>(event->timestamp - first) > seconds * 1e6) break;
    lcm::LogEvent copy = *event;
    out.writeEvent(&copy);
    any = true;
  }
  return any;
}

// "" if the two sequences are identical, else where they first differ.
inline std::string firstDifference(const std::vector<LoggedEvent>& a, const std::vector<LoggedEvent>& b) {
  for (size_t i = 0; i < a.size() && i < b.size(); ++i) {
    if (a[i].channel != b[i].channel || a[i].utime != b[i].utime || a[i].data != b[i].data) {
      return "event " + std::to_string(i) + ": " + a[i].channel + " at " + std::to_string(a[i].utime) + " vs " +
             b[i].channel + " at " + std::to_string(b[i].utime) +
             (a[i].data != b[i].data ? " (payloads differ)" : "");
    }
  }
  if (a.size() != b.size()) return "lengths differ: " + std::to_string(a.size()) + " vs " + std::to_string(b.size());
  return "";
}

}  // namespace testing_util
}  // namespace roam
