// What the host drives: one configured estimator, in this process (PluginInstance) or in a child
// process of its own (IsolatedInstance). The host calls the same methods in the same order either
// way, so a replay's output does not depend on where an estimator runs.
//
// Inputs return false (and leave the instance failed) if the estimator fails; a failed instance
// ignores further input and keeps its error. An isolated instance may answer an input call before
// the child has finished it: the next call that needs the answer (failed(), a poll, status())
// waits for it, so the host can hand one event to several children before it reads any answer.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "roam/options.hpp"
#include "roam/plugin_abi.h"

namespace roam {
namespace runtime {

// Time limits on calls into an estimator, in wall-clock seconds; 0 = none.
struct CallLimits {
  double max_update_s = 0.0;  // one input message and the outputs polled after it
  double max_finish_s = 0.0;  // the end of input: finish and the final outputs
};

// What every kind of instance keeps about its estimator: whether and why it failed, and the time
// spent inside the plugin.
struct InstanceRecord {
  bool failed = false;
  std::string error;  // the first failure's
  double cpu_total_s = 0.0, cpu_last_s = 0.0;
  double wall_last_s = 0.0;  // wall-clock seconds of the last update (input and outputs)

  void fail(const std::string& why) {
    if (failed) return;
    failed = true;
    error = why;
  }
};

class EstimatorInstance {
 public:
  virtual ~EstimatorInstance() = default;

  virtual const std::string& name() const = 0;
  virtual const std::string& pluginName() const = 0;
  // The record, once every answer still in flight (on a worker thread, from a child process)
  // has arrived.
  virtual InstanceRecord& record() = 0;
  bool failed() { return record().failed; }
  const std::string& error() { return record().error; }
  double cpuTotalSeconds() { return record().cpu_total_s; }
  double cpuLastSeconds() { return record().cpu_last_s; }
  // For live mode's backlog report.
  double wallLastSeconds() { return record().wall_last_s; }
  // Marks the instance failed from outside (e.g. the host caught something); the first failure
  // is the one kept.
  void markFailed(const std::string& error) { record().fail(error); }
  virtual KeyValues effectiveConfig() = 0;

  // A team estimator's robots, once, before any input (only for a plugin with set_team).
  virtual bool setTeam(const std::vector<std::string>& robots) = 0;
  virtual bool setInitialPose(const roam_pose& pose) = 0;
  virtual bool setBeacons(const std::vector<roam_beacon>& beacons) = 0;
  virtual bool addOdometry(const roam_odometry& odometry) = 0;
  virtual bool addRange(const roam_range& range) = 0;
  // End of input; from here on CallLimits::max_finish_s applies instead of max_update_s.
  virtual bool finish() = 0;

  virtual bool pollPoses(std::vector<roam_pose>* poses) = 0;
  virtual bool pollMap(bool* changed, std::vector<roam_beacon>* beacons) = 0;
  virtual bool pollTrajectory(bool force, bool* available, std::vector<roam_pose>* poses) = 0;

  struct Status {
    int32_t state = ROAM_STATE_INITIALIZING;
    int64_t odometry_accepted = 0, odometry_rejected = 0, ranges_accepted = 0, ranges_rejected = 0;
    std::string last_rejection;
    std::vector<std::string> keys;
    std::vector<double> values;
  };
  virtual Status status() = 0;

  // Runs on the calling thread the job a worker has been handed but not yet started; true if it
  // did (only instances on a worker have such jobs). The host uses it to take a share of the
  // end-of-input solves instead of waiting for one worker to get through its queue.
  virtual bool runQueuedHere() { return false; }
};

}  // namespace runtime
}  // namespace roam
