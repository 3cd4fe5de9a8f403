// Configuration of the ekf plugin, with the reasoning behind each default (see README.md).
#pragma once

#include "roam/estimation/motion_model.hpp"
#include "roam/calibration_priors.hpp"
#include "roam/options.hpp"
#include "roam/sensor_noise.hpp"

namespace roam {
namespace ekf {

// The sensors' stated noise (roam/sensor_noise.hpp, the run's [sensors]: odometry noise per step,
// range_sigma_m, bearing_sigma_rad), then the EKF's own keys. Fields marked [internal] are
// internal constants of the algorithm, not INI keys (README, "Internal constants"): set them
// through this struct (unit tests, studies; no bounds are checked on them); their defaults are
// what every run uses.
struct EkfConfig : SensorNoise {
  // start_pose: the INITIAL_POSE is exact and every beacon is initialised from ranges;
  // beacons: the BEACONS message gives a prior on each beacon (sigma beacon_sigma_m).
  enum class Anchor { kStartPose, kBeacons };
  // none: ranges are unbiased; shared: one range scale and offset for all beacons, estimated.
  enum class RangeBias { kNone, kShared };
  Anchor anchor = Anchor::kStartPose;
  double beacon_sigma_m = 0.1;             // surveyed beacon position, 1 sigma per axis
  double start_sigma_m = 0.5;              // anchor = beacons: prior on the start position
  double start_heading_sigma_rad = 0.05;   // anchor = beacons: prior on the start heading

  // anchor = beacons: a bank of filters whose odometry translation noise (odo_distance_sigma_rel
  // and _m) is 1 ... translation_noise_max_factor times configured, at geometric steps, run side
  // by side; the one whose ranges were predicted best (EkfSlam::predictiveLogLikelihood) is
  // published (multiple-model adaptive estimation). A stated odometry noise is a floor, not the
  // truth (GOATS 16 states 2 cm per edge for ~1 m). 1 model: the configured noise alone.
  int translation_noise_models = 4;
  double translation_noise_max_factor = 10.0;  // [internal] sigma factor: 2 % -> 20 % per metre
  // A model whose log-likelihood falls this far behind the best is dropped (a Bayes factor of
  // e^20); 0: none is dropped. [internal]
  double translation_noise_drop_nats = 20.0;
  // anchor = beacons: each model of the bank has a twin with gyro_bias_max_drift_rad = 0 (the
  // heading-rate bias estimated at any rate), chosen where its range log-likelihood beats the
  // best held model's by half the 1-dof chi-square quantile at gate_probability (ekf_bank.hpp).
  bool gyro_bias_twins = true;

  // Odometry calibration as filter states (estimation::OdometryCalibration): distance scale s
  // (prior 1 +- kDistanceScalePriorSigma) and heading-rate bias b (prior 0 +-
  // kHeadingRateBiasPriorSigma_rad_s: the SDK's roam/calibration_priors.hpp, every estimator's),
  // random walk gyro_bias_walk_rad_s_per_sqrt_s.
  bool estimate_odometry_calibration = true;
  double gyro_bias_walk_rad_s_per_sqrt_s = 1e-5;
  // Observability of the heading-rate bias from the ranges (estimation::BiasObservability): the
  // heading is re-fixed about every three position fixes; if the bias prior turns the heading by
  // more than this over that time (kHeadingRateBiasPriorSigma_rad_s x 3 x the mean interval
  // between the fix times of the first 20 ranges), the EKF's heading leaves its linear regime
  // before the ranges can observe the bias, and the bias is fixed at 0 instead (sparse, AUV-like
  // data), with a note at the end of the run. The shared kHeadingRateBiasMaxDrift_rad (0.08 rad,
  // roam/calibration_priors.hpp says why); 0: always estimate it.
  double gyro_bias_max_drift_rad = kHeadingRateBiasMaxDrift_rad;
  // Zero-rate update below this speed (the robot stands still: its reported turn is the bias).
  double stationary_speed_mps = 0.02;
  // ... in this many steps in a row, each turning at the rate of the one before (within the gate).
  // [internal]: one step at one rate is noise; a run of them is a standstill's bias.
  int stationary_min_steps = 5;
  // anchor = start_pose: re-filter the run once from the start when the bias sigma falls to
  // this fraction of its prior (0: never). [internal]
  double calib_rerun_fraction = 0.1;
  // TRAJECTORY: the filtered path smoothed backwards (Rauch-Tung-Striebel, ekf_smoother.hpp);
  // false: the filtered path. POSE messages are the filter's either way.
  bool smooth_trajectory = true;
  // What the smoother may keep (its operations grow with the run: ~1.5 kB per step with 4
  // beacons, O(state size)); past it the oldest poses keep their filtered estimate. 256 MB is
  // ~10 h of a 5 Hz run with 4 beacons. [internal]
  double smooth_max_memory_mb = 256.0;
  // Live (the host's periodic TRAJECTORY request before the end of input): the backward pass
  // runs over the last smooth_live_lag_s of data only (and every pose since the previous
  // request); older poses keep the smoothed values they were last published with. A whole pass
  // per request cost O(run length), 70 ms per request at the end of Plaza 1, and stalled the
  // live host. At the end of input the whole pass runs, so the final TRAJECTORY is unchanged.
  // 60 s: a range's smoothing effect on a pose fades as the odometry between them grows
  // uncertain (at UWB rates a pose is re-fixed within seconds). 0: the whole pass every time.
  // [internal]
  double smooth_live_lag_s = 60.0;

