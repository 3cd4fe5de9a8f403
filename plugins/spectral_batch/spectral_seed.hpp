// The spectral core (plugins/spectral, Boots & Gordon 2013) as the seed of the batch solve,
// used only through the roam::Estimator interface. Built only when the CMake target
// roam_spectral_core exists (ROAM_HAVE_SPECTRAL); otherwise makeSpectralSeed() throws.
#pragma once

#include <memory>

#include "batch_config.hpp"
#include "roam/estimator.hpp"

namespace roam {
namespace spectral_batch {

// True if this build links the spectral core.
bool spectralSeedAvailable();

// A spectral estimator with the same anchor and odometry gate as `config`.
// Throws std::invalid_argument if the spectral core is not built in.
std::unique_ptr<Estimator> makeSpectralSeed(const SpectralBatchConfig& config);

}  // namespace spectral_batch
}  // namespace roam
