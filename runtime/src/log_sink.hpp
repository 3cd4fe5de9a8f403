// A Sink that appends events to an LCM log file.
//
// Each event is encoded in memory (LCM log format: sync word 0xEDA1DA01, event number,
// timestamp, channel and data lengths, channel, data; big-endian) and written with a single
// write(2), so the file on disk only ever holds whole events: a run stopped at any moment,
// even by a second Ctrl-C that exits at once, leaves a readable log.
//
// A write that fails (a full disk, a file that cannot grow) is cut back to the end of the last
// whole event, so the log stays readable, and the sink fails: it says why and where (path, how many
// events are intact), sets the stop flag it was given, and writes nothing more. A log removed
// during the run (the file or its folder) is noticed every 1024 events and at flush().
#pragma once

#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

#include "host.hpp"

namespace roam {
namespace runtime {

// The LCM log format's sync word, first in every event.
constexpr uint32_t kLogSyncWord = 0xEDA1DA01u;

class LogSink : public Sink {
 public:
  // Throws std::runtime_error if the file cannot be created.
  explicit LogSink(const std::string& path);
  ~LogSink() override;
  LogSink(const LogSink&) = delete;
  LogSink& operator=(const LogSink&) = delete;

  void write(const std::string& channel, int64_t utime, const void* data, int size) override;
  // Asks the kernel to put the data on disk (fsync), and checks the file is still there.
  void flush();
  int64_t events() const { return events_; }
  // Set to true when the log fails (the run's stop flag).
  void stopOnFailure(std::atomic<bool>* stop) { stop_ = stop; }
  bool failed() const { return !error_.empty(); }
  // "PATH: cannot write the output log: No space left on device; the N events before it are intact"
  const std::string& error() const { return error_; }

 private:
  void fail(const std::string& why);
  void checkStillThere();

  int fd_ = -1;
  std::string path_;
  int64_t events_ = 0;
  int64_t bytes_ = 0;  // the end of the last whole event
  std::vector<uint8_t> buffer_;
  std::string error_;
  std::atomic<bool>* stop_ = nullptr;
};

// Sends every event to several sinks.
class TeeSink : public Sink {
 public:
  void add(Sink* sink) { sinks_.push_back(sink); }
  void write(const std::string& channel, int64_t utime, const void* data, int size) override {
    for (Sink* sink : sinks_) sink->write(channel, utime, data, size);
  }

 private:
  std::vector<Sink*> sinks_;
};

}  // namespace runtime
}  // namespace roam
