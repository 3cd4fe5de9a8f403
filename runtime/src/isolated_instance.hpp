// An estimator in a child process of roam-run (`isolation = process`): a plugin that crashes,
// aborts, hangs or runs out of memory takes only its own process down.
//
// The child is a fork of roam-run made before any data is read; it creates the plugin instance
// and answers requests over a socketpair, one at a time, in the order the host makes them, so
// the estimator sees exactly the calls it would see in process and a replay's output is the same.
// An input request is answered with the outputs polled after it; the host reads the answer only
// when it needs it, so several isolated estimators work on one event at the same time.
//
// A child that dies is reported with how it died (the signal's name) and the request it was
// given; one that does not answer within max_update_s (max_finish_s at the end of input) is
// killed. Either way the instance is failed, with the last status it reported, marked FAILED.
#pragma once

#include <sys/types.h>

#include <memory>
#include <string>
#include <vector>

#include "estimator_instance.hpp"
#include "plugin_library.hpp"

namespace roam {
namespace runtime {

struct IsolationLimits {
  CallLimits calls;
  double max_memory_mb = 0.0;  // address space the child may add to what it starts with (RLIMIT_AS); 0 = none
};

class IsolatedInstance : public EstimatorInstance {
 public:
  // Forks the child and creates the instance in it; throws PluginConfigError if the plugin
  // refuses its config, PluginError if the child dies or cannot be started.
  IsolatedInstance(std::shared_ptr<PluginLibrary> library, std::string name, const KeyValues& config,
                   IsolationLimits limits);
  ~IsolatedInstance() override;
  IsolatedInstance(const IsolatedInstance&) = delete;
  IsolatedInstance& operator=(const IsolatedInstance&) = delete;

  const std::string& name() const override { return name_; }
  const std::string& pluginName() const override { return plugin_name_; }
  InstanceRecord& record() override;
  KeyValues effectiveConfig() override { return effective_; }

  bool setTeam(const std::vector<std::string>& robots) override;
  bool setInitialPose(const roam_pose& pose) override;
  bool setBeacons(const std::vector<roam_beacon>& beacons) override;
  bool addOdometry(const roam_odometry& odometry) override;
  bool addRange(const roam_range& range) override;
  bool finish() override;

  bool pollPoses(std::vector<roam_pose>* poses) override;
  bool pollMap(bool* changed, std::vector<roam_beacon>* beacons) override;
  bool pollTrajectory(bool force, bool* available, std::vector<roam_pose>* poses) override;

  Status status() override;

  pid_t pid() const { return pid_; }

 private:
  // Sends one request (kind byte first); false if the child is gone.
  bool send(const std::vector<uint8_t>& request, std::string what);
  // Reads the answer to the request in flight, if any, and applies it.
  void settle();
  // The child died or was ended: reap it and fail with how, naming the request in flight.
  void childGone(const std::string& how);
  std::string reapAndDescribe(bool wait);

  std::string name_, plugin_name_;
  IsolationLimits limits_;
  pid_t pid_ = -1;
  int fd_ = -1;
  bool alive_ = false;
  bool finishing_ = false;
  bool pending_ = false;
  double sent_at_s_ = 0.0;
  std::string in_flight_;  // "add_odometry of the message at utime 123"
  InstanceRecord record_;
  KeyValues effective_;
  // Outputs the child polled after the last input, not yet taken by the host.
  std::vector<roam_pose> poses_;
  bool poses_fresh_ = false, map_fresh_ = false, map_changed_ = false;
  std::vector<roam_beacon> beacons_;
  bool trajectory_available_ = false;
  std::vector<roam_pose> trajectory_;
  Status last_status_;
  std::vector<uint8_t> frame_;
};

}  // namespace runtime
}  // namespace roam
