// A Sink that appends events to an LCM log file.
//
// Each event is encoded in memory (LCM log format: sync word 0xEDA1DA01, event number,
// timestamp, channel and data lengths, channel, data; big-endian) and written with a single
// write(2), so the file on disk only ever holds whole events: a run stopped at any moment,
// even by a second Ctrl-C that exits at once, leaves a readable log.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "host.hpp"

namespace roam {
namespace runtime {

class LogSink : public Sink {
 public:
  // Throws std::runtime_error if the file cannot be created.
  explicit LogSink(const std::string& path);
  ~LogSink() override;
  LogSink(const LogSink&) = delete;
  LogSink& operator=(const LogSink&) = delete;

  void write(const std::string& channel, int64_t utime, const void* data, int size) override;
  // Asks the kernel to put the data on disk (fsync).
  void flush();
  int64_t events() const { return events_; }

 private:
  int fd_ = -1;
  std::string path_;
  int64_t events_ = 0;
  std::vector<uint8_t> buffer_;
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
