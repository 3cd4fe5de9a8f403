// The requests and answers between roam-run and an isolated estimator's child (wire.hpp frames).
//
//   request:  kind (uint8), then the input as a byte copy of its roam_* struct (or a vector of them)
//   answer:   failed, error, CPU total / last, wall time of the update, the poses and the map
//             polled after an input, the path after kTrajectory, the status after kStatus
//   creation: ok, then the effective config (keys, values) or the refusing key and message
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "estimator_instance.hpp"
#include "plugin_library.hpp"
#include "wire.hpp"

namespace roam {
namespace runtime {
namespace isolation {

enum Kind : uint8_t {
  kInitialPose = 1,
  kBeacons,
  kOdometry,
  kRange,
  kFinish,
  kPoll,        // outputs only (the host polls after an event no estimator was given)
  kTrajectory,  // then force (uint8)
  kStatus,
  kTeam  // the team's robot names (strs)
};

struct Answer {
  bool failed = false;
  std::string error;
  double cpu_total_s = 0.0, cpu_last_s = 0.0, wall_last_s = 0.0;
  bool polled = false;  // poses and map below were polled
  std::vector<roam_pose> poses;
  bool map_changed = false;
  std::vector<roam_beacon> beacons;
  bool trajectory_available = false;
  std::vector<roam_pose> trajectory;
  bool has_status = false;
  EstimatorInstance::Status status;
};

inline void write(wire::Writer& out, const Answer& a) {
  out.pod<uint8_t>(a.failed).str(a.error).pod(a.cpu_total_s).pod(a.cpu_last_s).pod(a.wall_last_s);
  out.pod<uint8_t>(a.polled).pods(a.poses).pod<uint8_t>(a.map_changed).pods(a.beacons);
  out.pod<uint8_t>(a.trajectory_available).pods(a.trajectory).pod<uint8_t>(a.has_status);
  if (a.has_status) {
    const auto& s = a.status;
    out.pod(s.state).pod(s.odometry_accepted).pod(s.odometry_rejected).pod(s.ranges_accepted);
    out.pod(s.ranges_rejected).str(s.last_rejection).strs(s.keys).pods(s.values);
  }
}

inline bool read(wire::Reader& in, Answer* a) {
  a->failed = in.pod<uint8_t>() != 0;
  a->error = in.str();
  a->cpu_total_s = in.pod<double>();
  a->cpu_last_s = in.pod<double>();
  a->wall_last_s = in.pod<double>();
  a->polled = in.pod<uint8_t>() != 0;
  a->poses = in.pods<roam_pose>();
  a->map_changed = in.pod<uint8_t>() != 0;
  a->beacons = in.pods<roam_beacon>();
  a->trajectory_available = in.pod<uint8_t>() != 0;
  a->trajectory = in.pods<roam_pose>();
  a->has_status = in.pod<uint8_t>() != 0;
  if (a->has_status) {
    auto& s = a->status;
    s.state = in.pod<int32_t>();
    s.odometry_accepted = in.pod<int64_t>();
    s.odometry_rejected = in.pod<int64_t>();
    s.ranges_accepted = in.pod<int64_t>();
    s.ranges_rejected = in.pod<int64_t>();
    s.last_rejection = in.str();
    s.keys = in.strs();
    s.values = in.pods<double>();
  }
  return in.ok();
}

// The child's side: creates the instance, answers requests on `fd` until it closes, exits.
[[noreturn]] void serveChild(int fd, const std::shared_ptr<PluginLibrary>& library, const std::string& name,
                             const KeyValues& config, double max_memory_mb);

}  // namespace isolation
}  // namespace runtime
}  // namespace roam
