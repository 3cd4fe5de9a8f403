// roam-logcheck LOG: reads every event of an LCM log, decodes each roam channel with its
// message type, and prints one line per channel: name, events, type, undecodable count.
// Exit status 0 if the log is whole and every roam message decodes, 1 if not, 2 if unreadable.
// Where odometry or ranges are logged behind an input stamped later than them (a sensor's
// latency), one more line says how many and how far behind: roam-run's reorder_window_s must
// cover it.
//
// Channel -> type: ODOMETRY odometry_t; RANGE range_t; INITIAL_POSE, GROUND_TRUTH, POSE_* pose_t;
// BEACONS, MAP_* map_t; TRAJECTORY_* trajectory_t; STATUS_* estimator_status_t; others: not checked.
#include <sys/stat.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <lcm/lcm-cpp.hpp>
#include <map>
#include <string>

#include "roam/estimator_status_t.hpp"
#include "roam/map_t.hpp"
#include "roam/odometry_t.hpp"
#include "roam/pose_t.hpp"
#include "roam/range_t.hpp"
#include "roam/trajectory_t.hpp"
#include "roam/safe_decode.hpp"

namespace {

bool startsWith(const std::string& text, const std::string& prefix) { return text.rfind(prefix, 0) == 0; }

template <typename Message>
bool decodes(const lcm::LogEvent& event) {
  Message message;
  return roam::decodeMessage(event.data, event.datalen, &message) == event.datalen;
}

// Returns the type name, and whether the event decodes as that type.
std::pair<std::string, bool> check(const lcm::LogEvent& event) {
  const std::string& c = event.channel;
  if (c == "ODOMETRY") return {"roam.odometry_t", decodes<roam::odometry_t>(event)};
  if (c == "RANGE") return {"roam.range_t", decodes<roam::range_t>(event)};
  if (c == "INITIAL_POSE" || c == "GROUND_TRUTH" || startsWith(c, "POSE_"))
    return {"roam.pose_t", decodes<roam::pose_t>(event)};
  if (c == "BEACONS" || startsWith(c, "MAP_")) return {"roam.map_t", decodes<roam::map_t>(event)};
  if (startsWith(c, "TRAJECTORY_")) return {"roam.trajectory_t", decodes<roam::trajectory_t>(event)};
  if (startsWith(c, "STATUS_")) return {"roam.estimator_status_t", decodes<roam::estimator_status_t>(event)};
  return {"-", true};
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: roam-logcheck LOG\n");
    return 2;
  }
  struct stat info {};
  if (stat(argv[1], &info) != 0) {
    std::fprintf(stderr, "roam-logcheck: %s: cannot open\n", argv[1]);
    return 2;
  }
  lcm::LogFile log(argv[1], "r");
  if (!log.good()) {
    std::fprintf(stderr, "roam-logcheck: %s: cannot open\n", argv[1]);
    return 2;
  }
  struct Count {
    long events = 0, bad = 0;
    std::string type;
  };
  std::map<std::string, Count> channels;
  long events = 0, bad = 0;
  long end = 0;
  long behind = 0;  // odometry and ranges logged behind an input stamped later
  int64_t newest_input_utime = INT64_MIN;
  double most_behind_s = 0.0;  // in double: a damaged utime near the ends of int64 cannot overflow
  while (const lcm::LogEvent* event = log.readNextEvent()) {
    int64_t utime = 0;
    const bool input = event->channel == "ODOMETRY" || event->channel == "RANGE";
    if (input && roam::decodeInputUtime(event->channel == "ODOMETRY", event->data, event->datalen, &utime)) {
      if (utime < newest_input_utime) {
        ++behind;
        most_behind_s = std::max(most_behind_s, 1e-6 * (static_cast<double>(newest_input_utime) - static_cast<double>(utime)));
      }
      newest_input_utime = std::max(newest_input_utime, utime);
    }
    auto [type, ok] = check(*event);
    Count& count = channels[event->channel];
    count.type = type;
    ++count.events;
    ++events;
    if (!ok) {
      ++count.bad;
      ++bad;
    }
    end = std::ftell(log.getFilePtr());
  }
  for (const auto& [channel, count] : channels) {
    std::printf("%-24s %8ld  %-26s %s\n", channel.c_str(), count.events, count.type.c_str(),
                count.bad ? (std::to_string(count.bad) + " undecodable").c_str() : "ok");
  }
  if (behind > 0)
    std::printf("%ld ODOMETRY and RANGE events logged behind an input stamped later, by up to %.3f s: roam-run feeds "
                "them in time order if its reorder_window_s (default 1 s) is longer\n",
                behind, most_behind_s);
  const bool whole = end == static_cast<long>(info.st_size);
  std::printf("%ld events, %ld undecodable, %s\n", events, bad,
              whole ? "log whole" : "log ends inside an event or has corrupt bytes");
  return (bad == 0 && whole) ? 0 : 1;
}
