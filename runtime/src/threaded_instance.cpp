#include "threaded_instance.hpp"

namespace roam {
namespace runtime {

WorkerPool::WorkerPool(int threads) {
  for (int i = 0; i < threads; ++i) {
    workers_.push_back(std::make_unique<Worker>());
    workers_.back()->thread = std::thread(run, workers_.back().get());
  }
}

WorkerPool::~WorkerPool() {
  for (auto& worker : workers_) {
    {
      std::lock_guard<std::mutex> lock(worker->mutex);
      worker->stop = true;
    }
    worker->wake.notify_one();
  }
  for (auto& worker : workers_) worker->thread.join();
}

void WorkerPool::submit(int worker, std::function<void()> job) {
  Worker& w = *workers_[static_cast<size_t>(worker) % workers_.size()];
  {
    std::lock_guard<std::mutex> lock(w.mutex);
    w.jobs.push_back(std::move(job));
  }
  w.wake.notify_one();
}

void WorkerPool::run(Worker* worker) {
  for (;;) {
    std::function<void()> job;
    {
      std::unique_lock<std::mutex> lock(worker->mutex);
      worker->wake.wait(lock, [&] { return worker->stop || !worker->jobs.empty(); });
      if (worker->jobs.empty()) return;  // stop, and nothing left to do
      job = std::move(worker->jobs.front());
      worker->jobs.pop_front();
    }
    job();
  }
}

ThreadedInstance::ThreadedInstance(std::unique_ptr<EstimatorInstance> inner, WorkerPool* pool, int worker)
    : inner_(std::move(inner)), pool_(pool), worker_(worker) {}

ThreadedInstance::~ThreadedInstance() {
  settle();
  // A job the host's thread ran itself leaves an entry in the worker's queue: wait it out.
  while (queue_entries_.load() > 0) std::this_thread::yield();
}

bool ThreadedInstance::runIfQueued() {
  int expected = kQueued;
  if (!state_.compare_exchange_strong(expected, kRunning)) return false;
  job_();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    state_.store(kIdle);
  }
  done_.notify_all();
  return true;
}

void ThreadedInstance::settle() {
  if (state_.load() == kIdle || runIfQueued()) return;
  // Running on the worker: most jobs take microseconds, so look a few times before sleeping.
  for (int i = 0; i < 200; ++i) {
    if (state_.load() == kIdle) return;
    std::this_thread::yield();
  }
  std::unique_lock<std::mutex> lock(mutex_);
  done_.wait(lock, [&] { return state_.load() == kIdle; });
}

bool ThreadedInstance::start(std::function<void(EstimatorInstance&)> call, bool with_trajectory) {
  settle();
  if (inner_->failed()) return false;
  job_ = [this, call = std::move(call), with_trajectory] {
    EstimatorInstance& inner = *inner_;
    call(inner);
    // The host's order after an input: poses, then the map (only if not failed), then at the end
    // of input the path.
    poses_ok_ = map_ok_ = trajectory_ok_ = false;
    bool changed = false;
    std::vector<roam_beacon> beacons;
    if (!inner.failed()) {
      std::vector<roam_pose> poses;
      poses_ok_ = inner.pollPoses(&poses);
      poses_.insert(poses_.end(), poses.begin(), poses.end());
      map_ok_ = inner.pollMap(&changed, &beacons);
    }
    if (changed) {
      map_changed_ = true;
      beacons_ = std::move(beacons);
    }
    poses_fresh_ = map_fresh_ = true;
    if (with_trajectory) {
      trajectory_fresh_ = true;
      trajectory_available_ = false;
      trajectory_.clear();
      if (!inner.failed()) trajectory_ok_ = inner.pollTrajectory(true, &trajectory_available_, &trajectory_);
    }
  };
  state_.store(kQueued);
  queue_entries_.fetch_add(1);
  pool_->submit(worker_, [this] {
    runIfQueued();
    queue_entries_.fetch_sub(1);
  });
  return true;
}

InstanceRecord& ThreadedInstance::record() {
  settle();
  return inner_->record();
}

KeyValues ThreadedInstance::effectiveConfig() {
  settle();
  return inner_->effectiveConfig();
}

bool ThreadedInstance::setTeam(const std::vector<std::string>& robots) {
  return start([robots](EstimatorInstance& inner) { inner.setTeam(robots); }, false);
}

bool ThreadedInstance::setInitialPose(const roam_pose& pose) {
  return start([pose](EstimatorInstance& inner) { inner.setInitialPose(pose); }, false);
}

bool ThreadedInstance::setBeacons(const std::vector<roam_beacon>& beacons) {
  return start([beacons](EstimatorInstance& inner) { inner.setBeacons(beacons); }, false);
}

bool ThreadedInstance::addOdometry(const roam_odometry& odometry) {
  return start([odometry](EstimatorInstance& inner) { inner.addOdometry(odometry); }, false);
}

bool ThreadedInstance::addRange(const roam_range& range) {
  return start([range](EstimatorInstance& inner) { inner.addRange(range); }, false);
}

bool ThreadedInstance::finish() {
  return start([](EstimatorInstance& inner) { inner.finish(); }, true);
}

bool ThreadedInstance::pollPoses(std::vector<roam_pose>* poses) {
  settle();
  if (!poses_fresh_) return inner_->pollPoses(poses);
  poses->swap(poses_);
  poses_.clear();
  poses_fresh_ = false;
  return poses_ok_;
}

bool ThreadedInstance::pollMap(bool* changed, std::vector<roam_beacon>* beacons) {
  settle();
  if (!map_fresh_) return inner_->pollMap(changed, beacons);
  *changed = map_changed_;
  beacons->swap(beacons_);
  beacons_.clear();
  map_changed_ = map_fresh_ = false;
  return map_ok_;
}

bool ThreadedInstance::pollTrajectory(bool force, bool* available, std::vector<roam_pose>* poses) {
  settle();
  if (!trajectory_fresh_ || !force) return inner_->pollTrajectory(force, available, poses);
  *available = trajectory_available_;
  poses->swap(trajectory_);
  trajectory_.clear();
  trajectory_fresh_ = false;
  return trajectory_ok_;
}

EstimatorInstance::Status ThreadedInstance::status() {
  settle();
  return inner_->status();
}

}  // namespace runtime
}  // namespace roam
