#include "spectral_config.hpp"

namespace roam::spectral {

void addSpectralOptions(Options& o, SpectralConfig* c) {
  o.add("anchor", &c->anchor, {{"beacons", SpectralAnchor::kBeacons}, {"start_pose", SpectralAnchor::kStartPose}},
        "frame anchor: surveyed beacons or the start pose");
  o.add("rank", &c->rank, "4: positions; 7: positions and headings").oneOf({4, 7});
  o.add("mode", &c->mode, {{"batch", SpectralMode::kBatch}, {"online", SpectralMode::kOnline}},
        "batch (all at the end) or online (incremental SVD)");
  o.add("window_s", &c->window_s, "interpolation window length (s); online latency")
      .min(0.0, false);
  o.add("window_ranges_per_beacon", &c->window_ranges_per_beacon,
        "batch: grow the window to hold this many ranges of the least-ranged beacon (0: fixed)")
      .min(0.0);
  o.add("window_max_factor", &c->window_max_factor, "batch: the grown window is at most this x window_s")
      .min(1.0);
  o.add("window_overlap", &c->window_overlap, "fraction of a window shared with the next")
      .min(0.0).max(1.0, false);
  o.add("min_ranges_per_window", &c->min_ranges_per_window,
        "fewest ranges to a beacon for a window to model it").min(4);
  o.add("interpolation_rcond", &c->interpolation_rcond,
        "relative singular-value cut-off of a window's regression").min(0.0).max(1.0, false);
  o.add("robust_interpolation", &c->robust_interpolation,
        "Tukey-weighted window fits (outlier ranges drop out); false: plain least squares");
  o.add("align_m", &c->align_m, "start_pose: metres of travel the path is aligned on")
      .min(0.0, false);
  o.add("start_gauge", &c->start_gauge,
        {{"whole_path", StartGaugeMode::kWholePath}, {"first_stretch", StartGaugeMode::kFirstStretch}},
        "start_pose: rotation and translation from the whole run's odometry, or the first align_m");
  o.add("gauge_about_start", &c->gauge_about_start,
        "start_pose: pose 0 on the start, the path turned about it onto the first align_m of dead reckoning");
  o.add("smooth_with_odometry", &c->smooth_with_odometry,
        "fuse the solved positions with the calibrated odometry's step displacements (frame kept)");
  o.add("smoothing_corrects_headings", &c->smoothing_corrects_headings,
        "smooth_with_odometry: also estimate a correction to each heading that turns the odometry");
  o.add("smoothing_uses_ranges", &c->smoothing_uses_ranges,
        "smooth_with_odometry: the ranges to the re-fitted map instead of the spectral positions");
  o.add("calibrate_odometry", &c->calibrate_odometry,
        "estimate the odometry distance scale and gyro bias against the solution, then solve again");
  o.add("gyro_bias_segment_s", &c->gyro_bias_segment_s,
        "calibrate_odometry: the gyro bias is constant over segments this long (s)").min(0.0, false);
  o.add("max_local_residual_sigma", &c->max_local_residual_sigma,
        "no solution if the windows' median range residual exceeds this x range_sigma_m").min(0.0, false);
  o.add("window_retries", &c->window_retries,
        "windows that do not fit the ranges are doubled and the solve repeated this many times").min(0);
  o.add("max_residual_ratio", &c->max_residual_ratio,
        "no solution if the solution's median range residual exceeds this x the windows'").min(1.0);
  o.add("consistent_residual_ratio", &c->consistent_residual_ratio,
        "a solution whose median range residual exceeds this x the windows' is solved again with "
        "the window doubled (window_retries); the lowest residual is kept (0: off)").min(0.0);
  o.add("outlier_drop_sigmas", &c->outlier_drop_sigmas,
        "after window retries: ranges this many robust sigmas off the solution are left out and "
        "the run solved again from the base window (0: off)").min(0.0);
  o.add("drop_range_jumps", &c->drop_range_jumps,
        "where the run would be refused: leave out each beacon's ranges in stretches entered by a "
        "jump up and left by a jump down beyond the distance travelled between them (NLOS in "
        "stretches) and solve once more");
  addSensorNoiseOptions(o, c, OdometryFloors::kPositive);  // its smoother weighs each step by its noise
}

}  // namespace roam::spectral
