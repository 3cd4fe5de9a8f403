// Loading estimator plugins: dlopen(RTLD_LOCAL), the ABI handshake, and the instances.
// A plugin file or folder that others may write or that someone else owns is refused.
//
// A PluginLibrary owns the dlopen handle; every PluginInstance keeps a shared_ptr to its
// library, so the code stays mapped while any object made by it lives, and each instance is
// destroyed with the plugin's own destroy function. Every call into an instance is timed in
// thread CPU time and wall-clock time. A call that fails, or that takes longer than its CallLimits
// allow, marks the instance failed: it keeps its error message and receives no more data, while
// the other instances go on. (A call in this process cannot be interrupted: the limit is checked
// when it returns. IsolatedInstance ends a child that does not answer in time.)
#pragma once

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "estimator_instance.hpp"
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
  // The plugin estimates a team in one instance (its descriptor has set_team).
  bool estimatesTeams() const { return descriptor_->set_team != nullptr; }
  const std::string& path() const { return path_; }
  // Plugin names found in a folder (libroam_<name>.so), sorted.
  static std::vector<std::string> available(const std::string& folder);
  // Refuses (PluginError, with the fix) a plugin file or folder that someone other than the
  // user or root owns, or that its group or others may write: like ssh with a key file, since
  // whoever can change a plugin runs code as the user of roam-run. `what`: "plugin", "plugin folder".
  static void checkTrusted(const std::string& path, const char* what);

 private:
  PluginLibrary() = default;
  void* handle_ = nullptr;
  const roam_plugin_descriptor* descriptor_ = nullptr;
  std::string path_;
};


class PluginInstance : public EstimatorInstance {
 public:
  // Creates an instance from key/values; throws PluginConfigError if the plugin refuses.
  PluginInstance(std::shared_ptr<PluginLibrary> library, std::string name, const KeyValues& config,
                 CallLimits limits = {});
  ~PluginInstance() override;
  PluginInstance(const PluginInstance&) = delete;
  PluginInstance& operator=(const PluginInstance&) = delete;

  const std::string& name() const override { return name_; }
  const std::string& pluginName() const override { return plugin_name_; }
  InstanceRecord& record() override { return record_; }
  KeyValues effectiveConfig() override;

  bool setTeam(const std::vector<std::string>& robots) override;
  bool setInitialPose(const roam_pose& pose) override;
  bool setBeacons(const std::vector<roam_beacon>& beacons) override;
  bool addOdometry(const roam_odometry& odometry) override;
  bool addRange(const roam_range& range) override;
  bool finish() override;

  // Outputs (copied out of the plugin's buffers).
  bool pollPoses(std::vector<roam_pose>* poses) override;
  bool pollMap(bool* changed, std::vector<roam_beacon>* beacons) override;
  bool pollTrajectory(bool force, bool* available, std::vector<roam_pose>* poses) override;

  Status status() override;

 private:
  // Runs one call into the plugin, timed; false and failed on error or over the time limit.
  template <typename Call>
  bool call(const char* what, Call&& body);

  std::shared_ptr<PluginLibrary> library_;
  const roam_plugin_descriptor* d_ = nullptr;
  roam_handle handle_ = nullptr;
  std::string name_;
  std::string plugin_name_;
  CallLimits limits_;
  bool finishing_ = false;  // finish() was called: max_finish_s applies
  InstanceRecord record_;
};

}  // namespace runtime
}  // namespace roam
