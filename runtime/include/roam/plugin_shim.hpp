// Adapts a roam::Estimator to the C plugin ABI (plugin_abi.h).
//
// In the plugin's shim file:
//
//   std::unique_ptr<roam::Estimator> makeSpectral(roam::Options& options) {
//     SpectralConfig config;
//     options.add("rank", &config.rank, "...").oneOf({4, 7});
//     options.parse();
//     return std::make_unique<SpectralEstimator>(config);
//   }
//   ROAM_DEFINE_PLUGIN("spectral", "Boots & Gordon 2013 spectral SLAM", makeSpectral)
//
// Every entry point catches exceptions, stores the message and returns ROAM_ERROR; nothing
// crosses the boundary. Inputs that are not finite are rejected (and counted) here, before
// the estimator sees them, so every plugin gets the same basic hygiene. So are implausibly
// long ranges and odometry that goes back in time or moves faster than a vehicle can: every
// plugin has the options `max_range_m` (default kDefaultMaxRange_m) and `max_speed_mps`
// (default kDefaultMaxSpeed_mps), added here before the plugin's own options, so a plugin must
// not declare keys of those names.
#pragma once

#include <cstring>
#include <exception>
#include <memory>
#include <string>
#include <vector>

#include "roam/estimator.hpp"
#include "roam/options.hpp"
#include "roam/plugin_abi.h"
#include "roam/self_check.hpp"

namespace roam {
namespace shim {

using Factory = std::unique_ptr<Estimator> (*)(Options& options);

// Ranges longer than this are rejected as implausible unless the config says otherwise
// (beacon radios reach a few hundred metres; a glitch reads 655.35 m or 1e9 m).
constexpr double kDefaultMaxRange_m = 1000.0;

// Odometry steps faster than this are rejected as jumps (a glitch, a reset counter). 30 m/s is
// above any ground robot, boat or AUV roam is meant for; a car on a road raises it. The step is
// compared with max_speed_mps * max(dt, 1 s): logs stamped in whole seconds, and steps with the
// same time as the previous one, are not rejected for their time resolution.
constexpr double kDefaultMaxSpeed_mps = 30.0;

// The SDK's odometry check, the same for every plugin: finite, not back in time, not faster
// than max_speed_mps. Returns "" or the reason for the rejection.
class OdometryCheck {
 public:
  double max_speed_mps = kDefaultMaxSpeed_mps;
  std::string check(const roam_odometry& odometry) const;
  void accepted(const roam_odometry& odometry);

