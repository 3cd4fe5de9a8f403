// Plugins that go wrong the way native code does, built from the real SDK, for the fault tests:
//   crashes — a segmentation fault (a store through a null pointer) at step fail_after + 1;
//   aborts  — abort() there (as a failed assert does);
//   hangs   — sleeps there for hang_s seconds (default: for ever), once or at every step after;
//   hungry  — allocates and touches hunger_mb megabytes there.
// Before that step each one publishes a pose per odometry step, like a working estimator.
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <memory>
#include <vector>

#include "roam/plugin_shim.hpp"

namespace {

struct Misbehaviour {
  int fail_after = 10;
  double hang_s = 0.0;  // 0: for ever
  bool hang_every_step = false;
  int hunger_mb = 4096;
};

class MisbehavingEstimator : public roam::Estimator {
 public:
  explicit MisbehavingEstimator(Misbehaviour config) : config_(config) {}
  void addOdometry(const roam::Odometry& odometry) override {
    if (++steps_ > config_.fail_after) misbehave();
    acceptOdometry();
    roam::Pose pose;
    pose.utime = odometry.utime;
    pose.x_m = static_cast<double>(steps_);
    emitPose(pose);
  }
  void addRange(const roam::Range&) override {}

 private:
  void misbehave() {
#if defined(ROAM_MISBEHAVE_CRASH)
    volatile int* volatile nowhere = nullptr;
    *nowhere = 42;
#elif defined(ROAM_MISBEHAVE_ABORT)
    std::abort();
#elif defined(ROAM_MISBEHAVE_HANG)
    if (steps_ != config_.fail_after + 1 && !config_.hang_every_step) return;
    if (config_.hang_s <= 0.0) {
      for (;;) ::pause();
    }
    ::usleep(static_cast<useconds_t>(config_.hang_s * 1e6));
#elif defined(ROAM_MISBEHAVE_HUNGRY)
    for (int mb = 0; mb < config_.hunger_mb; mb += 64) {
      hoard_.push_back(std::make_unique<char[]>(64u << 20));
      std::memset(hoard_.back().get(), 1, 64u << 20);
    }
#endif
  }
  Misbehaviour config_;
  int steps_ = 0;
  std::vector<std::unique_ptr<char[]>> hoard_;
};

std::unique_ptr<roam::Estimator> makeMisbehaving(roam::Options& options) {
  Misbehaviour config;
  options.add("fail_after", &config.fail_after, "steps before the misbehaviour").min(0);
  options.add("hang_s", &config.hang_s, "hangs: seconds to sleep (0: for ever)").min(0.0);
  options.add("hang_every_step", &config.hang_every_step, "hangs: sleep at every step after fail_after");
  options.add("hunger_mb", &config.hunger_mb, "hungry: megabytes to allocate").min(0);
  options.parse();
  return std::make_unique<MisbehavingEstimator>(config);
}

}  // namespace

ROAM_DEFINE_PLUGIN(ROAM_FAULTY_NAME, "a plugin that crashes, aborts, hangs or eats memory, for the fault tests",
                   makeMisbehaving)
