// ABI shim: the spectral SLAM core as plugin "spectral".
#include "roam/plugin_shim.hpp"
#include "spectral_slam.hpp"

namespace {

std::unique_ptr<roam::Estimator> makeSpectral(roam::Options& options) {
  roam::spectral::SpectralConfig config;
  roam::spectral::addSpectralOptions(options, &config);
  options.parse();
  return std::make_unique<roam::spectral::SpectralSlam>(config);
}

}  // namespace

ROAM_DEFINE_PLUGIN("spectral", "Boots & Gordon 2013 spectral range-only SLAM", makeSpectral)
