// Plugins that fail on purpose, built from the real SDK:
//   create_fails  — its factory throws (as a plugin does when a resource is missing);
//   throws        — dead reckoning that throws from addOdometry after `fail_after` steps.
#include <stdexcept>

#include "roam/plugin_shim.hpp"

namespace {

class ThrowingEstimator : public roam::Estimator {
 public:
  explicit ThrowingEstimator(int fail_after) : fail_after_(fail_after) {}
  void addOdometry(const roam::Odometry& odometry) override {
    if (++steps_ > fail_after_) throw std::runtime_error("deliberate failure at step " + std::to_string(steps_));
    acceptOdometry();
    roam::Pose pose;
    pose.utime = odometry.utime;
    emitPose(pose);
  }
  void addRange(const roam::Range&) override {}

 private:
  int fail_after_;
  int steps_ = 0;
};

std::unique_ptr<roam::Estimator> makeFaulty(roam::Options& options) {
  int fail_after = 10;
  options.add("fail_after", &fail_after, "steps before the deliberate failure").min(0);
  options.parse();
#ifdef ROAM_FAULTY_CREATE_FAILS
  throw std::runtime_error("deliberate create failure");
#endif
  return std::make_unique<ThrowingEstimator>(fail_after);
}

}  // namespace

ROAM_DEFINE_PLUGIN(ROAM_FAULTY_NAME, "a deliberately failing plugin for the loader's tests", makeFaulty)