  // Range noise: max(the message's sigma, range_sigma_m) (a stated sigma is a floor, not truth).
  RangeBias range_bias = RangeBias::kShared;
  // The scale's prior (mean 1) is the shared kRangeScalePriorSigma (roam/calibration_priors.hpp).
  double range_offset_sigma_m = 0.5;       // prior on the offset (mean 0)
  // Per-beacon range offsets: each surveyed beacon's ranges carry its own offset o_b (an acoustic
  // transponder's turn-around delay, a UWB anchor's antenna delay), a state with prior
  // 0 +- beacon_range_offset_sigma_m, on top of the shared offset (0: none). anchor = beacons only.
  double beacon_range_offset_sigma_m = 1.5;

  // Huber threshold (innovation sigmas) of the range update: beyond it a range is down-weighted
  // by k / |z|; 1.345 is 95 % efficient on Gaussian noise (0: plain EKF update). [internal]
  double range_huber_k = 1.345;
  double gate_probability = 0.999;         // Mahalanobis gate; 1 disables gating
  // [internal], with every recover_* and lost_beacon_gated_ranges below: the recovery's triggers.
  // Starvation: after this many ranges to known beacons gated in a row, the filter is taken as
  // lost and its position variance is widened by the smallest of their squared innovations.
  int recover_after_gated = 8;
  // ... or after this many ranges to one beacon gated in a row (none applied between) whose
  // innovations agree within the gate's width (sqrt(chi2) x the range's sigma): outliers scatter
  // over tens of metres, a lost filter's ranges repeat one innovation (0: never).
  int recover_consistent_gated = 4;
  // ... and, where the repeated innovation is an excess (ranges long), only where one position
  // error explains it: that innovation and the innovations of the other surveyed beacons applied
  // since its run began must all fit |d_b - e| - |d_b| for one offset e (d_b the beacon less the
  // robot; each within the gate of its own innovation variance). A beacon out of sight for a
  // while (a wall, a hull: NLOS in stretches) repeats one excess while the others' ranges pass
  // with none; a lost filter is off against every beacon not square to its error. A blocked line
  // of sight only lengthens a path, so repeated short ranges are the filter's either way. Needs
  // three beacons in two directions; fewer: the run alone decides.
  bool recover_consistent_fit = true;
  // ... and where a surveyed beacon's repeated innovation is a shortfall that its own range offset,
  // long by at least as much, would take back (within the gate's width), and no one position
  // error explains it, that offset took up an excess (a stretch of NLOS ranges agree as a real
  // offset would): its variance is re-opened by the shortfall instead of the pose's.
  bool recover_offset_reopen = true;
  // ... and the widening is put on trial: the filter runs on without it while the next this many
  // ranges to known beacons are scored, then the steps since are re-run with it, and whichever
  // run explains those ranges better (outlier-mixture likelihood) is kept. With half the ranges
  // outliers a run of 8 gated ones comes by chance about twice in 1000 ranges; a filter that is
  // not lost then widens onto the next outlier (0: the widening is applied at once).
  int recover_trial_ranges = 32;
  // A beacon placed from the ranges (no survey) whose last this many ranges were all gated is lost:
  // re-solved from those ranges alone (their filtered poses; the initialisation's solve and
  // checks), and moved there, with the initialisation's weak prior, where they place it outside
  // the gate of where the filter has it and the new place explains more of its last
  // init_max_ranges ranges, applied and gated, than the old. 0: never.
  int lost_beacon_gated_ranges = 12;
  // Each recovery also multiplies the odometry covariance by 4 (up to motion_noise_max_scale);
  // each applied range multiplies it by motion_noise_decay (down to 1). [internal]: the recovery's
  // inflation, 400 = a sigma 20 x configured; 0.95: ~27 applied ranges undo one recovery's x4.
  double motion_noise_max_scale = 400.0;
  double motion_noise_decay = 0.95;
  // Largest factor on the range variance when applied ranges' NIS averages above 2 (1: off).
  // [internal]: a sigma up to 4 x stated.
  double range_noise_max_scale = 16.0;
  // Delayed initialisation (anchor = start_pose, or beacons not in BEACONS). [internal], every
  // init_*: the multilateration's acceptance checks and buffers (init_max_ranges >= init_min_ranges).
  int init_min_ranges = 6;                 // more than the 4 unknowns (beacon, scale, offset)
  double init_min_baseline_m = 3.0;        // cheap pre-check before the solve
  double init_max_sigma_m = 1.0;           // the beacon's marginal sigma accepted
  double init_min_angle_rad = 1.0;         // ~57 deg: range intersection dilution <= ~2
  double init_mirror_chi2 = 16.0;          // evidence ratio e^8 ~ 3000 : 1 over the mirror
  int init_max_ranges = 200;               // buffer per pending beacon (oldest dropped)
  double init_window_s = 600.0;            // buffered ranges older than this are dropped
  double init_prior_inflation = 100.0;     // batch covariance x this = prior before re-applying
  // anchor = start_pose: once every beacon seen so far is in the state, the window from the start
  // solved jointly, path and map (ekf_window_init.cpp), used where its ranges refute the
  // dead-reckoned path; its beacons enter with their solve's covariance x
  // init_window_prior_inflation (1: the window has fixed their frame; x100 let the re-run turn
  // the map back, nlos 301-310 mean 0.60 against 0.52 m).
  bool init_window_solve = true;
  double init_window_block_s = 5.0;        // the path's heading error: constant over blocks this long
  double init_window_prior_inflation = 1.0;
};

// Registers every key of the [estimator.*] section with its checks (the shim calls parse();
// EkfSlam runs the same checks on a struct with checkConfig): the only validator. The [internal]
// fields are not keys.
void addEkfOptions(Options& options, EkfConfig* config);

// The configured noise of one odometry step as the floor of estimation::incrementCovariance:
// sigma_d (forward and lateral) from odo_distance_sigma_rel and _m, sigma_theta from the
// odo_heading_* keys (variances add), used as the per-step minimum; a reported covariance is used
// where it is larger. The one-robot filter and the team filter (ekf_team.hpp) both step with it.
estimation::MotionNoise configuredMotionNoise(const EkfConfig& config, const Odometry& odometry);

// Chi-square quantile for dof = 1 or 2 at the given probability (infinity for probability 1).
double chiSquareQuantile(int dof, double probability);
// The chi-square quantile for any dof >= 1 by the Wilson-Hilferty approximation (within ~1 % of
// the exact quantile beyond a few dof); the EKF's early-window gate (one dof per heading block).
double chiSquareQuantileWilsonHilferty(int dof, double probability);

}  // namespace ekf
}  // namespace roam
