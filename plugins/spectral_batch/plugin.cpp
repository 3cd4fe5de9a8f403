// ABI shim: the spectral + batch (Ceres) SLAM core as plugin "spectral_batch".
#include "batch_config.hpp"
#include "roam/plugin_shim.hpp"
#include "spectral_batch_slam.hpp"

namespace {

std::unique_ptr<roam::Estimator> makeSpectralBatch(roam::Options& options) {
  roam::spectral_batch::SpectralBatchConfig config;
  roam::spectral_batch::addSpectralBatchOptions(options, &config);
  options.parse();
  return std::make_unique<roam::spectral_batch::SpectralBatchSlam>(config);
}

}  // namespace

ROAM_DEFINE_TEAM_PLUGIN("spectral_batch",
                   "Ceres batch range-only SLAM seeded by spectral SLAM or dead reckoning",
                   makeSpectralBatch)
