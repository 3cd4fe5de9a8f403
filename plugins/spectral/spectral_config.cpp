#include "spectral_config.hpp"

#include <cmath>
#include <stdexcept>

namespace roam::spectral {

void SpectralConfig::validate() const {
  auto fail = [](const std::string& what) { throw std::invalid_argument("spectral: " + what); };
  if (rank != 4 && rank != 7) fail("rank must be 4 or 7, got " + std::to_string(rank));
  if (!(window_s > 0.0) || !std::isfinite(window_s)) fail("window_s must be > 0");
  if (!(window_ranges_per_beacon >= 0.0) || !std::isfinite(window_ranges_per_beacon))
    fail("window_ranges_per_beacon must be >= 0");
  if (!(range_sigma_m > 0.0) || !std::isfinite(range_sigma_m)) fail("range_sigma_m must be > 0");
  if (!(window_max_factor >= 1.0) || !std::isfinite(window_max_factor)) fail("window_max_factor must be >= 1");
  if (!(window_overlap >= 0.0 && window_overlap < 1.0)) fail("window_overlap must be in [0, 1)");
  if (!(gyro_bias_segment_s > 0.0)) fail("gyro_bias_segment_s must be > 0");
  if (!(max_local_residual_sigma > 0.0)) fail("max_local_residual_sigma must be > 0");
  if (!(max_residual_ratio >= 1.0)) fail("max_residual_ratio must be >= 1");
  if (!(consistent_residual_ratio >= 0.0)) fail("consistent_residual_ratio must be >= 0");
  if (window_retries < 0) fail("window_retries must be >= 0");
  if (min_ranges_per_window < 4)
    fail("min_ranges_per_window must be >= 4 (the model has 4 parameters)");
  if (!(interpolation_rcond >= 0.0 && interpolation_rcond < 1.0))
    fail("interpolation_rcond must be in [0, 1)");
  if (!(align_m > 0.0) || !std::isfinite(align_m)) fail("align_m must be > 0");
}

SpectralAnchor parseSpectralAnchor(const std::string& text) {
  if (text == "beacons") return SpectralAnchor::kBeacons;
  if (text == "start_pose") return SpectralAnchor::kStartPose;
  throw std::invalid_argument("spectral: anchor must be beacons | start_pose, got '" + text + "'");
}

SpectralMode parseSpectralMode(const std::string& text) {
  if (text == "batch") return SpectralMode::kBatch;
  if (text == "online") return SpectralMode::kOnline;
  throw std::invalid_argument("spectral: mode must be batch | online, got '" + text + "'");
}

}  // namespace roam::spectral
