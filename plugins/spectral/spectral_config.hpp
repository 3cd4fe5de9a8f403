// Configuration of the spectral range-only SLAM core (Boots & Gordon, ICML 2013).
//
// Every default is argued from the sensors and the maths (see README/report), never searched
// on a benchmark run. addSpectralOptions() declares every key with its checks: the plugin shim
// parses them, SpectralSlam checks a struct with them (checkConfig), so there is no other validator.
// Fields marked [internal] are internal constants of the method, not INI keys (README, "Internal
// constants"): set them through this struct (unit tests, studies; no bounds are checked on them);
// their defaults are what every run uses.
#pragma once

#include "roam/options.hpp"
#include "roam/sensor_noise.hpp"

namespace roam::spectral {

enum class SpectralAnchor {
  kBeacons,   // least squares to >= 4 surveyed beacons (BEACONS) fixes the frame
  kStartPose  // no surveyed beacons: structure of X, then the start pose and early odometry
};

enum class StartGaugeMode {
  kWholePath,     // start_gauge.hpp: the whole run's odometry, weighted by its noise
  kFirstStretch,  // the first align_m of travel alone
};

enum class SpectralMode {
  kBatch,  // everything at finish()
  kOnline  // Brand's incremental SVD; a pose per step, window_s behind the input
};

// The sensors' stated noise (roam/sensor_noise.hpp, the run's [sensors]): range_sigma_m scales the
// robust fit's first (Huber) stage and the self-check; the odometry noise per step weighs the
// whole_path gauge and the odometry smoother. Then spectral's own keys and internal constants.
struct SpectralConfig : SensorNoise {
  // beacons: the paper's Plaza setting (regression onto surveyed beacons) and the most accurate.
  SpectralAnchor anchor = SpectralAnchor::kBeacons;
  // 4: positions only (Eq. 4-7); 7: positions and headings (Eq. 8-11).
  int rank = 7;
  SpectralMode mode = SpectralMode::kBatch;

  // Interpolation (Sec. 3.4). A window must hold >= 3 ranges per regression parameter (4) for
  // every beacon: UWB round-robin at ~2 Hz over 4 beacons gives ~0.5 Hz per beacon, so 30 s
  // hold ~15; at walking speed that is ~30 m of travel, over which dead reckoning (1-2 % of
  // distance) stays at decimetres. Half-overlapping windows: every pose is averaged over two fits.
  double window_s = 30.0;
  // The window grows to hold window_ranges_per_beacon ranges of the least-ranged beacon, at that
  // beacon's mean rate over the run (N beacons sharing one round-robin radio each get 1/N of its
  // rate: 8 beacons at 2 Hz need ~70 s), up to window_max_factor x window_s. 16 = twice
  // min_ranges_per_window, the margin the 30 s default gives 4 beacons at 2 Hz. 0: fixed window_s.
  // Batch solves only (online mode needs its window before the data arrive: window_s).
  // [internal], these two and the three below: the interpolation's own sizes and cut-offs.
  double window_ranges_per_beacon = 16.0;
  double window_max_factor = 4.0;
  double window_overlap = 0.5;  // fraction of a window shared with the next, in [0, 1)
  // Fewest ranges to one beacon for a window to fit that beacon's model (2 per parameter).
  int min_ranges_per_window = 8;
  // Relative singular-value cut-off of a window's regression (features centred and scaled to
  // unit RMS radius): drops the direction a near-straight stretch does not determine.
  double interpolation_rcond = 1e-3;
  // Robust per-window fit (Tukey's biweight, range_interpolation.hpp): UWB ranges through or
  // around obstacles read metres long, and one such range bends a window's least-squares model
  // for every pose in it. On Gaussian noise the biweight keeps 95 % of the efficiency; on
  // noise-free data it is the least-squares fit. false: the paper's plain least squares.
  // [internal]: the switch exists for the comparison with the paper.
  bool robust_interpolation = true;

  // anchor = start_pose: distance travelled from the start over which the learned path is rotated
  // and translated onto dead reckoning from the start pose (scale and reflection come from the
  // whole path). With learned positions good to ~0.5 m, a 50 m stretch fixes the rotation to
  // ~0.01 rad, while odometry (1-2 % of distance) has drifted by well under a metre. [internal]
  double align_m = 50.0;
  // anchor = start_pose: where the rotation comes from (start_gauge.hpp). first_stretch: one fit
  // over the first align_m. whole_path: every half-window chunk's rotation onto dead reckoning from
  // the start pose, weighted by the heading noise the odometry accumulated up to it and by the
  // learned path's own scatter (robust generalised least squares). Scale and reflection come from
  // the whole path and the translation from the first align_m either way. Default first_stretch:
  // on fresh synthetic seeds whole_path is no better (figure-8 drift: mean 0.50 vs 0.52 m over 12
  // seeds; lawn-mower drift: 0.68 vs 0.57 m over 6): the odometry's heading random walk over the
  // first tens of metres bounds the rotation either way (README). [internal]: a study switch.
  StartGaugeMode start_gauge = StartGaugeMode::kFirstStretch;
  // anchor = start_pose: after the solve (and smooth_with_odometry), pose 0 of the published path
  // is put on the start position and the path turned about it onto the calibrated dead reckoning
  // of the first align_m (spectral_batch's window gauge; spectral_solver.cpp gaugeAboutStart).
  // The solve's own frame (start_gauge) fixes the translation freely, and its first poses sit
  // 0.2-0.5 m off the start on drift figure-8 runs; the rotation about the start, on the smoothed
  // path, is what spectral_batch reaches (README "Round 7"). false: the solve's frame as is.
  // [internal]: a study switch.
  bool gauge_about_start = true;

