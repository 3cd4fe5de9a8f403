#include "quiet_bus.hpp"

#include <cstdio>
#include <ctime>

namespace roam {
namespace runtime {
namespace {

// "01:23:45 UTC"
std::string clockTime(QuietBusWatch::Clock::time_point when) {
  const std::time_t seconds = QuietBusWatch::Clock::to_time_t(when);
  std::tm utc{};
  gmtime_r(&seconds, &utc);
  char text[32];
  std::strftime(text, sizeof text, "%H:%M:%S UTC", &utc);
  return text;
}

double secondsBetween(QuietBusWatch::Clock::time_point later, QuietBusWatch::Clock::time_point earlier) {
  return std::chrono::duration<double>(later - earlier).count();
}

}  // namespace

QuietBusWatch::QuietBusWatch(std::vector<std::string> channels, double idle_warning_s, Clock::time_point start)
    : idle_warning_s_(idle_warning_s), start_(start) {
  for (auto& name : channels) {
    Channel channel;
    channel.name = std::move(name);
    channel.last = start;
    channels_.push_back(channel);
  }
}

void QuietBusWatch::onMessage(const std::string& name, int64_t utime, Clock::time_point now) {
  for (auto& channel : channels_) {
    if (channel.name != name) continue;
    if (channel.warned) {
      std::fprintf(stderr, "roam-run: %s resumed after %.1f s quiet\n", name.c_str(),
                   secondsBetween(now, channel.last));
      channel.warned = false;
    }
    channel.seen = true;
    channel.last = now;
    channel.last_utime = utime;
  }
}

void QuietBusWatch::check(Clock::time_point now) {
  if (idle_warning_s_ <= 0.0) return;
  for (auto& channel : channels_) {
    const double quiet_s = secondsBetween(now, channel.last);
    if (channel.warned || quiet_s < idle_warning_s_) continue;
    channel.warned = true;
    if (channel.seen) {
      std::fprintf(stderr,
                   "roam-run: warning: no message on %s for %.1f s (since %s; the last had data time %.3f s)\n",
                   channel.name.c_str(), quiet_s, clockTime(channel.last).c_str(),
                   static_cast<double>(channel.last_utime) * 1e-6);
    } else {
      std::fprintf(stderr, "roam-run: warning: no message on %s since the start (%.1f s, since %s)\n",
                   channel.name.c_str(), quiet_s, clockTime(start_).c_str());
    }
  }
}

}  // namespace runtime
}  // namespace roam
