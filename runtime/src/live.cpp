#include "live.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <chrono>
#include <cstdio>
#include <lcm/lcm-cpp.hpp>

#include "quiet_bus.hpp"
#include "roam/messages.hpp"

namespace roam {
namespace runtime {
namespace {

int64_t wallUtime() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// Publishes outputs on the bus.
class BusSink : public Sink {
 public:
  explicit BusSink(lcm::LCM* bus) : bus_(bus) {}
  void write(const std::string& channel, int64_t, const void* data, int size) override {
    bus_->publish(channel, data, static_cast<unsigned int>(size));
  }

 private:
  lcm::LCM* bus_;
};

// Writes to the log with the receive (wall-clock) time as event time, like lcm-logger; the
// messages inside keep their data utimes.
class WallClockLogSink : public Sink {
 public:
  explicit WallClockLogSink(LogSink* log) : log_(log) {}
  void write(const std::string& channel, int64_t, const void* data, int size) override {
    log_->write(channel, wallUtime(), data, size);
  }

 private:
  LogSink* log_;
};

// Feeds received messages to the host and measures the lag from reception to the end of
// handling: if the estimators could not keep up, the lag would grow with the backlog. A lag over
// kBacklogWarning_s is reported (at most every kBacklogRepeat_s) with the estimator that took
// longest on that message.
class Receiver {
 public:
  Receiver(Host* host, QuietBusWatch* quiet) : host_(host), quiet_(quiet) {}
  void onMessage(const lcm::ReceiveBuffer* buffer, const std::string& channel) {
    host_->onEvent(channel, buffer->recv_utime, buffer->data, static_cast<int>(buffer->data_size));
    host_->maybeRequestTrajectories();
    quiet_->onMessage(channel, host_->receivedUtime(), std::chrono::system_clock::now());
    const int64_t now = wallUtime();
    const double lag_s = static_cast<double>(now - buffer->recv_utime) * 1e-6;
    lags_ms_.push_back(lag_s * 1e3);
    if (lag_s > kBacklogWarning_s && static_cast<double>(now - last_backlog_warning_) * 1e-6 > kBacklogRepeat_s) {
      last_backlog_warning_ = now;
      reportBacklog(channel, lag_s);
    }
  }
  void reportBacklog(const std::string& channel, double lag_s) {
    const EstimatorSlot* slowest = nullptr;
    double slowest_s = -1.0;
    for (const auto& slot : host_->estimators()) {
      const double wall_s = slot.instance->wallLastSeconds();
      if (wall_s > slowest_s) {
        slowest_s = wall_s;
        slowest = &slot;
      }
    }
    std::fprintf(stderr,
                 "roam-run: warning: live backlog: a message on %s was handled %.2f s after it arrived; the "
                 "slowest estimator on it: '%s' (%.2f s)%s\n",
                 channel.c_str(), lag_s, slowest ? slowest->section.name.c_str() : "", slowest_s,
                 slowest && slowest->section.max_update_s <= 0.0
                     ? "; max_update_s would stop it from holding up the others"
                     : "");
  }
  // "N messages; handling lag median X ms, 99th percentile Y ms, max Z ms"
  std::string lagSummary() {
    if (lags_ms_.empty()) return "no messages received";
    std::vector<double> sorted = lags_ms_;
    std::sort(sorted.begin(), sorted.end());
    auto at = [&](double q) { return sorted[static_cast<size_t>(q * static_cast<double>(sorted.size() - 1))]; };
    // Compare the first and last tenth: a growing backlog shows as a growing lag.
    const size_t tenth = std::max<size_t>(1, lags_ms_.size() / 10);
    double first = 0.0, last = 0.0;
    for (size_t i = 0; i < tenth; ++i) {
      first += lags_ms_[i];
      last += lags_ms_[lags_ms_.size() - 1 - i];
    }
    char text[256];
    std::snprintf(text, sizeof(text),
                  "%zu messages; handling lag median %.2f ms, 99th percentile %.2f ms, max %.2f ms; "
                  "mean lag first tenth %.2f ms, last tenth %.2f ms",
                  sorted.size(), at(0.5), at(0.99), sorted.back(), first / static_cast<double>(tenth),
                  last / static_cast<double>(tenth));
    return text;
  }

