// Configuration of the spectral_batch plugin (Ceres batch range-only SLAM), with the reasoning
// behind each default. Defaults come from the sensors' stated noise and the maths, never from a
// search on a benchmark run. Fields marked "Internal constant" are numbers and sub-step switches
// of the method itself, not INI keys (README "Internal constants"): C++ callers and tests set
// them here. The team solve (team_batch.hpp) uses the same struct.
#pragma once

#include "roam/calibration_priors.hpp"
#include "roam/options.hpp"
#include "roam/sensor_noise.hpp"

namespace roam {
namespace spectral_batch {

// The sensors' stated noise (roam/sensor_noise.hpp, the run's [sensors]): odometry noise per step,
// range_sigma_m for a range that states none; then the batch's own keys.
struct SpectralBatchConfig : SensorNoise {
  // Ranges at 0.3 m, not [sensors]' 0.5: the batch solves every range jointly under a Cauchy loss
  // (a range a few sigmas off loses its weight, where a filter's gate and Huber weight would act
  // on it once, in the order it came), so it needs less margin for multipath that repeats from
  // place to place. Measured, not searched: at
  // 0.5 m the start-pose solve went 0.37 -> 0.41 m on Plaza 1 and 0.36 -> 0.43 m on its drpath.
  SpectralBatchConfig() { range_sigma_m = 0.3; }

  enum class Init { kSpectral, kDeadReckoning };
  enum class Anchor { kStartPose, kBeacons };
  enum class Loss { kHuber, kCauchy, kTukey, kNone };
  enum class Gauge { kWindow, kPinned };
  enum class LinearSolver { kSparseNormalCholesky, kDenseQr, kSparseSchur, kIterativeSchur, kCgnr };

  // Initial guess of the first solve: spectral (the spectral core's path and map) or
  // deadreckoning (integrated odometry; beacons by linear multilateration from that path, or
  // the surveyed ones with anchor = beacons) - the paper's "Batch Opt." row, same solver.
  Init init = Init::kSpectral;
  // Gauge: start_pose fixes the first pose at INITIAL_POSE (SLAM with unknown beacons);
  // beacons fixes the surveyed beacons from BEACONS (the start pose then only seeds the path).
  Anchor anchor = Anchor::kStartPose;
  // init = spectral: > 0 (default) replaces the spectral core's own headings (its rank-7 heading
  // rows) by the dead-reckoned heading plus the rotation aligning dead reckoning to the spectral
  // positions over this many metres of travel around each pose (initial_guess.hpp). The spectral
  // headings are arbitrary where the robot stands still (Plaza 1 starts so: ~90 deg off at pose 0),
  // and a seed whose headings contradict its own positions and the odometry starts the solve in a
  // wrong basin. 10 m: ~0.3 m position noise over ~10 m of chord gives ~0.02 rad, while odometry
  // heading drifts ~0.01 rad/sqrt(m) * sqrt(5 m) ~ 0.02 rad inside the window. 0: spectral headings.
  // Internal constant: how the seed is built.
  double seed_heading_align_m = 10.0;

  // anchor = beacons: INITIAL_POSE as a prior on pose 0 with these sigmas (0: none, pose 0 free).
  // With far beacons all on one side (an AUV's acoustic net), a shift of the whole path away
  // from them and a longer range offset are nearly the same fit; a start known to a metre (a GPS
  // fix at the surface, a surveyed dock) and ~6 deg separates them. Where no INITIAL_POSE came,
  // no prior.
  double start_pose_sigma_m = 1.0;
  double start_heading_sigma_rad = 0.1;

  // anchor = start_pose, final solve: the rotation about the start (a gauge freedom when no beacon
  // is surveyed) is set by aligning the solved path to the calibrated dead reckoning over this
  // much travel from the start, as the spectral core sets its frame (its align_m, 50 m: long
  // enough to average decimetre position noise to ~0.01 rad, short enough that odometry heading
  // drift after calibration stays ~0.01 rad/sqrt(m) * sqrt(50 m) ~ 0.07 rad at its end and
  // less on average). 0: the rotation the solve ends with (pose-0 heading or the seed's).
  // Internal constant: the window's length follows the noise, as spectral's align_m.
  double gauge_align_m = 50.0;
  // Which rotation gauge (anchor = start_pose, final solve): `window` (the gauge_align_m alignment
  // above) or `pinned`: the final solution is turned so that pose 0 has the start heading (rotation
  // about pose 0 is an exact symmetry of the cost, so this picks the gauge and costs one warm
  // solve): 30 % NLOS seeds 301-310 mean 0.50 m against 0.72 m with `window`, 401-410 0.64 against
  // 0.62, and Plaza 1 1.87 m (its odometry is ~0.1 rad off over the first 2-20 m).
  Gauge gauge = Gauge::kWindow;

