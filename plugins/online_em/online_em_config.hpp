// Configuration of the online EM SLAM core (Le Corff, Fort & Moulines 2011), with the
// defaults and the reason for each. addOnlineEmOptions() registers every key with its check;
// the plugin shim, the tools and the tests share it so that a key has one definition.
// Fields marked "Internal constant" are numbers and sub-step switches of the method itself, not
// INI keys (README "Internal constants"): C++ callers and tests set them here.
#pragma once

#include "roam/calibration_priors.hpp"
#include "roam/options.hpp"

namespace roam {
namespace online_em {

// The learned outlier weight's bound (estimate_mixture): inliers are the majority, or nothing
// anchors the map; a weight that ends here is why a start-pose run falls back to dead reckoning
// (fallback_deadreckoning).
constexpr double kMaxOutlierWeight = 0.6;

struct OnlineEmConfig {
  enum class Anchor { kStartPose, kBeacons };
  enum class Resampling { kMultinomial, kSystematic };
  enum class MotionModel { kOdometry, kBicycle };
  enum class Indicators { kSampled, kMarginal };

  // Frame: start_pose (known first pose, beacons unknown: multilateration) or beacons
  // (surveyed BEACONS enter the M-step as a prior, as pseudo-observations).
  Anchor anchor = Anchor::kStartPose;
  int num_particles = 100;  // the paper's N
  int seed = 1;             // std::mt19937_64 seed: the same input gives the same output

  // Ancestor draw each step: multinomial (Algorithm 1: J^l ~ {w_{t-1}^j}, independently) or
  // systematic (one uniform, stratified: same expectation, less resampling noise; with equal
  // weights every particle keeps exactly one child, so steps without ranges lose no diversity).
  // Default systematic: on the seeded synthetic runs of tests/online_em with the exact map it
  // halves the path error of 100 particles (0.59 -> 0.31 m); multinomial is the paper's choice.
  Resampling resampling = Resampling::kSystematic;

  // Motion model. odometry: move then turn with (d, dtheta) plus noise in the frame of the
  // previous pose (forward, lateral, heading). bicycle: the paper's Sec. 4.1 model, controls
  // (v, psi) with wheelbase B recovered from (d, dtheta) = (v dt, v dt sin(psi) / B).
  MotionModel motion_model = MotionModel::kOdometry;
  // Odometry noise, per step: sigma_forward = rel * d + abs, sigma_lateral = rel * d + abs,
  // sigma_heading = heading_sigma_rad. Defaults: wheel odometry of a lawn-mower-class robot:
  // 2 % of distance (slip), 1 mm floor (keeps the transition density non-degenerate when the
  // robot stands still), 0.005 rad per step (~0.3 deg: a gyro-less heading random walk that
  // drifts ~0.5 rad over 10^4 steps, the order of magnitude of wheel-odometry heading drift).
  double odo_distance_sigma_rel = 0.02;
  double odo_distance_sigma_m = 0.001;
  double odo_heading_sigma_rad = 0.005;
  // odo_heading_sigma_rad is the heading noise of a step between odo_heading_step_min_s and
  // odo_heading_step_max_s (5 Hz odometry with its clock's jitter: Plaza 1's steps are
  // 0.171-0.232 s). The heading noise is a random walk over time (a gyro's, or wheels' over
  // the distance a step covers at a given speed), so a step of dt outside that span gets
  // sigma * sqrt(dt / the nearer bound), its share of the same noise per second:
  // - shorter: 20 Hz odometry is not noisier per second than 5 Hz. With sigma per step it told
  //   the M-step a quarter as much about the gyro bias per second, the calibrated re-run came
  //   late or never, and the drifting figure-8 at 20 Hz from the start pose landed at 1.13 m
  //   (with the share 0.31 m);
  // - longer, only where the ranges re-fix the heading often enough to select among the
  //   particles' headings (heading_rate_bias_max_drift_rad's rule, as for the scale spread below):
  //   a slow robot (1 s steps, a range every 2 s) whose gyro walks 0.0067 rad per step lost
  //   its path with 0.005 (start pose / beacons 3.41 / 3.91 m over ten seeds; 0.66 / 0.36 with
  //   the share). Where the ranges are too sparse for that (an AUV: a fix every 3 s or more) the
  //   particles cannot carry more heading spread than the per-step sigma: heading noise grown
  //   with the synthetic AUV's 3 s steps (0.0112 rad) took it from 14.8 to 26.3 m, and an AUV's
  //   heading comes from a compass, whose error does not grow with the step.
  // 0 for a bound: no share on that side. Internal constant: the span is 5 Hz odometry's.
  double odo_heading_step_min_s = 0.15;
  double odo_heading_step_max_s = 0.25;
  // A covariance reported with the odometry is used, each variance floored by the above
  // (roam::estimation::incrementCovariance): a file that states centimetres for odometry good
  // to a metre cannot make the filter overconfident.
  bool use_reported_covariance = true;

