// ABI shim: the dead-reckoning core as plugin "deadreckoning".
#include "dead_reckoning.hpp"
#include "roam/plugin_shim.hpp"

namespace {

std::unique_ptr<roam::Estimator> makeDeadReckoning(roam::Options& options) {
  roam::DeadReckoningConfig config;
  options.add("max_step_m", &config.max_step_m, "odometry steps longer than this are rejected")
      .min(0.0, false);
  options.parse();
  return std::make_unique<roam::DeadReckoning>(config);
}

}  // namespace

ROAM_DEFINE_PLUGIN("deadreckoning", "integrates odometry from the start pose", makeDeadReckoning)
