// ABI shim: the EKF SLAM core as plugin "ekf"; in a team run ([team] robots = ...) one instance
// runs the centralised team filter (ekf_team.hpp).
#include "ekf_bank.hpp"
#include "ekf_config.hpp"
#include "ekf_slam.hpp"
#include "roam/plugin_shim.hpp"

namespace {

std::unique_ptr<roam::Estimator> makeEkf(roam::Options& options) {
  roam::ekf::EkfConfig config;
  roam::ekf::addEkfOptions(options, &config);
  options.parse();
  // With surveyed beacons, a bank of translation-noise models (ekf_bank.hpp).
  if (config.anchor == roam::ekf::EkfConfig::Anchor::kBeacons && config.translation_noise_models > 1)
    return std::make_unique<roam::ekf::EkfBank>(config);
  return std::make_unique<roam::ekf::EkfSlam>(config);
}

}  // namespace

ROAM_DEFINE_TEAM_PLUGIN("ekf", "Cartesian range-only EKF SLAM with delayed beacon initialisation", makeEkf)