  // Odometry calibration in theta: distance scale s (true distance = s * reported) and
  // heading-rate bias b (rad/s, a gyro bias), estimated in the M-step from the smoothed
  // increments (the transition density is Gaussian and linear in (s, b): an exact quadratic
  // M-step, see odometry calibration in online_em_slam.hpp). Priors (pseudo-observations): the
  // shared ones (roam/calibration_priors.hpp), s ~ N(1, kDistanceScalePriorSigma^2) and
  // b ~ N(0, kHeadingRateBiasPriorSigma_rad_s^2). calibrate_odometry = false keeps s = 1, b = 0
  // for odometry known to be clean.
  bool calibrate_odometry = true;
  // Per-particle distance-scale spread (calibrate_odometry, odometry model): each particle
  // carries its own fractional deviation d_k from the learned s, an AR(1) process of stationary
  // sigma distance_scale_particle_sigma (the prior sigma of s: the cloud spans the scales the
  // prior allows) and correlation length distance_scale_particle_length_m over the distance
  // travelled, and moves with s (1 + d_k). Without it the cloud cannot hold a persistent scale error
  // (2 % per-step noise, a 3 % scale error accumulates linearly), the ranges cannot select the
  // lineages that moved further, and the complete-data statistic of s only sees the s it was
  // proposed with (30 % NLOS + 0.97 scale, beacons: s learned 1.00 against 1.031). 0 = off.
  // Active only where s is observable: anchor = beacons (the surveyed beacons fix the metric),
  // or estimate_range_scale = false. From the start pose with a range scale in theta,
  // (s, range scale, map) -> (l s, range scale / l, l map) fits every range: the spread lets
  // the cloud drift along that direction (gyro-drift figure-8, start pose: s 0.94, range scale
  // 1.066, 0.63 -> 1.00 m), so it is off there. Internal constants: the spread follows the
  // shared scale prior, not a sensor statement.
  double distance_scale_particle_sigma = 0.05;
  double distance_scale_particle_length_m = 20.0;
  bool scaleSpreadActive() const {
    return calibrate_odometry && distance_scale_particle_sigma > 0.0 && motion_model == MotionModel::kOdometry &&
           (anchor == Anchor::kBeacons || !estimate_range_scale);
  }
  // Observability of the heading-rate bias (the EKF's gyro_bias_max_drift_rad, same rule and
  // value: estimation::BiasObservability): the ranges re-fix the heading about every three
  // position fixes; over that time the bias prior turns it by prior_sigma x 3 x (mean interval
  // between the fix times of the first 20 ranges). Above this, the bias is fixed at 0 (the
  // distance scale is still estimated) and the run ends with a note: the particles cannot tell
  // it from the heading noise, and what the M-step learned for it (1e-4-1e-3 rad/s on AUV-like
  // runs with none) rotated the path by tens of metres. The shared kHeadingRateBiasMaxDrift_rad
  // (0.08 rad, roam/calibration_priors.hpp): UWB rates estimate it, AUV rates do not. Until the
  // 20th range b is held at 0 (its statistics accumulate all along). 0: always estimate. A key:
  // the run's note tells a user with a drifting gyro and clean ranges to set it to 0.
  double heading_rate_bias_max_drift_rad = kHeadingRateBiasMaxDrift_rad;
  // A vehicle standing still does not turn. A standstill by the shared rule
  // (roam/estimation/standstill.hpp: stationary_min_steps steps in a row slower than
  // stationary_speed_mps, each turning at the rate of the one before within 3 sigma; the EKF's
  // keys) whose reported turn rate is under stationary_max_turn_rate_rad_s (5 x the bias prior's
  // sigma: a rate no gyro bias reaches; a turn on the spot is faster) turns the particles by 0,
  // and the calibration statistic sees its reported turn as bias alone: a stand measures b
  // before the vehicle moves. Values differ from the EKF's (0.02 m/s, 5 steps): see the README,
  // "Round 9". 0 = never. Internal constants: thresholds of the shared standstill rule.
  double stationary_speed_mps = 0.01;
  int stationary_min_steps = 1;
  double stationary_max_turn_rate_rad_s = 0.05;
  // Calibrated re-run (anchor = start_pose): once the heading-rate bias is known to
  // rerun_bias_sigma_fraction of its prior sigma and the frame it implies is significant (the
  // frame correction's gate), the filter is run once more from the start on the inputs so far
  // with (s, b) fixed at the learned value, so the first landmarks are placed from a calibrated
  // path; poses already published stay, the state (map, particles, path) is replaced. The sigma
  // is the complete-data one (poses taken as known), which ignores the missing information of
  // the particle paths: 0.05 of the prior (5e-4 rad/s) is the EKF's 10 % of the actual
  // uncertainty. On the synthetic drift figure-8, b still wandered by ~1e-3 rad/s while that
  // sigma was 0.1 of the prior (re-run at b = 0.0106 vs 0.0100 true: 0.65 m; at 0.05: 0.51 m).
  // Internal constants (with rerun_end_bias_sigmas): when the method re-runs itself.
  bool calibrated_rerun = true;
  double rerun_bias_sigma_fraction = 0.05;
  // At the end of input, with no calibrated re-run made: re-run with b as learned over the whole
  // run when |b| >= this many sigma_b (0: off). Where b's complete-data sigma never falls under
  // the fraction above (long lanes: it stays at 6.4e-4 rad/s), a run whose particles turned with
  // the bias before it was learned followed its dead reckoning to the end (12.5 m) though it
  // learned b to within 25 %. 3: a two-sided 0.3 % test; with no bias at all (30 % NLOS and
  // radio-silence runs, seeds 301-320) the learned b stays within 1.9 sigma_b. README "Round 17".
  double rerun_end_bias_sigmas = 3.0;
  // At the end of the run, where the learned outlier weight sits at its bound (kMaxOutlierWeight,
  // 0.6: fewer than 40 % of the ranges fit) the solution is not trusted and dead reckoning is
  // published instead, with a note naming this key and dead_reckoning_fallback = 1 in STATUS
  // (spectral + batch's key). From the start pose no beacon is fixed: the map is fitted to the
  // same ranges, and below the breakdown point a wrong basin that explains another minority fits
  // as well (landmarks placed at their mirror images across an AUV's first lane); its landmarks
  // are multilaterated from the dead-reckoned path. With surveyed beacons the map is held to the
  // survey, so the path is what fails to fit: the cloud lost the vehicle (README "Round 20").
  // AUV kinds, seeds 2001-2100, runs over 1.25 x dead reckoning: start pose 16 -> 2 of 200,
  // beacons 1 -> 0. Needs estimate_mixture (the weight is learned) and marginal indicators.
  // README "Round 21". false: publish the filter's solution whatever its mixture says.
  bool fallback_deadreckoning = true;
  // The published trajectory (TRAJECTORY) smoothed: a Rauch-Tung-Striebel backward pass over the
  // particle cloud's Gaussian summary at each step (estimation/pose_smoother.hpp), the shared
  // motion model's prediction. off (the filtered means, what POSE streams), beacons (where
  // anchor = beacons), always, sparse (default: anchor = beacons where the ranges are too sparse
  // to re-fix the heading between fixes, the heading-rate bias rule heading_rate_bias_max_drift_rad
  // holds b; decided at the 20th range, OnlineEmSlam::smoothsTrajectory). Sparse: between an
  // AUV's fixes the filtered path carries the odometry's whole drift, and the final theta
  // (offsets, mixture, kappa) is learned from hundreds of ranges the early path never saw. At
  // UWB rates it stays off: Plaza 1 with beacons, the README table's particle seed, went 0.42 ->
  // 0.57 m with it (five particle seeds: mean 0.51 -> 0.50; plaza1-drpath 0.50 -> 0.42), so the
  // README's rule would break on one seed's draw (README "Round 23"). From the start pose the
  // error is the frame its map was placed in, a rigid motion no smoothing moves.
  enum class SmoothTrajectory { kOff, kBeacons, kAlways, kSparse };
  SmoothTrajectory smooth_trajectory = SmoothTrajectory::kSparse;
  // Whether the backward pass may run: for sparse, the run decides (OnlineEmSlam::smoothsTrajectory).
  bool maySmooth(Anchor a) const {
    return smooth_trajectory == SmoothTrajectory::kAlways ||
           ((smooth_trajectory == SmoothTrajectory::kBeacons || smooth_trajectory == SmoothTrajectory::kSparse) &&
            a == Anchor::kBeacons);
  }
  // Before the backward pass, run the pose-only particle filter once more over every input
  // against the final theta (map, range scale and offsets, calibration, mixture, kappa). On
  // (since round 23): better than the plain backward pass on every synthetic beacons kind and
  // AUV kind, plaza1-drpath and plaza1-drift (README "Round 23"). Internal constant: a sub-step
  // of smooth_trajectory.
  bool trajectory_repass = true;
  // Bicycle model (paper Sec. 4.1): sigma_v (m/s), sigma_psi (rad), wheelbase B (m), and a
  // small heading jitter that makes the 2-D control noise a proper 3-D density for smoothing.
  double wheelbase_m = 1.5;
  double speed_sigma_mps = 0.5;
  double steer_sigma_rad = 0.05235987755982988;  // pi / 60
  double heading_jitter_rad = 0.001;  // internal constant: a regulariser, not the paper's model

