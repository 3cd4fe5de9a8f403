#include "dataset_log.hpp"

#include <algorithm>
#include <lcm/lcm-cpp.hpp>
#include <stdexcept>
#include <tuple>
#include <vector>

#include "roam/messages.hpp"
#include "roam/plugin_shim.hpp"
#include "roam/robot_range_t.hpp"

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

enum class Source { kGroundTruth = 0, kOdometry = 1, kRange = 2, kRobotRange = 3 };  // the tie order

struct Item {
  int64_t utime;
  Source source;
  size_t index;
  int robot = 0;  // a team's member (team order breaks ties after the source)
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
      case Source::kRobotRange:  // a team's alone
        break;
    }
  }
  summary.events = log.events();
  return summary;
}

TeamLogWriteSummary writeTeamLog(const std::string& path, const TeamDataset& team) {
  const size_t n = team.robots.size();
  if (team.members.size() != n)
    throw std::invalid_argument(path + ": a team of " + std::to_string(n) + " names and " +
                                std::to_string(team.members.size()) + " members");
  if (n == 0) throw std::invalid_argument(path + ": a team without robots");
  std::vector<Item> items;
  for (size_t r = 0; r < n; ++r) {
    const Dataset& d = team.members[r];
    const int robot = static_cast<int>(r);
    for (size_t i = 0; i < d.ground_truth.size(); ++i) items.push_back({d.ground_truth[i].utime, Source::kGroundTruth, i, robot});
    for (size_t i = 0; i < d.odometry.size(); ++i) items.push_back({d.odometry[i].utime, Source::kOdometry, i, robot});
    for (size_t i = 0; i < d.ranges.size(); ++i) items.push_back({d.ranges[i].utime, Source::kRange, i, robot});
  }
  for (size_t i = 0; i < team.robot_ranges.size(); ++i) {
    const Range& range = team.robot_ranges[i];
    const int size = static_cast<int>(n);
    if (range.robot < 0 || range.robot >= size || range.other_robot < 0 || range.other_robot >= size ||
        range.robot == range.other_robot)
      throw std::invalid_argument(path + ": robot range " + std::to_string(i) + " is between robots " +
                                  std::to_string(range.robot) + " and " + std::to_string(range.other_robot) +
                                  " of a team of " + std::to_string(n));
    items.push_back({range.utime, Source::kRobotRange, i, range.robot});
  }
  std::stable_sort(items.begin(), items.end(), [](const Item& a, const Item& b) {
    return std::make_tuple(a.utime, static_cast<int>(a.source), a.robot) <
           std::make_tuple(b.utime, static_cast<int>(b.source), b.robot);
  });

  int64_t first_utime = team.members[0].start.utime;
  for (const Dataset& d : team.members) first_utime = std::min(first_utime, d.start.utime);
  LogOut log(path);
  TeamLogWriteSummary summary;
  summary.members.resize(n);
  summary.robot_ranges.assign(n, 0);
  summary.beacons = static_cast<long>(team.beacons.size());
  for (size_t r = 0; r < n; ++r) {
    log.write(teamChannel(channels::INITIAL_POSE, team.robots[r]), first_utime, toMessage(shim::toC(team.members[r].start)));
    summary.members[r].beacons = summary.beacons;
  }
  log.write(channels::BEACONS, first_utime, toMessage(shim::toC(team.beacons), first_utime));
  for (const Item& item : items) {
    const std::string& name = team.robots[static_cast<size_t>(item.robot)];
    const Dataset& d = team.members[static_cast<size_t>(item.robot)];
    LogWriteSummary& counts = summary.members[static_cast<size_t>(item.robot)];
    switch (item.source) {
      case Source::kGroundTruth:
        log.write(teamChannel(channels::GROUND_TRUTH, name), item.utime, toMessage(shim::toC(d.ground_truth[item.index])));
        ++counts.ground_truth;
        break;
      case Source::kOdometry:
        log.write(teamChannel(channels::ODOMETRY, name), item.utime, toMessage(shim::toC(d.odometry[item.index])));
        ++counts.odometry;
        break;
      case Source::kRange:
        log.write(teamChannel(channels::RANGE, name), item.utime, toMessage(shim::toC(d.ranges[item.index])));
        ++counts.ranges;
        break;
      case Source::kRobotRange: {
        const Range& range = team.robot_ranges[item.index];
        roam::robot_range_t message;
        message.utime = range.utime;
        message.other_robot = team.robots[static_cast<size_t>(range.other_robot)];
        message.range = range.range_m;
        message.sigma = range.sigma_m;
        log.write(teamChannel(channels::ROBOT_RANGE, name), item.utime, message);
        ++summary.robot_ranges[static_cast<size_t>(item.robot)];
        break;
      }
    }
  }
  for (size_t r = 0; r < n; ++r)
    summary.members[r].events = summary.members[r].ground_truth + summary.members[r].odometry + summary.members[r].ranges +
                                summary.robot_ranges[r] + 1;  // + its INITIAL_POSE
  summary.events = log.events();
  return summary;
}

}  // namespace roam