  // Final solve from a spectral seed (or with a scanned heading-rate bias): a second solve from
  // dead reckoning (with the scanned bias), the lower robust cost kept, guards against a seed in a
  // wrong basin. `when_in_doubt` (default) makes it only where the first solve does not fit the
  // model: its odometry cost above half the number of ranges (2 x the cost of a correct solve is
  // chi-square with the problem's redundancy, at most one per range, so the odometry's share is
  // expected below that; correct basins on the sweep kinds are at 0.005-0.09 of the number of
  // ranges, a spectral seed in a wrong basin at 2.9), or fewer than doubt_inlier_fraction of its
  // ranges inliers (a seed dragged by outliers explains fewer). Elsewhere the two solves end at
  // the same cost (205 of 206 spectral-seeded runs on the sweep kinds' development seeds), and the
  // second costs more than the first (957 of 1,038 s at 10^6 steps). `always`: both, every time.
  // Internal constants (with doubt_inlier_fraction): when the method guards its seed.
  enum class DeadReckoningSeed { kWhenInDoubt, kAlways };
  DeadReckoningSeed dead_reckoning_seed = DeadReckoningSeed::kWhenInDoubt;
  // A Gaussian range falls outside the 4-sigma inlier window once in ~16000, so a clean run's
  // solve calls ~100 % of its ranges inliers, and one with a few percent of outliers the rest;
  // under nine in ten is a run with many outliers, where the dead-reckoning seed is kept solved.
  double doubt_inlier_fraction = 0.9;

  // Final solve with no beacon fixed: the solution must explain at least this fraction of the
  // ranges as inliers (within 4 sigmas), or the estimator fails with that reason. The
  // beacons are then fitted to the same ranges, and an M-estimator's breakdown point is one half:
  // a solution that calls most of its data outliers cannot be told from a wrong basin that
  // explains a different minority (AUV-like runs: 42 % inliers and 2 x dead reckoning's error).
  // With surveyed beacons fixed, the map is outside information and the check does not apply.
  // 0: off. Internal constant: the breakdown point of an M-estimator, not a choice.
  double min_inlier_fraction = 0.5;
  // When a final solve fails a check above (or ends above odometry alone): true publishes dead
  // reckoning from the start pose (the odometry alone, uncalibrated, beacons multilaterated from
  // it) with dead_reckoning_fallback = 1 in STATUS and the reason on stderr; false fails the
  // estimator with the reason. Dead reckoning is the answer the data still support: its error is
  // the odometry's own, where a refused solve may be twice that.
  bool fallback_deadreckoning = true;

  // The odometry (SensorNoise): sigma_d = rel d + floor along the track; the lateral
  // displacement over a step is held by hypot(sigma_d, d sigma_dtheta): a heading error of
  // sigma_dtheta moves the end of a step of length d sideways by d sigma_dtheta.
  // Robust loss on the whitened range residual: huber | cauchy | tukey | none. The scale is in
  // sigmas; 0 picks the loss's 95 %-efficiency constant (huber 1.345, cauchy 2.385, tukey 4.685).
  // Cauchy: its influence falls off for gross errors. Huber's stays at its scale however far
  // out, and 30 % NLOS ranges, all long (2-40 m), then pull every beacon and the path's edges
  // one way (shape error after a rigid fit 0.18 m against 0.09 m with cauchy, and 2 m at the
  // start of one run).
  Loss loss = Loss::kCauchy;
  double loss_scale = 0.0;  // internal constant: the loss's own efficiency constant
  // Annealing: the robust loss starts up to loss_anneal_factor^(stages-1) times wider (at the
  // seed's robust residual spread, never under the final scale) and narrows evenly per stage, so a
  // start far from the optimum is not down-weighted into a stall. A seed at the inliers' spread
  // is solved once, at the final scale. Internal constants, as is loss_anneal_check below.
  int loss_anneal_stages = 3;
  double loss_anneal_factor = 4.0;
  // The annealing is a way to the optimum, not the objective: a wide first stage can let ranges
  // that agree with each other but not with the rest (an NLOS stretch) bend the path into a basin
  // the narrow stages keep. Each annealed solve is also made from the same start at the final
  // scale alone, and the lower cost (the same objective) is kept. Solves from a seed only: the
  // warm-started re-solves (noise scale, gauge) start in the basin already chosen; and not where
  // the first stage is at the final scale already (the same solve).
  bool loss_anneal_check = true;

  // Calibration of the ranging radio: measured = scale * |beacon - robot| + offset, with one
  // scale and one offset shared by all beacons, estimated with the rest (UWB ranges are often
  // biased: the scale is observable against odometry distances, the offset against the spread of
  // ranges).
  bool estimate_range_scale = true;
  bool estimate_range_offset = true;
  // Prior sigma of the range scale about 1 (0, the default: none). With no beacon fixed the range
  // scale and the odometry's distance scale trade off with the map's size (nothing in ranges and
  // odometry tells them apart): with no prior the distance scale is held at 1 there and the range
  // scale carries the relative scale; with one, the two priors share it out (0.01 against
  // kDistanceScalePriorSigma 0.05 gives 96 % of it to the odometry). 0 by default: Plaza 1's UWB
  // ranges are 6.5 % long (its surveyed beacons say so, anchor = beacons: range scale 1.065,
  // distance scale 1.00), so a tight prior on the range scale moves that into the map (start
  // pose 0.35 -> 1.45 m). > 0 for a radio or sound speed known to that fraction.
  double range_scale_sigma = 0.0;
  // The shared range offset's prior (about 0) is the shared kRangeOffsetPriorSigma_m
  // (roam/calibration_priors.hpp): it also keeps heavy one-sided outliers (NLOS is always long)
  // from dragging the offset to tens of metres.