  // Observation noise: delta ~ w0 N(0, sigma0^2 R) + (1 - w0) N(0, sigma1^2 R), R = [[sr^2, rho],
  // [rho, sb^2]] (range-only: sr^2). Defaults: the paper's Sec. 4.1 values (w0 0.8, sigma0 1,
  // sigma1 5, sr 0.5 m, sb pi/60 rad, rho 0.01): 0.5 m is the usual UWB ranging accuracy and the
  // wide component absorbs multipath outliers. A range's own sigma (> 0) replaces sr.
  // The wide component is the outlier model (issue 15: 10-50 % non-line-of-sight ranges, metres
  // to tens of metres long; acoustic echoes hundreds): sigma1 = 20 sr (10 m at sr 0.5 m; 15 m
  // at GOATS' stated 0.75 m) covers NLOS excesses of a few to ~30 m, while its statistics weigh
  // 1/400 of an inlier's in the M-step. The paper's 5 sr (2.5 m) treats a 10 m NLOS range as a
  // 4-sigma inlier of the wide component and pulls the map (30 % NLOS synthetic: beacon anchor
  // 7.8 m path error; 20 sr: 0.16 m).
  double mixture_weight0 = 0.8;
  double mixture_sigma0 = 1.0;
  double mixture_sigma1 = 20.0;
  double range_sigma_m = 0.5;
  double bearing_sigma_rad = 0.05235987755982988;  // pi / 60
  double range_bearing_cov = 0.01;
  // Mixture indicators: sampled (Algorithm 1: I ~ Bernoulli(w1) per particle, the weight and
  // the statistic use the sampled component) or marginal (Rao-Blackwellised: the weight uses
  // the mixture likelihood, the statistic the posterior probabilities of the two components).
  // Default marginal: with sampled indicators only ~20 % of the particles carry the wide
  // component for a given outlier and the weights collapse onto them (30 % NLOS synthetic:
  // beacon anchor: minimum ESS 4 of 100 with sampled, 51 with marginal).
  Indicators indicators = Indicators::kMarginal;
  // On by default (outlier_model uniform, estimate_mixture true) since round 4: with the
  // heading-rate bias held at 0 on sparse ranges (above), it holds every AUV-like seed within
  // 1.25 x dead reckoning from the start pose and Plaza 1 with a drifting gyro at 0.51 m; it
  // moves clean Plaza 1 from the start pose 0.90 -> 1.04 m (the README's limit, 1.14 + 0.05,
  // holds), see README.
  // Outlier component of range-only observations: "uniform" over [0, the longest range received
  // so far] (physical units: an echo or NLOS path can land anywhere in the span the ranges
  // cover, -150 to +100 m on an AUV; its density does not depend on the particle, so an outlier
  // cannot decide which particles survive, where a 15 m Gaussian tail weighted them by
  // e^2 / sigma1^2 across a 10 m particle spread) or "gaussian" (sigma1 sr, the paper's form).
  // Internal constant (with estimate_inlier_sigma and mixture_prior_count below): how the
  // mixture is modelled and learned, not what the sensor states.
  enum class OutlierModel { kUniform, kGaussian };
  OutlierModel outlier_model = OutlierModel::kUniform;
  // Mixture in theta (range-only, marginal indicators): the outlier weight w1 = 1 - w0 and
  // the inlier scale sigma0 (in sr) estimated in the M-step from the posterior component
  // probabilities and inlier residuals, with mixture_prior_count pseudo-ranges at the
  // configured (w0, sigma0); neither drops below its configured value (the stated sigma is a
  // floor: GOATS states 0.75 m for ranges that scatter ~2 m; over-counting outliers costs
  // little, under-counting them lets one outlier pick the particles), and w1 <= 0.6 (inliers
  // are the majority, or nothing anchors the map: kMaxOutlierWeight).
  bool estimate_mixture = true;
  bool estimate_inlier_sigma = true;  // the sigma0 half of estimate_mixture (w1 alone: false)
  double mixture_prior_count = 20.0;
  // Adaptive motion noise (innovation covariance matching, Mehra 1972): the particle cloud is
  // the filter's predictive distribution of each range, r_k = s |m - p_k| + b, with variance
  // v (the cloud's) + the map's J P_m J^T + sr^2 (the range noise: the stated sigma times the
  // current inlier scale). If the odometry is noisier than configured, the cloud is too
  // narrow and the inliers' squared innovations e^2 = (y - mean r_k)^2 exceed that sum. The
  // cloud's range variance grows with the square of the translation noise scale kappa (it is
  // made of the translation noise drawn since the last ranges), so matching
  //   E[pi (e^2 - sr^2 - v_map)] = kappa^2 E[pi v / kappa_then^2]
  // (pi: the range's posterior inlier probability; running averages with the M-step's step
  // sizes over the ranges) gives kappa^2, floored at 1 (the configured noise is a floor) and
  // capped at motion_noise_max_scale^2. kappa multiplies the forward and lateral standard
  // deviations (not the turn's: the heading noise is the gyro's, and scaling it random-walks
  // the heading of every particle; the EKF found the same). STATUS `motion_noise_scale`.
  // Only the excess beyond twice its standard error counts (a squared Gaussian innovation has
  // standard deviation sqrt(2) x its variance; the running average spans 1 / sum(weights^2)
  // ranges): without it a 10 % error in the learned range sigma, with a cloud 10x narrower
  // than the range noise, reads as kappa ~ 3. motion_noise_max_scale 10: 2 % -> 20 % of the
  // distance, DVL-less AUV dead reckoning. Figures: README. Internal constants: the configured
  // noise stays the user's floor; the adaptation is a step of the method.
  bool adapt_motion_noise = true;
  double motion_noise_max_scale = 10.0;