 private:
  static constexpr double kBacklogWarning_s = 1.0;
  static constexpr double kBacklogRepeat_s = 10.0;
  Host* host_;
  QuietBusWatch* quiet_;
  std::vector<double> lags_ms_;
  int64_t last_backlog_warning_ = 0;
};

}  // namespace

std::string liveBusUrl(const std::string& url) {
  if (url.rfind("udpm://", 0) != 0 || url.find("recv_buf_size=") != std::string::npos) return url;
  return url + (url.find('?') == std::string::npos ? "?" : "&") + "recv_buf_size=4194304";
}

int runLive(const RunConfig& config, std::vector<EstimatorSlot> slots, LogSink* log,
            const LiveOptions& options, const std::atomic<bool>& stop, std::unique_ptr<Host>* host) {
  const std::string url = liveBusUrl(config.input);
  lcm::LCM bus(url);
  if (!bus.good()) {
    std::fprintf(stderr, "roam-run: error: cannot open the LCM bus '%s'\n", url.c_str());
    return 2;
  }
  BusSink bus_sink(&bus);
  TeeSink outputs;
  outputs.add(&bus_sink);
  std::unique_ptr<WallClockLogSink> log_sink;
  if (log != nullptr) {
    log_sink = std::make_unique<WallClockLogSink>(log);
    outputs.add(log_sink.get());
  }
  *host = std::make_unique<Host>(config, std::move(slots), &outputs, log_sink.get());
  // A team's inputs are on <CHANNEL>_<robot>, each robot's from its own host on the one bus.
  std::vector<std::string> watched, subscribed;
  const std::vector<std::string> suffixes = config.isTeam() ? config.team : std::vector<std::string>{""};
  for (const std::string& robot : suffixes) {
    const std::string suffix = robot.empty() ? "" : "_" + robot;
    watched.push_back(config.odometry_channel + suffix);
    watched.push_back(config.range_channel + suffix);
    subscribed.push_back(config.initial_pose_channel + suffix);
    subscribed.push_back(config.ground_truth_channel + suffix);
    if (!robot.empty()) subscribed.push_back(std::string(channels::ROBOT_RANGE) + suffix);
  }
  subscribed.insert(subscribed.end(), watched.begin(), watched.end());
  subscribed.push_back(config.beacons_channel);
  QuietBusWatch quiet(watched, config.idle_warning_s, std::chrono::system_clock::now());
  Receiver receiver(host->get(), &quiet);
  for (const std::string& channel : subscribed) {
    bus.subscribe(channel, &Receiver::onMessage, &receiver)->setQueueCapacity(kInputQueueCapacity);
  }
  std::fprintf(stderr, "roam-run: live on %s (Ctrl-C to finish)\n", url.c_str());
  const auto start = std::chrono::steady_clock::now();
  auto last_flush = start;
  while (!stop.load()) {
    const int rc = bus.handleTimeout(100);
    if (rc < 0) {
      if (errno == EINTR || stop.load()) continue;  // a signal: the loop condition decides
      std::fprintf(stderr, "roam-run: error: the LCM bus failed: %s\n", std::strerror(errno));
      break;
    }
    quiet.check(std::chrono::system_clock::now());
    const auto now = std::chrono::steady_clock::now();
    if (log != nullptr && now - last_flush > std::chrono::milliseconds(500)) {
      log->flush();
      last_flush = now;
    }
    if (options.duration_s > 0.0 &&
        std::chrono::duration<double>(now - start).count() >= options.duration_s) {
      break;
    }
  }
  (*host)->finish();
  std::fprintf(stderr, "live: %s\n", receiver.lagSummary().c_str());
  return 0;
}

}  // namespace runtime
}  // namespace roam
