// Loading estimator plugins: dlopen(RTLD_LOCAL), the ABI handshake, and the instances.
//
// A PluginLibrary owns the dlopen handle; every PluginInstance keeps a shared_ptr to its
// library, so the code stays mapped while any object made by it lives, and each instance is
// destroyed with the plugin's own destroy function. Every call into an instance is timed in
// thread CPU time. A call that fails marks the instance failed: it keeps its error message and
// receives no more data, while the other instances go on.
#pragma once

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "roam/options.hpp"
#include "roam/plugin_abi.h"
#include "roam/types.hpp"

namespace roam {
namespace runtime {

class PluginError : public std::runtime_error {
 public:
  explicit PluginError(const std::string& message) : std::runtime_error(message) {}
};

// Thrown by PluginLibrary::create when the plugin rejects its config: names the key.
class PluginConfigError : public std::runtime_error {
 public:
  PluginConfigError(std::string key, const std::string& message)
      : std::runtime_error(message), key_(std::move(key)) {}
  const std::string& key() const { return key_; }

 private:
  std::string key_;
};

class PluginInstance;

class PluginLibrary {
 public:
  // Opens <folder>/libroam_<name>.so and checks its descriptor; throws PluginError.
  // libroam_<name>.so from the first of the ':'-separated folders of `search_path` that has it.
  static std::shared_ptr<PluginLibrary> open(const std::string& search_path, const std::string& name);
  // The folders of a ':'-separated search path, in order (empty parts skipped).
  static std::vector<std::string> searchFolders(const std::string& search_path);
  // Opens a library by path (tests load deliberately broken plugins this way).
  static std::shared_ptr<PluginLibrary> openFile(const std::string& path);
  ~PluginLibrary();
  PluginLibrary(const PluginLibrary&) = delete;
  PluginLibrary& operator=(const PluginLibrary&) = delete;

  const roam_plugin_descriptor& descriptor() const { return *descriptor_; }
  const std::string& path() const { return path_; }
  // Plugin names found in a folder (libroam_<name>.so), sorted.
  static std::vector<std::string> available(const std::string& folder);

 private:
  PluginLibrary() = default;
  void* handle_ = nullptr;
  const roam_plugin_descriptor* descriptor_ = nullptr;
  std::string path_;
};


class PluginInstance {
 public:
  // Creates an instance from key/values; throws PluginConfigError if the plugin refuses.
  PluginInstance(std::shared_ptr<PluginLibrary> library, std::string name, const KeyValues& config);
  ~PluginInstance();
  PluginInstance(const PluginInstance&) = delete;
  PluginInstance& operator=(const PluginInstance&) = delete;

  const std::string& name() const { return name_; }
  const std::string& pluginName() const { return plugin_name_; }
  bool failed() const { return failed_; }
  const std::string& error() const { return error_; }
  double cpuTotalSeconds() const { return cpu_total_s_; }
  double cpuLastSeconds() const { return cpu_last_s_; }
  KeyValues effectiveConfig();

  // Inputs; each returns false (and marks the instance failed) if the plugin reports an error.
  // A failed instance ignores further input.
  bool setInitialPose(const roam_pose& pose);
  bool setBeacons(const std::vector<roam_beacon>& beacons);
  bool addOdometry(const roam_odometry& odometry);
  bool addRange(const roam_range& range);
  bool finish();

  // Outputs (copied out of the plugin's buffers).
  bool pollPoses(std::vector<roam_pose>* poses);
  bool pollMap(bool* changed, std::vector<roam_beacon>* beacons);
  bool pollTrajectory(bool force, bool* available, std::vector<roam_pose>* poses);

  struct Status {
    int32_t state = ROAM_STATE_INITIALIZING;
    int64_t odometry_accepted = 0, odometry_rejected = 0, ranges_accepted = 0, ranges_rejected = 0;
    std::string last_rejection;
    std::vector<std::string> keys;
    std::vector<double> values;
  };
  Status status();
  // Marks the instance failed from outside (e.g. the host caught something).
  void markFailed(const std::string& error);

 private:
  // Runs one call into the plugin, timed; false and failed on error.
  template <typename Call>
  bool call(const char* what, Call&& body);

  std::shared_ptr<PluginLibrary> library_;
  const roam_plugin_descriptor* d_ = nullptr;
  roam_handle handle_ = nullptr;
  std::string name_;
  std::string plugin_name_;
  bool failed_ = false;
  std::string error_;
  double cpu_total_s_ = 0.0;
  double cpu_last_s_ = 0.0;
};

}  // namespace runtime
}  // namespace roam
