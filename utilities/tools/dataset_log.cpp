#include "dataset_log.hpp"

#include <algorithm>
#include <lcm/lcm-cpp.hpp>
#include <stdexcept>
#include <vector>

#include "roam/messages.hpp"
#include "roam/plugin_shim.hpp"

namespace roam {
namespace {

class LogOut {
 public:
  explicit LogOut(const std::string& path) : path_(path), log_(path, "w") {
    if (!log_.good()) throw std::runtime_error(path + ": cannot open for writing");
  }

  template <typename Message>
  void write(const std::string& channel, int64_t utime, const Message& message) {
    const int size = message.getEncodedSize();
    buffer_.resize(static_cast<size_t>(size));
    if (message.encode(buffer_.data(), 0, size) != size) {
      throw std::runtime_error(path_ + ": cannot encode a " + channel + " message");
    }
    lcm::LogEvent event;
    event.eventnum = events_;
    event.timestamp = utime;
    event.channel = channel;
    event.datalen = size;
    event.data = buffer_.data();
    if (log_.writeEvent(&event) != 0) throw std::runtime_error(path_ + ": write failed");
    ++events_;
  }

  long events() const { return events_; }

 private:
  std::string path_;
  lcm::LogFile log_;
  std::vector<uint8_t> buffer_;
  long events_ = 0;
};

enum class Source { kGroundTruth = 0, kOdometry = 1, kRange = 2 };  // the tie order

struct Item {
  int64_t utime;
  Source source;
  size_t index;
};

}  // namespace

LogWriteSummary writeDatasetLog(const std::string& path, const Dataset& dataset, int64_t range_latency_us) {
  std::vector<Item> items;
  items.reserve(dataset.ground_truth.size() + dataset.odometry.size() + dataset.ranges.size());
  for (size_t i = 0; i < dataset.ground_truth.size(); ++i)
    items.push_back({dataset.ground_truth[i].utime, Source::kGroundTruth, i});
  for (size_t i = 0; i < dataset.odometry.size(); ++i)
    items.push_back({dataset.odometry[i].utime, Source::kOdometry, i});
  for (size_t i = 0; i < dataset.ranges.size(); ++i)
    items.push_back({dataset.ranges[i].utime + range_latency_us, Source::kRange, i});
  std::stable_sort(items.begin(), items.end(), [](const Item& a, const Item& b) {
    if (a.utime != b.utime) return a.utime < b.utime;
    return static_cast<int>(a.source) < static_cast<int>(b.source);
  });

  LogOut log(path);
  LogWriteSummary summary;
  log.write(channels::INITIAL_POSE, dataset.start.utime, toMessage(shim::toC(dataset.start)));
  log.write(channels::BEACONS, dataset.start.utime, toMessage(shim::toC(dataset.beacons), dataset.start.utime));
  summary.beacons = static_cast<long>(dataset.beacons.size());
  for (const Item& item : items) {
    switch (item.source) {
      case Source::kGroundTruth:
        log.write(channels::GROUND_TRUTH, item.utime, toMessage(shim::toC(dataset.ground_truth[item.index])));
        ++summary.ground_truth;
        break;
      case Source::kOdometry:
        log.write(channels::ODOMETRY, item.utime, toMessage(shim::toC(dataset.odometry[item.index])));
        ++summary.odometry;
        break;
      case Source::kRange:
        log.write(channels::RANGE, item.utime, toMessage(shim::toC(dataset.ranges[item.index])));  // arrival
        ++summary.ranges;
        break;
    }
  }
  summary.events = log.events();
  return summary;
}

}  // namespace roam
