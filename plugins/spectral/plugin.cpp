// ABI shim: the spectral SLAM core as plugin "spectral".
#include <string>

#include "roam/plugin_shim.hpp"
#include "spectral_slam.hpp"

namespace {

std::unique_ptr<roam::Estimator> makeSpectral(roam::Options& options) {
  roam::spectral::SpectralConfig config;
  std::string anchor = "beacons", mode = "batch";
  options.add("anchor", &anchor, "frame anchor: surveyed beacons or the start pose")
      .oneOf({"beacons", "start_pose"});
  options.add("rank", &config.rank, "4: positions; 7: positions and headings").oneOf({4, 7});
  options.add("mode", &mode, "batch (all at the end) or online (incremental SVD)").oneOf({"batch", "online"});
  options.add("window_s", &config.window_s, "interpolation window length (s); online latency")
      .min(0.0, false);
  options.add("window_ranges_per_beacon", &config.window_ranges_per_beacon,
              "batch: grow the window to hold this many ranges of the least-ranged beacon (0: fixed)")
      .min(0.0);
  options.add("window_max_factor", &config.window_max_factor, "batch: the grown window is at most this x window_s")
      .min(1.0);
  options.add("window_overlap", &config.window_overlap, "fraction of a window shared with the next")
      .min(0.0).max(1.0, false);
  options.add("min_ranges_per_window", &config.min_ranges_per_window,
              "fewest ranges to a beacon for a window to model it").min(4);
  options.add("interpolation_rcond", &config.interpolation_rcond,
              "relative singular-value cut-off of a window's regression").min(0.0).max(1.0, false);
  options.add("robust_interpolation", &config.robust_interpolation,
              "Tukey-weighted window fits (outlier ranges drop out); false: plain least squares");
  options.add("range_sigma_m", &config.range_sigma_m, "range noise (m): the robust fit's Huber scale")
      .min(0.0, false);
  options.add("align_m", &config.align_m, "start_pose: metres of travel the path is aligned on")
      .min(0.0, false);
  options.add("calibrate_odometry", &config.calibrate_odometry,
              "estimate the odometry distance scale and gyro bias against the solution, then solve again");
  options.add("gyro_bias_segment_s", &config.gyro_bias_segment_s,
              "calibrate_odometry: the gyro bias is constant over segments this long (s)").min(0.0, false);
  options.add("max_local_residual_sigma", &config.max_local_residual_sigma,
              "no solution if the windows' median range residual exceeds this x range_sigma_m").min(0.0, false);
  options.add("window_retries", &config.window_retries,
              "windows that do not fit the ranges are doubled and the solve repeated this many times").min(0);
  options.add("max_residual_ratio", &config.max_residual_ratio,
              "no solution if the solution's median range residual exceeds this x the windows'").min(1.0);
  options.add("consistent_residual_ratio", &config.consistent_residual_ratio,
              "a solution whose median range residual exceeds this x the windows' is solved again with "
              "the window doubled (window_retries); the lowest residual is kept (0: off)").min(0.0);
  options.parse();
  config.anchor = roam::spectral::parseSpectralAnchor(anchor);
  config.mode = roam::spectral::parseSpectralMode(mode);
  return std::make_unique<roam::spectral::SpectralSlam>(config);
}

}  // namespace

ROAM_DEFINE_PLUGIN("spectral", "Boots & Gordon 2013 spectral range-only SLAM", makeSpectral)