  // Stochastic approximation: gamma_n = c / n^alpha per landmark, n = its own observation count.
  double step_c = 1.0;
  double step_alpha = 0.8;
  int mstep_every = 1;  // M-step after every k-th step that observed a landmark (internal: Algorithm 1's 1)

  // Range model r = scale * |beacon - robot| + offset, (scale, offset) in the parameter theta.
  // Priors (pseudo-observations): scale ~ N(1, 0.1^2) (UWB clock/antenna errors of a few %),
  // offset ~ N(0, 1 m^2) (antenna delay).
  // The scale is estimated by default: a clock-rate error scales every time of flight. The
  // offset is not: seen from tens of metres, a shared offset and a map grown by the same amount
  // explain range-only data almost equally well, and on synthetic runs the estimated offset
  // drifted by metres while the map expanded to match; a fixed antenna delay is a factory
  // calibration. Turn it on for radios known to carry one.
  bool estimate_range_scale = true;
  bool estimate_range_offset = false;
  // The scale's prior (about 1) is the shared kRangeScalePriorSigma (roam/calibration_priors.hpp).
  // Internal constant: the shared offset's prior, kRangeOffsetPriorSigma_m's value (a shared
  // calibration prior, as in the other estimators, not a key).
  double range_offset_prior_sigma_m = 1.0;
  // Prior sigma of a surveyed beacon whose covariance is not given (anchor = beacons).
  double beacon_prior_sigma_m = 0.1;
  // Per-beacon range offsets (anchor = beacons): each surveyed beacon's ranges read
  // scale * distance + offset + o_b, o_b ~ N(0, beacon_range_offset_sigma_m^2) (a transponder's
  // turn-around delay or an anchor's antenna delay is the beacon's own; GOATS: 1-2 m). o_b is in
  // theta, solved in the M-step with the beacon's smoothed statistics (inlier-weighted by the
  // mixture's posterior) and the prior as pseudo-observations. The EKF's key and default:
  // offsets of either sign, magnitude uniform in [1, 2] m, have sigma sqrt(7/3) = 1.53 m.
  // On by default, like the EKF's: acoustic transponders and UWB anchors carry their own
  // delays, and with them AUV-like runs stay within 1.25 x dead reckoning where without them one
  // in 33 did not; where the ranges carry none the o_b absorb some of the path's error (AUV-like
  // median +0.2 m; README "Per-beacon range offsets").
  bool estimate_beacon_range_offsets = true;
  double beacon_range_offset_sigma_m = 1.5;