  // Final step (odometry_smoother.hpp): the solved positions, noise from their own range residuals
  // (sigma_r sqrt(2 / ranges per pose)), fused with the calibrated odometry's step displacements
  // turned by the solved headings, by linear least squares; the frame is kept. The solved path's
  // error sits at periods of ~5-100 s (the windows), where one step of odometry is good to ~1 cm
  // but a pose's spectral position only to decimetres (README "Round 6"). false: the solve as is.
  bool smooth_with_odometry = true;
  // The smoother also estimates a correction to each heading that turns the odometry (a random
  // walk with the odometry's heading noise per step): the rank-4 local-fit headings are one-sided
  // at the path's ends and off there by 30-70 mrad (README "Round 7b"). false: headings as given.
  // [internal]: a study switch (a sub-step of smooth_with_odometry).
  bool smoothing_corrects_headings = true;
  // The smoother takes the ranges themselves (to the solve's map, re-fitted; smoother_ranges.hpp)
  // instead of the spectral positions, which at the path's ends are one window's edge fit (README
  // "Round 8"). Not where the windows' outlier fraction makes outlier-majority windows plausible.
  // false: the spectral positions. [internal]: a study switch (a sub-step of smooth_with_odometry).
  bool smoothing_uses_ranges = true;

  // Estimate the odometry's distance scale and heading-rate (gyro) bias against the spectral
  // solution and solve again with the calibrated odometry (odometry_calibration.hpp). Costs one
  // to three more batch solves; false: the odometry is taken as it is.
  bool calibrate_odometry = true;
  // The gyro bias is taken as constant over segments this long (a continuous piecewise-linear
  // heading error; at least 6 windows each): a MEMS gyro's bias wanders with temperature and bias
  // instability over minutes, and one constant over a half-hour run would turn a late drift into
  // an early error. A run shorter than this gets one constant bias. [internal]
  double gyro_bias_segment_s = 300.0;

  // [internal], everything below: the self-check's thresholds and the retries' counts and switches.
  // Self-check before anything is published (spectral_solver.hpp). The windows' median residual
  // |range - interpolated range| must be at most this x range_sigma_m: on Gaussian noise it is
  // 0.67 sigma, so 3 leaves room for a sigma set at the low end and a few outliers, while windows
  // that outliers or sparse ranges defeated sit at several metres (30 % NLOS: 3.3 m; AUV-like
  // sparse: 18 m).
  double max_local_residual_sigma = 3.0;
  // Windows that fail that test are doubled and the solve repeated, up to this many times: with a
  // third of the ranges far off, a window of ~16 ranges per beacon leaves the minimal-subset start
  // too few clean ranges in too many windows; 4x as many fit (synthetic 30 % NLOS: 48 s windows
  // fail, 192 s give 0.8 m). 0: no retry. 3 reaches 8x: at 30 % outliers 384 s (48 s base).
  int window_retries = 3;
  // The solution's median residual |range - |p - m|| (less a per-beacon offset) must be at most
  // this x the windows' own: a consistent solution explains the ranges about as well as the local
  // fits (synthetic: 1.2x), a wrong one does not (a failed start-pose upgrade: >= 27x; goats16
  // with beacons: 7x). 4 sits between, with room for range scale errors the windows absorb.
  double max_residual_ratio = 4.0;
  // A solution that passes but explains the ranges worse than this x the windows' own residual is
  // not taken at once: the window is doubled (within window_retries) and, of the solutions that
  // pass, the one with the lowest median residual is kept. With a third of the ranges off, a
  // window that passes can still hold beacon-windows with an outlier majority (binomial: 16
  // ranges at 30 % give ~7 % of them); the solution's residual then sits 1.7-4x the windows'
  // (synthetic 30 % NLOS seeds), while consistent ones sit at 1.0-1.3x. 0: off (first pass taken).
  double consistent_residual_ratio = 1.5;
  // Only where the retries grew the window (outliers): ranges farther than this many robust sigmas
  // (1.4826 x the median |residual|, at least range_sigma_m) off the long-window solution are left
  // out and the run is solved again from the base window; the second solution is kept if it
  // explains all the ranges at least as well. 3: three sigmas of a Gaussian (0.3 % of inliers).
  // 0: off.
  double outlier_drop_sigmas = 3.0;
  // Where the run would be refused (no solution), each beacon's ranges in stretches entered by a
  // jump up and left by a jump down, beyond what the robot can have travelled between them
  // (range_jumps.hpp: NLOS in stretches, or half the ranges NLOS), are left out and the run is
  // solved once more under the same self-check; where that fails too, the first reason stands.
  // Only on the refusal path: where the run solves, its robust windows already carry range-by-
  // range outliers better than dropping them (30 % NLOS, beacons: 0.20 -> 0.35-0.52 m median
  // with the drop always on, seeds 301-310). false: refuse as before.
  bool drop_range_jumps = true;
};

// Registers every key of the [estimator.*] section with its checks (the shim calls parse()). The
// [internal] fields are not keys.
void addSpectralOptions(Options& options, SpectralConfig* config);

}  // namespace roam::spectral
