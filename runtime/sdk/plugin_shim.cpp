#include "roam/plugin_shim.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <stdexcept>

namespace roam {
namespace shim {
namespace {

Instance* instance(roam_handle h) { return static_cast<Instance*>(h); }

// Runs `body` on the instance; any exception becomes ROAM_ERROR with its message stored.
template <typename Body>
int guarded(roam_handle h, Body&& body) {
  Instance* self = instance(h);
  if (self == nullptr) return ROAM_ERROR;
  try {
    self->last_error.clear();
    body(*self);
    return ROAM_OK;
  } catch (const std::exception& error) {
    self->last_error = error.what();
  } catch (...) {
    self->last_error = "unknown exception";
  }
  if (self->last_error.empty()) self->last_error = "error with no message";
  return ROAM_ERROR;
}

}  // namespace

namespace {

// A covariance between a C array and a std::array of the same size.
template <typename To, typename From>
void copyCovariance(To& to, const From& from) {
  static_assert(sizeof(To) == sizeof(From), "covariances of different sizes");
  std::copy(std::begin(from), std::end(from), std::begin(to));
}

// The field lists: the C structs of plugin_abi.h and the structs of roam/types.hpp share their
// field names, so each list is written once and serves both directions.
template <typename To, typename From>
To copyPose(const From& in) {
  To out{};
  out.utime = in.utime;
  out.x_m = in.x_m;
  out.y_m = in.y_m;
  out.heading_rad = in.heading_rad;
  copyCovariance(out.covariance, in.covariance);
  out.robot = in.robot;
  return out;
}

template <typename To, typename From>
To copyBeacon(const From& in) {
  To out{};
  out.id = in.id;
  out.x_m = in.x_m;
  out.y_m = in.y_m;
  copyCovariance(out.covariance, in.covariance);
  return out;
}

template <typename To, typename From>
To copyOdometry(const From& in) {
  To out{};
  out.utime = in.utime;
  out.forward_m = in.forward_m;
  out.lateral_m = in.lateral_m;
  out.delta_heading_rad = in.delta_heading_rad;
  copyCovariance(out.covariance, in.covariance);
  out.robot = in.robot;
  return out;
}

template <typename To, typename From>
To copyRange(const From& in) {
  To out{};
  out.utime = in.utime;
  out.beacon_id = in.beacon_id;
  out.range_m = in.range_m;
  out.sigma_m = in.sigma_m;
  out.has_bearing = in.has_bearing != 0;  // bool <-> the ABI's 0 or 1
  out.bearing_rad = in.bearing_rad;
  out.robot = in.robot;
  return out;
}

}  // namespace

roam_pose toC(const Pose& pose) { return copyPose<roam_pose>(pose); }
Pose fromC(const roam_pose& pose) { return copyPose<Pose>(pose); }
roam_beacon toC(const Beacon& beacon) { return copyBeacon<roam_beacon>(beacon); }
Beacon fromC(const roam_beacon& beacon) { return copyBeacon<Beacon>(beacon); }
roam_odometry toC(const Odometry& odometry) { return copyOdometry<roam_odometry>(odometry); }
Odometry fromC(const roam_odometry& odometry) { return copyOdometry<Odometry>(odometry); }
// Range::other_robot (-1: a beacon) is roam_range::to_robot - 1 (0: a beacon).
roam_range toC(const Range& range) {
  roam_range out = copyRange<roam_range>(range);
  out.to_robot = range.other_robot + 1;
  return out;
}
Range fromC(const roam_range& range) {
  Range out = copyRange<Range>(range);
  out.other_robot = range.to_robot - 1;
  return out;
}

std::string checkOdometry(const roam_odometry& odometry) {
  if (!std::isfinite(odometry.forward_m) || !std::isfinite(odometry.lateral_m) ||
      !std::isfinite(odometry.delta_heading_rad))
    return "not finite";
  return "";
}

std::string OdometryCheck::check(const roam_odometry& odometry) const {
  const std::string problem = checkOdometry(odometry);
  if (!problem.empty()) return problem;
  double dt_s = 1.0;
  if (have_last_) {
    if (odometry.utime < last_utime_) return "time went backwards";
    dt_s = std::max(1.0, (static_cast<double>(odometry.utime) - static_cast<double>(last_utime_)) * 1e-6);
  }
  if (std::hypot(odometry.forward_m, odometry.lateral_m) > max_speed_mps * dt_s) {
    return "faster than max_speed_mps";
  }
  return "";
}

void OdometryCheck::accepted(const roam_odometry& odometry) {
  have_last_ = true;
  last_utime_ = odometry.utime;
}

std::string checkRange(const roam_range& range) {
  if (!std::isfinite(range.range_m)) return "not finite";
  if (range.range_m <= 0.0) return "not positive";
  if (!std::isfinite(range.sigma_m)) return "sigma not finite";
  if (range.has_bearing && !std::isfinite(range.bearing_rad)) return "bearing not finite";
  return "";
}

void copyError(roam_error* error, const std::string& key, const std::string& message) {
  if (error == nullptr) return;
  std::snprintf(error->key, sizeof(error->key), "%s", key.c_str());
  std::snprintf(error->message, sizeof(error->message), "%s", message.c_str());
}

namespace {
// "" if `robot` (and a range's `other_robot`) name members of the instance's team (robot 0 and
// no other robot for an estimator of one robot), else why not.
std::string checkMembers(const Instance& self, int32_t robot, int32_t other_robot = -1) {
  const auto size = static_cast<int32_t>(std::max<size_t>(1, self.team.size()));
  if (robot < 0 || robot >= size) return "robot " + std::to_string(robot) + " is not in the team";
  if (other_robot == -1) return "";
  if (self.team.empty()) return "a range to another robot (this estimator estimates one robot)";
  if (other_robot < 0 || other_robot >= size) return "other robot " + std::to_string(other_robot) + " is not in the team";
  if (other_robot == robot) return "a range from a robot to itself";
  return "";
}
}  // namespace

roam_handle create(Factory factory, const roam_kv* config, int32_t num_config,
                   roam_error* error) {
  try {
    KeyValues values;
    for (int32_t i = 0; i < num_config; ++i) {
      values.emplace_back(config[i].key ? config[i].key : "", config[i].value ? config[i].value : "");
    }
    Options options(values);
    auto self = std::make_unique<Instance>();
    options.add("max_range_m", &self->max_range_m, "longer ranges are rejected as implausible")
        .min(0.0, false);
    options.add("max_speed_mps", &self->odometry_check.max_speed_mps,
                "odometry steps faster than this (over max(dt, 1 s)) are rejected as jumps")
        .min(0.0, false);
    self->estimator = factory(options);
    if (!self->estimator) {
      copyError(error, "", "the plugin's factory returned no estimator");
      return nullptr;
    }
    self->effective = options.effective();
    for (const auto& [key, value] : self->effective) {
      self->effective_view.push_back(roam_kv{key.c_str(), value.c_str()});
      if (key == "anchor") {
        self->self_check.anchor(value);
        self->team_self_check.anchor(value);
      }
    }
    return self.release();
  } catch (const ConfigError& config_error) {
    copyError(error, config_error.key(), config_error.what());
  } catch (const std::exception& other) {
    copyError(error, "", other.what());
  } catch (...) {
    copyError(error, "", "unknown exception");
  }
  return nullptr;
}

void destroy(roam_handle h) { delete instance(h); }

int describeConfig(roam_handle h, const roam_kv** config, int32_t* num_config) {
  return guarded(h, [&](Instance& self) {
    *config = self.effective_view.data();
    *num_config = static_cast<int32_t>(self.effective_view.size());
  });
}

int setInitialPose(roam_handle h, const roam_pose* pose) {
  return guarded(h, [&](Instance& self) {
    if (!std::isfinite(pose->x_m) || !std::isfinite(pose->y_m) || !std::isfinite(pose->heading_rad)) {
      self.estimator->rejectInput("initial pose", "not finite");
      return;
    }
    if (const std::string problem = checkMembers(self, pose->robot); !problem.empty()) {
      self.estimator->rejectInput("initial pose", problem);
      return;
    }
    self.estimator->setInitialPose(fromC(*pose));
    if (self.team.empty()) self.self_check.startPose(fromC(*pose));
    else self.team_self_check.startPose(fromC(*pose));
  });
}

int setBeacons(roam_handle h, const roam_beacon* beacons, int32_t num_beacons) {
  return guarded(h, [&](Instance& self) {
    Map map;
    for (int32_t i = 0; i < num_beacons; ++i) {
      if (!std::isfinite(beacons[i].x_m) || !std::isfinite(beacons[i].y_m)) {
        self.estimator->rejectInput("beacon", "not finite");  // the others are still used
        continue;
      }
      map.push_back(fromC(beacons[i]));
    }
    self.estimator->setBeacons(map);
    self.self_check.surveyed(map);
    self.team_self_check.surveyed(map);
  });
}

int addOdometry(roam_handle h, const roam_odometry* odometry) {
  return guarded(h, [&](Instance& self) {
    if (const std::string problem = checkMembers(self, odometry->robot); !problem.empty()) {
      self.estimator->rejectOdometry(problem);
      return;
    }
    OdometryCheck& check = self.team.empty() ? self.odometry_check : self.team_odometry_checks[odometry->robot];
    const std::string problem = check.check(*odometry);
    if (!problem.empty()) {
      self.estimator->rejectOdometry(problem);
      return;
    }
    check.accepted(*odometry);
    const Odometry step = fromC(*odometry);
    const int64_t accepted_before = self.estimator->odometryAccepted();
    self.estimator->addOdometry(step);
    const bool accepted = self.estimator->odometryAccepted() > accepted_before;
    if (self.team.empty()) self.self_check.odometry(step, accepted);
    else self.team_self_check.odometry(step, accepted);
  });
}

int addRange(roam_handle h, const roam_range* range) {
  return guarded(h, [&](Instance& self) {
    const std::string problem = checkRange(*range);
    if (!problem.empty()) {
      self.estimator->rejectRange(problem);
      return;
    }
    if (range->range_m > self.max_range_m) {
      self.estimator->rejectRange("longer than max_range_m");
      return;
    }
    if (const std::string members = checkMembers(self, range->robot, range->to_robot - 1); !members.empty()) {
      self.estimator->rejectRange(members);
      return;
    }
    const Range accepted = fromC(*range);
    const int64_t rejected_before = self.estimator->rangesRejected();
    self.estimator->addRange(accepted);
    if (self.team.empty()) self.self_check.range(accepted);
    else self.team_self_check.range(accepted, self.estimator->rangesRejected() > rejected_before);
  });
}

int finish(roam_handle h) {
  return guarded(h, [&](Instance& self) {
    self.estimator->finish();
    if (self.team.empty()) self.self_check.finished();
    else self.team_self_check.finished();
  });
}

int pollPoses(roam_handle h, const roam_pose** poses, int32_t* num_poses) {
  return guarded(h, [&](Instance& self) {
    self.poses = toC(self.estimator->takePoses());
    *poses = self.poses.data();
    *num_poses = static_cast<int32_t>(self.poses.size());
  });
}

int pollMap(roam_handle h, int32_t* changed, const roam_beacon** beacons, int32_t* num_beacons) {
  return guarded(h, [&](Instance& self) {
    Map map;
    *changed = self.estimator->takeMap(&map) ? 1 : 0;
    self.beacons = toC(map);
    *beacons = self.beacons.data();
    *num_beacons = static_cast<int32_t>(self.beacons.size());
  });
}

int pollTrajectory(roam_handle h, int32_t force, int32_t* available, const roam_pose** poses,
                   int32_t* num_poses) {
  return guarded(h, [&](Instance& self) {
    Path path;
    *available = self.estimator->trajectory(force != 0, &path) ? 1 : 0;
    if (*available && self.team.empty()) self.self_check.apply(*self.estimator, &path);
    if (*available && !self.team.empty()) self.team_self_check.apply(*self.estimator, &path);
    self.path = toC(path);
    *poses = self.path.data();
    *num_poses = static_cast<int32_t>(self.path.size());
  });
}

int getStatus(roam_handle h, roam_status* status) {
  return guarded(h, [&](Instance& self) {
    const Estimator& estimator = *self.estimator;
    status->state = static_cast<int32_t>(estimator.state());
    status->odometry_accepted = estimator.odometryAccepted();
    status->odometry_rejected = estimator.odometryRejected();
    status->ranges_accepted = estimator.rangesAccepted();
    status->ranges_rejected = estimator.rangesRejected();
    self.last_rejection = estimator.lastRejection();
    status->last_rejection = self.last_rejection.c_str();
    self.diagnostic_keys.clear();
    self.diagnostic_values.clear();
    // Per-reason rejection counts first, then the estimator's own diagnostics.
    for (const auto& [reason, count] : estimator.rejections()) {
      self.diagnostic_keys.push_back("rejected " + reason);
      self.diagnostic_values.push_back(static_cast<double>(count));
    }
    for (const auto& [key, value] : estimator.diagnostics()) {
      self.diagnostic_keys.push_back(key);
      self.diagnostic_values.push_back(value);
    }
    if (self.self_check.replaced()) {
      self.diagnostic_keys.push_back(SelfCheck::kNote);
      self.diagnostic_values.push_back(1.0);
    }
    for (const auto& [key, value] : self.team.empty() ? self.self_check.diagnostics() : self.team_self_check.diagnostics()) {
      self.diagnostic_keys.push_back(key);
      self.diagnostic_values.push_back(value);
    }
    self.diagnostic_key_ptrs.clear();
    for (const auto& key : self.diagnostic_keys) self.diagnostic_key_ptrs.push_back(key.c_str());
    status->num_values = static_cast<int32_t>(self.diagnostic_values.size());
    status->keys = self.diagnostic_key_ptrs.data();
    status->values = self.diagnostic_values.data();
  });
}

int setTeam(roam_handle h, const char* const* robots, int32_t num_robots) {
  return guarded(h, [&](Instance& self) {
    if (!self.team.empty()) throw std::runtime_error("set_team: the team was already set");
    if (num_robots < 1) throw std::runtime_error("set_team: a team needs at least one robot");
    std::vector<std::string> names;
    for (int32_t i = 0; i < num_robots; ++i) names.emplace_back(robots[i] != nullptr ? robots[i] : "");
    self.estimator->setTeam(names);
    self.team = names;
    self.team_self_check.team(names);
    self.team_odometry_checks.assign(names.size(), self.odometry_check);
  });
}

const char* lastError(roam_handle h) {
  Instance* self = instance(h);
  return self == nullptr ? "no instance" : self->last_error.c_str();
}

}  // namespace shim
}  // namespace roam
