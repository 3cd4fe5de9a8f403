// Estimators on worker threads (`[runtime] threads`): the host hands one event to every
// estimator, each on its worker, and reads their outputs in estimator order, so the output log is
// the same whatever the number of threads.
//
// A ThreadedInstance wraps an in-process instance. An input call (and finish) becomes a job on
// the instance's worker that makes the call and polls the outputs after it, in the order the host
// would; the first call that needs the answer waits for the job, or runs it itself if its worker
// has not started it yet (so the host's thread works too, and a job of a few microseconds costs no
// hand-over). Everything else runs on the calling thread once the job is done, so the plugin is
// never called from two threads at once.
#pragma once

#include <atomic>
#include <condition_variable>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "estimator_instance.hpp"

namespace roam {
namespace runtime {

// A fixed set of threads, each running its own queue of jobs in order.
class WorkerPool {
 public:
  explicit WorkerPool(int threads);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;
  int size() const { return static_cast<int>(workers_.size()); }
  void submit(int worker, std::function<void()> job);

 private:
  struct Worker {
    std::mutex mutex;
    std::condition_variable wake;
    std::deque<std::function<void()>> jobs;
    bool stop = false;
    std::thread thread;
  };
  static void run(Worker* worker);
  std::vector<std::unique_ptr<Worker>> workers_;
};

class ThreadedInstance : public EstimatorInstance {
 public:
  ThreadedInstance(std::unique_ptr<EstimatorInstance> inner, WorkerPool* pool, int worker);
  ~ThreadedInstance() override;

  const std::string& name() const override { return inner_->name(); }
  const std::string& pluginName() const override { return inner_->pluginName(); }
  InstanceRecord& record() override;
  KeyValues effectiveConfig() override;

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
  bool runQueuedHere() override { return runIfQueued(); }

 private:
  // Queues `call` for the worker, then polls poses and map (and, at the end of input, the path).
  bool start(std::function<void(EstimatorInstance&)> call, bool with_trajectory);
  // Runs the queued job here if no thread has taken it yet; true if it did.
  bool runIfQueued();
  void settle();

  enum State { kIdle, kQueued, kRunning };
  std::unique_ptr<EstimatorInstance> inner_;
  WorkerPool* pool_;
  int worker_;
  std::function<void()> job_;
  std::atomic<int> state_{kIdle};
  std::atomic<int> queue_entries_{0};  // entries for this instance still in the worker's queue
  std::mutex mutex_;
  std::condition_variable done_;
  // What the job polled, until the host takes it.
  bool poses_fresh_ = false, map_fresh_ = false, trajectory_fresh_ = false;
  std::vector<roam_pose> poses_, trajectory_;
  bool map_changed_ = false, trajectory_available_ = false;
  bool poses_ok_ = false, map_ok_ = false, trajectory_ok_ = false;  // what the polls returned
  std::vector<roam_beacon> beacons_;
};

}  // namespace runtime
}  // namespace roam
