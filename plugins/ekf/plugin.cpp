// ABI shim: the EKF SLAM core as plugin "ekf".
#include "ekf_config.hpp"
#include "ekf_slam.hpp"
#include "roam/plugin_shim.hpp"

namespace {

std::unique_ptr<roam::Estimator> makeEkf(roam::Options& options) {
  roam::ekf::EkfConfig config;
  roam::ekf::addEkfOptions(options, &config);
  options.parse();
  return std::make_unique<roam::ekf::EkfSlam>(config);
}

}  // namespace

ROAM_DEFINE_PLUGIN("ekf", "Cartesian range-only EKF SLAM with delayed beacon initialisation", makeEkf)
