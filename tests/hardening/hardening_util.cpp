#include "hardening_util.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <sstream>

#include "../runtime/small_world.hpp"
#include "../runtime/test_util.hpp"
#include "dataset_log.hpp"
#include "result_log.hpp"
#include "roam/estimator_status_t.hpp"
#include "roam/messages.hpp"
#include "roam/plugin_shim.hpp"
#include "roam/safe_decode.hpp"
#include "sim.hpp"

namespace roam {
namespace hardening {

Events cleanEvents() {
  // One folder per process: ctest runs the tests of this suite in parallel.
  const fs::path dir = testing_util::scratchDir("hardening_clean_" + std::to_string(getpid()));
  const fs::path path = dir / "clean.lcmlog";
  writeDatasetLog(path.string(), sim::simulate(testing_util::smallWorld()));
  Events events;
  lcm::LogFile log(path.string(), "r");
  while (const lcm::LogEvent* event = log.readNextEvent()) {
    events.push_back(Event{event->channel, event->timestamp,
                           std::string(static_cast<const char*>(event->data), static_cast<size_t>(event->datalen))});
  }
  return events;
}

void writeLog(const fs::path& path, const Events& events) {
  lcm::LogFile log(path.string(), "w");
  int64_t number = 0;
  for (const Event& e : events) {
    lcm::LogEvent event;
    event.eventnum = number++;
    event.timestamp = e.utime;
    event.channel = e.channel;
    event.datalen = static_cast<int32_t>(e.bytes.size());
    event.data = const_cast<char*>(e.bytes.data());
    log.writeEvent(&event);
  }
}

std::vector<size_t> indicesOf(const Events& events, const std::string& channel) {
  std::vector<size_t> out;
  for (size_t i = 0; i < events.size(); ++i) {
    if (events[i].channel == channel) out.push_back(i);
  }
  return out;
}

std::vector<std::string> pluginsInBuild() {
  std::vector<std::string> names;
  const std::string prefix = "libroam_", suffix = ".so";
  for (const auto& entry : fs::directory_iterator(fs::path(ROAM_BINARY_DIR) / "lib/roam/plugins")) {
    const std::string file = entry.path().filename().string();
    if (file.size() > prefix.size() + suffix.size() && file.rfind(prefix, 0) == 0 &&
        file.compare(file.size() - suffix.size(), suffix.size(), suffix) == 0) {
      names.push_back(file.substr(prefix.size(), file.size() - prefix.size() - suffix.size()));
    }
  }
  std::sort(names.begin(), names.end());
  return names;
}

std::string RunResult::summaryLine(const std::string& estimator) const {
  std::istringstream lines(output);
  std::string line;
  while (std::getline(lines, line)) {
    if (line.rfind(estimator + " ", 0) == 0) return line;
  }
  return "";
}

namespace {

void readResult(const fs::path& path, RunResult* result) {
  if (!fs::exists(path)) return;
  lcm::LogFile log(path.string(), "r");
  result->result_log_whole = true;
  long end = 0;
  while (const lcm::LogEvent* event = log.readNextEvent()) {
    end = std::ftell(log.getFilePtr());
    const std::string& channel = event->channel;
    ++result->events[channel];
    bool ok = true;
    if (channel.rfind("STATUS_", 0) == 0) {
      roam::estimator_status_t m;
      if ((ok = decodeMessage(event->data, event->datalen, &m) == event->datalen)) {
        Status& s = result->status[m.estimator];
        s = Status{};
        s.state = stateName(m.state);
        s.odometry_accepted = m.odometry_accepted;
        s.odometry_rejected = m.odometry_rejected;
        s.ranges_accepted = m.ranges_accepted;
        s.ranges_rejected = m.ranges_rejected;
        s.last_rejection = m.last_rejection;
        s.last_error = m.last_error;
        for (int i = 0; i < m.num_values; ++i) s.values[m.keys[i]] = m.values[i];
      }
    } else if (channel.rfind("POSE_", 0) == 0) {
      roam::pose_t m;
      if ((ok = decodeMessage(event->data, event->datalen, &m) == event->datalen)) {
        result->poses[m.estimator].push_back(shim::fromC(fromMessage(m)));
      }
    } else if (channel.rfind("TRAJECTORY_", 0) == 0) {
      roam::trajectory_t m;
      if ((ok = decodeMessage(event->data, event->datalen, &m) == event->datalen)) {
        result->trajectory[m.estimator] = shim::fromC(fromMessage(m));
      }
    }
    if (!ok) result->result_log_whole = false;
  }
  if (end != static_cast<long>(fs::file_size(path))) result->result_log_whole = false;
}

}  // namespace

RunResult runEveryPlugin(const std::string& test_name, const Events& events, const std::string& plugin_keys,
                         const std::string& runtime_keys, const std::string* raw_log) {
  const fs::path dir = testing_util::scratchDir("hardening_" + test_name);
  const fs::path input = dir / "input.lcmlog";
  if (raw_log != nullptr) {
    std::ofstream(input, std::ios::binary) << *raw_log;
  } else {
    writeLog(input, events);
  }
  std::string config = "[runtime]\ninput = input.lcmlog\noutput = result.lcmlog\n" + runtime_keys + "\n";
  for (const auto& plugin : pluginsInBuild()) {
    config += "[estimator." + plugin + "]\nplugin = " + plugin + "\n" + plugin_keys + "\n";
  }
  testing_util::writeFile(dir / "run.ini", config);
  const auto command = testing_util::run(testing_util::roamRun() + " " + (dir / "run.ini").string() + " --no-progress");
  RunResult result;
  result.exit_status = command.status;
  result.output = command.output;
  readResult(dir / "result.lcmlog", &result);
  return result;
}

std::map<std::string, long> countByChannel(const Events& events) {
  std::map<std::string, long> counts;
  for (const Event& e : events) ++counts[e.channel];
  return counts;
}

void expectSafeRun(const RunResult& result, const std::map<std::string, long>& input_events) {
  EXPECT_EQ(result.exit_status, 0) << result.output;
  EXPECT_TRUE(result.result_log_whole) << "the result log does not read back whole";
  for (const auto& [channel, count] : input_events) {
    const auto it = result.events.find(channel);
    EXPECT_EQ(it == result.events.end() ? 0 : it->second, count) << channel << " events lost on the way";
  }
  for (const auto& plugin : pluginsInBuild()) {
    SCOPED_TRACE("plugin " + plugin);
    const auto status = result.status.find(plugin);
    ASSERT_NE(status, result.status.end()) << "no STATUS_ for " << plugin << "\n" << result.output;
    EXPECT_NE(status->second.state, "failed") << status->second.last_error;
    EXPECT_EQ(status->second.last_error, "");
    EXPECT_NE(result.summaryLine(plugin), "") << result.output;
    const auto poses = result.poses.find(plugin);
    if (poses != result.poses.end()) {
      for (const Pose& pose : poses->second) {
        ASSERT_TRUE(std::isfinite(pose.x_m) && std::isfinite(pose.y_m) && std::isfinite(pose.heading_rad))
            << "a non-finite pose at utime " << pose.utime;
      }
    }
    const auto path = result.trajectory.find(plugin);
    if (path != result.trajectory.end()) {
      for (const Pose& pose : path->second) {
        ASSERT_TRUE(std::isfinite(pose.x_m) && std::isfinite(pose.y_m)) << "a non-finite path pose";
      }
    }
  }
}

}  // namespace hardening
}  // namespace roam
