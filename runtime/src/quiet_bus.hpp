// Live mode's watch on the input channels: a channel with no message for idle_warning_s gets one
// warning (which channel, since when), and one line when it resumes. Wall-clock time: a quiet bus
// is about the radio or the robot, not the data's own clock.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

namespace roam {
namespace runtime {

class QuietBusWatch {
 public:
  using Clock = std::chrono::system_clock;
  // Watches `channels`; idle_warning_s <= 0 turns the watch off.
  QuietBusWatch(std::vector<std::string> channels, double idle_warning_s, Clock::time_point start);
  // A message on `channel` at `now` with data time `utime`; prints "resumed" after a warning.
  void onMessage(const std::string& channel, int64_t utime, Clock::time_point now);
  // Prints the warning for every channel quiet for idle_warning_s that has not had one yet.
  void check(Clock::time_point now);

 private:
  struct Channel {
    std::string name;
    bool seen = false;
    Clock::time_point last;
    int64_t last_utime = 0;
    bool warned = false;
  };
  std::vector<Channel> channels_;
  double idle_warning_s_;
  Clock::time_point start_;
};

}  // namespace runtime
}  // namespace roam
