// ABI shim: the dead-reckoning core as plugin "deadreckoning".
#include "dead_reckoning.hpp"
#include "roam/plugin_shim.hpp"

namespace {

std::unique_ptr<roam::Estimator> makeDeadReckoning(roam::Options& options) {
  options.parse();  // no keys of its own: max_speed_mps and max_range_m are the SDK's
  return std::make_unique<roam::deadreckoning::DeadReckoning>();
}

}  // namespace

ROAM_DEFINE_PLUGIN("deadreckoning", "integrates odometry from the start pose", makeDeadReckoning)
