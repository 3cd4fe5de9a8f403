// Deterministic replay of a log file through the host, as fast as the CPU allows.
#pragma once

#include <atomic>
#include <cstdint>
#include <string>

#include "host.hpp"

namespace roam {
namespace runtime {

struct ReplayReport {
  int64_t events = 0;
  int64_t bytes_skipped = 0;  // corrupt bytes the reader resynchronised over
  bool damaged_tail = false;  // the log ends inside an event (cut or corrupt)
  bool interrupted = false;   // stopped by a signal
  std::string damage() const;  // "" if the log was whole
};

// Reads every event of `path` in file order and hands it to the host (which copies it to
// the result log). Stops early when *stop becomes true. Throws std::runtime_error if the file
// cannot be opened. A progress bar goes to stderr if `progress` and the replay takes > 1 s.
// Throws std::runtime_error naming `path` unless it can be opened and holds at least one whole
// LCM event: an empty file, a text file or a pyfg file is refused before any output is opened.
void checkInputLog(const std::string& path);

ReplayReport replayLog(const std::string& path, Host& host, const std::atomic<bool>& stop,
                       bool progress);

}  // namespace runtime
}  // namespace roam
