#include "replay.hpp"

#include "log_sink.hpp"

#include <sys/stat.h>

#include <chrono>
#include <cstdio>
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <stdexcept>
#include <vector>

namespace roam {
namespace runtime {
namespace {

// The on-disk size of an event: sync word, event number, timestamp, two lengths, payload.
int64_t eventBytes(const lcm::LogEvent& event) {
  return 4 + 8 + 8 + 4 + 4 + static_cast<int64_t>(event.channel.size()) + event.datalen;
}

class ProgressBar {
 public:
  ProgressBar(bool enabled, int64_t total_bytes)
      : enabled_(enabled), total_(total_bytes), start_(Clock::now()), last_(start_) {}
  void update(int64_t done_bytes) {
    if (!enabled_ || total_ <= 0) return;
    const auto now = Clock::now();
    if (now - start_ < std::chrono::seconds(1) || now - last_ < std::chrono::milliseconds(100)) return;
    last_ = now;
    const double fraction = static_cast<double>(done_bytes) / static_cast<double>(total_);
    const int width = 40;
    const int filled = static_cast<int>(fraction * width);
    std::fprintf(stderr, "\r[%-*s] %5.1f%%", width, std::string(static_cast<size_t>(filled), '#').c_str(),
                 100.0 * fraction);
    drawn_ = true;
  }
  ~ProgressBar() {
    if (drawn_) std::fprintf(stderr, "\r%*s\r", 50, "");
  }