  // Odometry calibration (estimation::OdometryCalibration) as two more unknowns of the problem,
  // with the shared Gaussian priors (roam/calibration_priors.hpp): a heading-rate bias b ~ 0 +-
  // kHeadingRateBiasPriorSigma_rad_s (0.01 rad/s, a MEMS gyro's bias; also the half-width / 3 of
  // the bias scan) and a distance scale s ~ 1 +- kDistanceScalePriorSigma (0.05). They cost nothing
  // where there is no bias (the prior holds them at 1 and 0 to within what the ranges can tell).
  // false: held at s = 1, b = 0.
  bool estimate_odometry_calibration = true;
  // The rule of the EKF and online EM on how often the ranges fix the position
  // (roam/estimation/bias_observability.hpp): where over three fixes the bias prior above would
  // turn the heading by more than this (rad), the ranges come too seldom to correct the heading
  // between fixes (AUV rates: GOATS 16 0.185 rad; UWB rates <= 0.06): the shared
  // kHeadingRateBiasMaxDrift_rad (roam/calibration_priors.hpp). <= 0: always dense.
  // A key (as in online EM): the run's note tells a user with a drifting gyro and clean ranges to
  // set it to 0.
  double heading_rate_bias_max_drift_rad = kHeadingRateBiasMaxDrift_rad;
  // anchor = start_pose where the rule above finds the ranges sparse and every odometry message
  // states a covariance: the heading noise is the stated one (floored by odo_heading_sigma_rad),
  // not the wheel model below (odo_heading_sigma_per_sqrt_m, _rel), the heading-rate bias is held
  // at 0, and the rotation gauge is the start heading (no gauge_align_m window). With no beacon
  // fixed, a path bent a few degrees per step and its beacons moved with it fit sparse ranges as
  // well as the straight one, and outliers pick the bend: GOATS-like runs with 30 % outliers
  // landed at up to 3.6 x dead reckoning with the wheel model's 0.022 rad per 5 m step, against a
  // heading stated to 0.002 rad (true to 0.001). A log that states nothing keeps the wheel model
  // and the window. false: the wheel model everywhere. Internal constant: a sub-step switch.
  bool sparse_heading_as_stated = true;
  // Odometry noise scale estimated from the data: after a solve, every odometry sigma times
  // k = 2, 4, ... 32 is tried, each a warm solve, while the Gaussian likelihood improves (a profile
  // likelihood over k). The configured (or reported) noise is the floor: never narrowed. A log's
  // stated noise is often its generator's setting, not the sensor's (GOATS: 2 cm per edge for
  // odometry good to a metre). false: the configured noise as it is. Internal constant: a
  // sub-step switch (the configured noise stays the user's floor).
  bool estimate_noise_scale = true;

  // Per-beacon range offsets (on top of the shared one), each with the shared zero-mean prior
  // kBeaconOffsetPriorSigma_m (roam/calibration_priors.hpp): acoustic beacons and UWB anchors have
  // their own delays (transponder turn-around, antenna delay). On by default: it costs nothing on
  // Plaza 1, where the prior holds them near 0, and takes up the per-beacon offsets that a shared
  // offset cannot.
  bool estimate_beacon_offsets = true;

  // Live mode: re-solve over all data so far every resolve_interval_s of data time, warm-started
  // from the previous solve (0: solve only at the end of input).
  double resolve_interval_s = 0.0;

  // Ceres solver. Sparse normal Cholesky suits the block-tridiagonal pose chain plus a few
  // dense beacon columns. Tolerances are Ceres' own defaults tightened so exact data converges
  // to well below a micrometre. The iteration limit and the tolerances (when a solve stops) are
  // internal constants; the linear solver, threads and verbosity are keys (solver resources).
  LinearSolver linear_solver = LinearSolver::kSparseNormalCholesky;  // | dense_qr | sparse_schur | iterative_schur | cgnr
  int max_iterations = 100;       // per annealing stage
  double function_tolerance = 1e-10;
  double gradient_tolerance = 1e-12;
  double parameter_tolerance = 1e-10;
  int num_threads = 1;            // deterministic and polite on a shared machine
  bool verbose = false;           // the solver summary on stderr after every solve
};

// The robust-loss scale actually used (loss_scale, or the loss's 95 %-efficiency constant).
double effectiveLossScale(const SpectralBatchConfig& config);

// Registers every key of the [estimator.*] section with its checks (the shim calls parse();
// SpectralBatchSlam runs the same checks on a struct with checkConfig): the only validator.
void addSpectralBatchOptions(Options& options, SpectralBatchConfig* config);

}  // namespace spectral_batch
}  // namespace roam
