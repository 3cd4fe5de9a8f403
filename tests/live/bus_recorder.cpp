// bus_recorder: the live tests' recorder on the logger's host. It writes every message of an LCM
// bus to a log file, as lcm-logger does, but its one subscription (".*") holds up to
// kQueueCapacity messages instead of LCM's default 30. lcm-logger keeps that default: at 20x
// Plaza 1 the bus carries ~360 messages a second, so a stall of lcm-logger's main loop over
// ~0.1 s (a busy host) dropped messages without a word, and the test then blamed roam for
// estimates the logger never recorded.
//
//   bus_recorder LCM_URL FILE   records until SIGINT or SIGTERM, then prints the event count
#include <lcm/lcm-cpp.hpp>

#include <csignal>
#include <cstdint>
#include <cstdio>
#include <string>

namespace {

constexpr int kQueueCapacity = 1000000;  // messages: minutes of the busiest test bus
constexpr int kPollMs = 100;

volatile std::sig_atomic_t stop_requested = 0;
void requestStop(int) { stop_requested = 1; }

struct Recorder {
  lcm::LogFile* log = nullptr;
  int64_t events = 0;
  bool write_failed = false;

  void handle(const lcm::ReceiveBuffer* buffer, const std::string& channel) {
    lcm::LogEvent event;
    event.eventnum = events;
    event.timestamp = buffer->recv_utime;
    event.channel = channel;
    event.datalen = static_cast<int32_t>(buffer->data_size);
    event.data = buffer->data;
    if (log->writeEvent(&event) != 0) write_failed = true;
    ++events;
  }
};

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: bus_recorder LCM_URL FILE\n");
    return 2;
  }
  lcm::LCM bus(argv[1]);
  if (!bus.good()) {
    std::fprintf(stderr, "bus_recorder: cannot open the LCM bus %s\n", argv[1]);
    return 1;
  }
  lcm::LogFile log(argv[2], "w");
  if (!log.good()) {
    std::fprintf(stderr, "bus_recorder: cannot write %s\n", argv[2]);
    return 1;
  }
  Recorder recorder;
  recorder.log = &log;
  lcm::Subscription* subscription = bus.subscribe(".*", &Recorder::handle, &recorder);
  if (subscription == nullptr || subscription->setQueueCapacity(kQueueCapacity) != 0) {
    std::fprintf(stderr, "bus_recorder: cannot subscribe to the bus\n");
    return 1;
  }
  std::signal(SIGINT, requestStop);
  std::signal(SIGTERM, requestStop);
  std::printf("bus_recorder: recording %s to %s\n", argv[1], argv[2]);
  std::fflush(stdout);
  while (!stop_requested)
    if (bus.handleTimeout(kPollMs) < 0) break;
  while (bus.handleTimeout(0) > 0) {
  }  // what was already queued when the stop came
  std::printf("bus_recorder: %lld events\n", static_cast<long long>(recorder.events));
  if (recorder.write_failed) {
    std::fprintf(stderr, "bus_recorder: writing %s failed\n", argv[2]);
    return 1;
  }
  return 0;
}
