#include "spectral_seed.hpp"

#include <stdexcept>

#ifdef ROAM_HAVE_SPECTRAL
#include "spectral_slam.hpp"
#endif

namespace roam {
namespace spectral_batch {

#ifdef ROAM_HAVE_SPECTRAL

bool spectralSeedAvailable() { return true; }

std::unique_ptr<Estimator> makeSpectralSeed(const SpectralBatchConfig& config) {
  spectral::SpectralConfig spectral;
  spectral.anchor = config.anchor == SpectralBatchConfig::Anchor::kBeacons ? spectral::SpectralAnchor::kBeacons : spectral::SpectralAnchor::kStartPose;
  return std::make_unique<spectral::SpectralSlam>(spectral);
}

#else

bool spectralSeedAvailable() { return false; }

std::unique_ptr<Estimator> makeSpectralSeed(const SpectralBatchConfig& /*config*/) {
  throw std::invalid_argument(
      "spectral_batch: init = spectral, but this build has no spectral core "
      "(plugins/spectral); use init = deadreckoning");
}

#endif

}  // namespace spectral_batch
}  // namespace roam