 private:
  bool have_last_ = false;
  int64_t last_utime_ = 0;
};
// One plugin instance on the C side: the estimator and the buffers handed across.
struct Instance {
  std::unique_ptr<Estimator> estimator;
  double max_range_m = kDefaultMaxRange_m;  // the SDK's own option
  OdometryCheck odometry_check;             // holds the SDK's max_speed_mps option
  // A team (set_team): each robot's own odometry check (its clock is its own), and the team's
  // self-check in place of the one-robot one.
  std::vector<std::string> team;
  std::vector<OdometryCheck> team_odometry_checks;
  SelfCheck self_check;                     // the SDK's rule on what is published (self_check.hpp)
  TeamSelfCheck team_self_check;            // the same rule on a team's answer
  std::string last_error;
  KeyValues effective;
  std::vector<roam_kv> effective_view;
  std::vector<roam_pose> poses;
  std::vector<roam_beacon> beacons;
  std::vector<roam_pose> path;
  std::string last_rejection;
  std::vector<std::string> diagnostic_keys;
  std::vector<const char*> diagnostic_key_ptrs;
  std::vector<double> diagnostic_values;
};

// The C side of the ABI <-> roam/types.hpp: the shim's one conversion each way per struct
// (plugin_shim.cpp). The host converts LCM <-> C (roam/messages.hpp) and never these.
roam_pose toC(const Pose& pose);
Pose fromC(const roam_pose& pose);
roam_beacon toC(const Beacon& beacon);
Beacon fromC(const roam_beacon& beacon);
roam_odometry toC(const Odometry& odometry);
Odometry fromC(const roam_odometry& odometry);
roam_range toC(const Range& range);
Range fromC(const roam_range& range);
// Element by element: a Map or Path to C and back.
template <typename T>
auto toC(const std::vector<T>& items) {
  std::vector<decltype(toC(items.front()))> out;
  out.reserve(items.size());
  for (const T& item : items) out.push_back(toC(item));
  return out;
}
template <typename C>
auto fromC(const std::vector<C>& items) {
  std::vector<decltype(fromC(items.front()))> out;
  out.reserve(items.size());
  for (const C& item : items) out.push_back(fromC(item));
  return out;
}
// "" if usable, else the reason (non-finite value, negative range, ...).
std::string checkOdometry(const roam_odometry& odometry);  // finite values only
std::string checkRange(const roam_range& range);
void copyError(roam_error* error, const std::string& key, const std::string& message);

roam_handle create(Factory factory, const roam_kv* config, int32_t num_config, roam_error* error);
void destroy(roam_handle h);
int describeConfig(roam_handle h, const roam_kv** config, int32_t* num_config);
int setInitialPose(roam_handle h, const roam_pose* pose);
int setBeacons(roam_handle h, const roam_beacon* beacons, int32_t num_beacons);
int addOdometry(roam_handle h, const roam_odometry* odometry);
int addRange(roam_handle h, const roam_range* range);
int finish(roam_handle h);
int pollPoses(roam_handle h, const roam_pose** poses, int32_t* num_poses);
int pollMap(roam_handle h, int32_t* changed, const roam_beacon** beacons, int32_t* num_beacons);
int pollTrajectory(roam_handle h, int32_t force, int32_t* available, const roam_pose** poses,
                   int32_t* num_poses);
int getStatus(roam_handle h, roam_status* status);
const char* lastError(roam_handle h);
int setTeam(roam_handle h, const char* const* robots, int32_t num_robots);

}  // namespace shim
}  // namespace roam

// A plugin that estimates one robot: ROAM_DEFINE_PLUGIN. One that estimates a team (its
// Estimator overrides setTeam and reads each input's `robot`): ROAM_DEFINE_TEAM_PLUGIN.
#define ROAM_DEFINE_PLUGIN(NAME, DESCRIPTION, FACTORY) ROAM_DEFINE_PLUGIN_WITH_TEAM(NAME, DESCRIPTION, FACTORY, nullptr)
#define ROAM_DEFINE_TEAM_PLUGIN(NAME, DESCRIPTION, FACTORY) \
  ROAM_DEFINE_PLUGIN_WITH_TEAM(NAME, DESCRIPTION, FACTORY, &::roam::shim::setTeam)
#define ROAM_DEFINE_PLUGIN_WITH_TEAM(NAME, DESCRIPTION, FACTORY, SET_TEAM)                     \
  extern "C" {                                                                                  \
  static roam_handle roam_shim_create(const roam_kv* c, int32_t n, roam_error* e) {             \
    return ::roam::shim::create(&FACTORY, c, n, e);                                             \
  }                                                                                             \
  __attribute__((visibility("default"))) const roam_plugin_descriptor* roam_plugin_entry(void) { \
    static const roam_plugin_descriptor descriptor = {                                          \
        ROAM_PLUGIN_ABI_VERSION,                                                                \
        static_cast<uint32_t>(sizeof(roam_plugin_descriptor)),                                  \
        ROAM_ABI_LAYOUTS,                                                                       \
        NAME,                                                                                   \
        DESCRIPTION,                                                                            \
        &roam_shim_create,                                                                      \
        &::roam::shim::destroy,                                                                 \
        &::roam::shim::describeConfig,                                                          \
        &::roam::shim::setInitialPose,                                                          \
        &::roam::shim::setBeacons,                                                              \
        &::roam::shim::addOdometry,                                                             \
        &::roam::shim::addRange,                                                                \
        &::roam::shim::finish,                                                                  \
        &::roam::shim::pollPoses,                                                               \
        &::roam::shim::pollMap,                                                                 \
        &::roam::shim::pollTrajectory,                                                          \
        &::roam::shim::getStatus,                                                               \
        &::roam::shim::lastError,                                                               \
        SET_TEAM,                                                                               \
    };                                                                                          \
    return &descriptor;                                                                         \
  }                                                                                             \
  }