  // Multilateration of a new landmark: wait for this many ranges taken from positions whose
  // spread (sqrt of the smaller eigenvalue of their covariance) is at least init_min_spread_m,
  // so that the mirror ambiguity of a straight path is resolved. Internal constants (as are the
  // window solve's and the gate below); init_min_spread_fraction is a key: the rejection warning
  // names it where an AUV's beacons are far (docs/other-robots.md).
  int init_min_ranges = 12;
  double init_min_spread_m = 3.0;
  // ... and at least this fraction of the median range: the positions must subtend a few
  // degrees (0.05: ~3 deg) seen from the beacon. Plaza's 10-40 m ranges keep the 3 m floor;
  // an AUV 300 m from a beacon waits for 15 m of spread.
  double init_min_spread_fraction = 0.05;
  // anchor = start_pose, ranges dense (the heading-rate bias rule): when the early window closes
  // (every landmark seen so far placed), solve the window's path and map jointly (roam/estimation/window_solve.hpp:
  // the path's heading random walk in blocks of init_window_block_s with the shared wheel model's
  // variance, the range scale with its prior, the ranges through the learned mixture) and replace
  // the multilaterated map, the window's path, the particles' frame and the landmark statistics
  // with it, where the ranges refute the dead-reckoned window (twice the log-posterior gain over
  // the same solve with the path held >= init_outlier_gate_sigmas^2). 30 % NLOS start pose, seeds
  // 301-310: mean 0.96 -> 0.54 m; Plaza 1 gains 6-8: not applied.
  bool init_window_solve = true;
  // 5 s at 1 m/s: the walk within a block moves the path ~5 cm, under the range noise.
  double init_window_block_s = 5.0;
  // Multilateration robust to outliers: every triple of ranges proposes a position; the one
  // with the most ranges within gate * sr (the range's sigma, or range_sigma_m; at least 1 m)
  // wins and is refined on them. 3 sigma: a Gaussian inlier passes with 99.7 %. (Widening the
  // gate by the particles' spread was tried: the 30 % NLOS start-pose run went 0.53 -> 3.8 m.)
  // 0: plain least squares on every range.
  double init_outlier_gate_sigmas = 3.0;
};

// Registers every key (with its check) on `options`, bound to `config`: the only validator
// (OnlineEmSlam runs the same checks on a struct with checkConfig).
void addOnlineEmOptions(Options& options, OnlineEmConfig* config);

}  // namespace online_em
}  // namespace roam