 private:
  using Clock = std::chrono::steady_clock;
  bool enabled_;
  int64_t total_;
  Clock::time_point start_, last_;
  bool drawn_ = false;
};

// Moves the reader to the next sync word at or after `from`; false if there is none.
bool resynchronise(FILE* file, int64_t from) {
  if (std::fseek(file, static_cast<long>(from), SEEK_SET) != 0) return false;
  uint32_t window = 0;
  int64_t position = from;
  for (int c = std::fgetc(file); c != EOF; c = std::fgetc(file), ++position) {
    window = (window << 8) | static_cast<uint32_t>(c);
    if (position - from >= 3 && window == kLogSyncWord) {
      return std::fseek(file, static_cast<long>(position - 3), SEEK_SET) == 0;
    }
  }
  return false;
}

// One whole event read straight from the bytes at `offset`. LCM's reader also refuses an intact
// event when the header *after* it is damaged ("Invalid header after log data"); this takes
// that event anyway. False if the bytes at `offset` are not a whole, plausible event.
struct RawEvent {
  std::string channel;
  int64_t timestamp = 0;
  std::vector<uint8_t> data;
  int64_t end = 0;
};

bool readEventAt(FILE* file, int64_t offset, int64_t file_size, RawEvent* event) {
  constexpr int kHeaderBytes = 4 + 8 + 8 + 4 + 4;
  constexpr int32_t kMaxChannelLength = 1000;  // LCM's own limit
  uint8_t header[kHeaderBytes];
  if (offset + kHeaderBytes > file_size || std::fseek(file, static_cast<long>(offset), SEEK_SET) != 0 ||
      std::fread(header, 1, kHeaderBytes, file) != kHeaderBytes) {
    return false;
  }
  auto big = [&](int at, int bytes) {
    uint64_t value = 0;
    for (int i = 0; i < bytes; ++i) value = (value << 8) | header[at + i];
    return value;
  };
  const int32_t channel_length = static_cast<int32_t>(big(20, 4));
  const int32_t data_length = static_cast<int32_t>(big(24, 4));
  if (big(0, 4) != kLogSyncWord || channel_length <= 0 || channel_length >= kMaxChannelLength ||
      data_length < 0 || offset + kHeaderBytes + channel_length + data_length > file_size) {
    return false;
  }
  event->timestamp = static_cast<int64_t>(big(12, 8));
  event->channel.resize(static_cast<size_t>(channel_length));
  event->data.resize(static_cast<size_t>(data_length));
  if (std::fread(&event->channel[0], 1, event->channel.size(), file) != event->channel.size() ||
      std::fread(event->data.data(), 1, event->data.size(), file) != event->data.size()) {
    return false;
  }
  event->end = offset + kHeaderBytes + channel_length + data_length;
  return true;
}

}  // namespace

std::string ReplayReport::damage() const {
  std::string text;
  if (bytes_skipped > 0) {
    text += std::to_string(bytes_skipped) + " corrupt bytes skipped";
  }
  if (damaged_tail) {
    if (!text.empty()) text += "; ";
    text += "the log ends inside an event (cut or corrupt): replayed up to there";
  }
  return text;
}

void checkInputLog(const std::string& path) {
  struct stat info {};
  if (stat(path.c_str(), &info) != 0) throw std::runtime_error(path + ": cannot open the input log");
  if (S_ISDIR(info.st_mode)) throw std::runtime_error(path + ": a folder, not an LCM log (roam-import turns a CSV folder into one)");
  if (info.st_size == 0) throw std::runtime_error(path + ": empty file: not an LCM log (no event to replay)");
  std::unique_ptr<FILE, int (*)(FILE*)> file(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!file) throw std::runtime_error(path + ": cannot open the input log");
  const int64_t size = static_cast<int64_t>(info.st_size);
  // The first whole event at or after each sync word; a damaged head is skipped as replay does.
  for (int64_t offset = 0;;) {
    RawEvent event;
    if (readEventAt(file.get(), offset, size, &event)) return;
    if (!resynchronise(file.get(), offset + 1)) break;
    offset = static_cast<int64_t>(std::ftell(file.get()));
  }
  throw std::runtime_error(path + ": not an LCM log (no event could be read; roam-import turns CSV and pyfg runs into logs)");
}

ReplayReport replayLog(const std::string& path, Host& host, const std::atomic<bool>& stop,
                       bool progress) {
  struct stat info {};
  if (stat(path.c_str(), &info) != 0) throw std::runtime_error(path + ": cannot open the input log");
  lcm::LogFile log(path, "r");
  if (!log.good()) throw std::runtime_error(path + ": cannot open the input log");
  const int64_t size = static_cast<int64_t>(info.st_size);
  ReplayReport report;
  ProgressBar bar(progress, size);
  int64_t expected_start = 0;
  while (!stop.load()) {
    const lcm::LogEvent* event = log.readNextEvent();
    if (event == nullptr) {
      if (expected_start >= size) break;
      RawEvent raw;
      if (readEventAt(log.getFilePtr(), expected_start, size, &raw)) {
        // An intact event followed by damage: replay it, then look for the next event.
        expected_start = raw.end;
        ++report.events;
        host.onEvent(raw.channel, raw.timestamp, raw.data.data(), static_cast<int>(raw.data.size()));
        if (!resynchronise(log.getFilePtr(), expected_start)) break;
        const int64_t resumed = static_cast<int64_t>(std::ftell(log.getFilePtr()));
        report.bytes_skipped += resumed - expected_start;
        expected_start = resumed;
        continue;
      }
      // LCM's reader stops at a bad header; look for the next event after the last good one.
      if (!resynchronise(log.getFilePtr(), expected_start + 1)) break;
      const int64_t resumed = static_cast<int64_t>(std::ftell(log.getFilePtr()));
      report.bytes_skipped += resumed - expected_start;
      expected_start = resumed;
      continue;
    }
    const int64_t end = static_cast<int64_t>(std::ftell(log.getFilePtr()));
    const int64_t start = end - eventBytes(*event);
    if (start > expected_start) report.bytes_skipped += start - expected_start;
    expected_start = end;
    ++report.events;
    host.onEvent(event->channel, event->timestamp, event->data, event->datalen);
    bar.update(end);
  }
  report.interrupted = stop.load();
  if (!report.interrupted && expected_start < size) report.damaged_tail = true;
  return report;
}

}  // namespace runtime
}  // namespace roam
