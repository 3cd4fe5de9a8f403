// Online EM SLAM — Le Corff, Fort & Moulines, "Online Expectation Maximization algorithm to
// solve the SLAM problem", IEEE SSP 2011.
//
// Model. The pose x_t = (p_t, th_t) is a hidden Markov chain driven by odometry (particle_motion.hpp);
// the map theta (landmark positions, plus a range scale s and offset b, see below) is a static
// parameter. Each observation y_{t,i} of landmark i is h(x_t, theta_i) + delta, delta a
// two-component Gaussian mixture with latent indicator I_{t,i} (observation_model.hpp).
// theta is estimated by online EM, the pose distribution by a particle filter.
//
// One step t (Algorithm 1):
//  1. Particle filter: ancestors J^l ~ Multinomial(w_{t-1}); xi_t^l ~ m(. | xi_{t-1}^{J^l}, u_t)
//     (the prior kernel); I_{t,i}^l ~ Bernoulli(w1) (the prior: the importance ratio is 1);
//     w_t^l ∝ g_theta^(y_t | xi_t^l, I_t^l). A range stamped between two odometry steps is scored
//     at the pose interpolated linearly between the particle's ancestor and itself.
//  2. Stochastic approximation (forward smoothing, Del Moral, Doucet & Singh 2010), per landmark:
//       rho_{t,i}^k = 1{i in A_t} g_n S_i(xi_t^k, I^k, y) + (1 - 1{i in A_t} g_n) [K rho_{t-1,i}]^k,
//       K_kl = w_{t-1}^l m(xi_t^k | xi_{t-1}^l) / sum_l' (...)
//     an N x N row-stochastic matrix applied to all statistics at once (one matrix product);
//     g_n = c / n^alpha with n the landmark's own observation count (a step that does not observe
//     the landmark only transports its statistic). S_i is the statistic of the observation
//     linearised at the current theta^ (Eq. 8).
//  3. M-step (closed form): E[S_i | y_1:t] ~ sum_k w_t^k rho_{t,i}^k = (A_i, v_i); maximise
//       sum_i n_i (phi_i^T v_i - 1/2 phi_i^T A_i phi_i) + log prior(theta),  phi_i = (m_i, s, b),
//     a quadratic in theta solved with one small linear system. Weighting landmark i by n_i makes
//     its averaged statistic count as n_i observations, so the shared (s, b) see every range and a
//     prior (surveyed beacons; scale ~ N(1, .), offset ~ N(0, .)) keeps its weight as
//     pseudo-observations instead of being forgotten by the step sizes.
//
// Odometry calibration (s, b) (calibrate_odometry): the transition density is Gaussian in the
// increment error e = z - J (s, b) (particle_motion.hpp), so its complete-data log-likelihood is
// quadratic in (s, b) with statistic (J^T W J, J^T W z). J^T W J does not depend on the poses (a
// running average); J^T W z is a pair-of-poses additive functional, smoothed by the same kernel:
//   c_t^k = (1 - g_t) [K c_{t-1}]^k + g_t J^T W sum_l K_kl z_kl,   g_t = c / t^alpha (t: steps).
// M-step: (t A + P) (s, b) = t sum_k w^k c^k + P (1, 0), with the priors P as pseudo-observations.
// The particles are propagated with the current (s, b) (the prior kernel m_theta).
//
// Frame of the start pose (anchor = start_pose, calibrate_odometry): the first landmarks are
// multilaterated from the path dead-reckoned with the calibration of that time (none), so a
// heading-rate bias rotates the whole map about the start, and nothing seen later can undo it
// (a rotation of map and path together fits every later range). The early window, from the
// start to the second landmark's initialisation, fixes that frame. After each calibration
// M-step, the rigid motion T (least squares, Procrustes) that takes the window's path
// dead-reckoned without calibration onto the same path with the current (s, b) is the frame's
// error; the part of T not yet applied moves landmarks, particles, the buffered poses, the path
// so far and the landmark statistics (the quadratic in phi re-parametrised exactly:
// phi = M phi' + c  =>  A' = M^T A M, v' = M^T (v - A c)). A rotation within twice the heading
// noise of the window (the shared wheel model's, estimation::wheelHeadingVariance_rad2: per metre
// driven and per turn, so standing still adds almost none) is not significant and is not applied
// (Plaza 1's learned b ~ 3e-4 rad/s would otherwise turn a correct frame by 0.025 rad).
//
// Calibrated re-run (calibrated_rerun, anchor = start_pose): the correction above fits the
// window's rotation only approximately, and the first landmarks stay placed from an
// uncalibrated path. So, once, when the correction is significant and the bias is known to a
// fraction of its prior (sigma_b = sqrt([(t A + P)^-1]_bb) < rerun_bias_sigma_fraction *
// prior sigma), the filter restarts from the start pose on every input received so far with
// (s, b) fixed at the learned value (no calibration statistics, M-step or frame correction
// during the replay), then goes on online. The calibration statistics keep their value (their
// particle-weighted mean, the steps are not counted twice); the frame correction afterwards
// compares the window dead-reckoned with the re-run's calibration to the current one. Poses
// already published stay published; the map, particles and path are the re-run's.
//
// Per-particle distance-scale spread (distance_scale_particle_sigma, particle_motion.hpp): each
// particle carries its own deviation d_k (AR(1) over the distance travelled) and moves with
// s (1 + d_k), so the ranges can select lineages with the right scale and the M-step's s sees
// them; after each M-step d_k is re-expressed about the new s. Where s is observable (anchor =
// beacons, or no range scale in theta) and the ranges are dense (the bias rule below, and before
// its 20th range the same rule on the ranges so far).
//
// Heading-rate bias observability (heading_rate_bias_max_drift_rad, the EKF's rule): b is
// held at 0 until the 20th range, then estimated only if its prior would turn the heading by
// at most that much over three mean range intervals; otherwise fixed at 0 (s alone in the
// calibration M-step).
//
// Adaptive motion noise (adapt_motion_noise): the translation noise scale kappa (particle
// proposal and transition density alike) from innovation covariance matching over the inlier
// ranges (online_em_config.hpp): kappa^2 = (E[pi (e^2 - sr^2 - v_map)] - 2 SE) / E[pi v / kappa^2],
// within [1, motion_noise_max_scale^2].
//
// Robust initialisation (multilateration.hpp): a consensus of range triples with an inlier gate
// of 3 sr (at least 1 m).
//
// Per-beacon range offsets (beacon_range_offset_sigma_m, surveyed beacons): phi_i's offset is
// b + o_i, so the landmark statistic's offset row observes o_i as well; the M-step adds o_i as an
// unknown with prior N(0, sigma_o^2) (pseudo-observations: a beacon with few inlier ranges stays
// near 0). The statistics are already inlier-weighted (marginal indicators). The statistic treats
// the path as known: the cloud's predicted-range variance v_c is missing information, so o_i's
// data curvature is deflated by f = sr^2 / (sr^2 + v_c) (running average over its inlier ranges).
//
// Range scale and offset: UWB ranges are often long by a few % (Plaza 1: 7 %); without (s, b) in
// theta the map expands to fit them. r = s |m - p| + b is linearised in (m, s, b) like the rest.
//
// Early window solve (init_window_solve, anchor = start_pose, dense ranges; roam/estimation/window_solve.hpp): the
// landmarks above are multilaterated as if the dead-reckoned mean path were known, so the map
// takes that path's frame. When the early window closes, its path (heading random walk in
// blocks) and map (with the range scale) are solved jointly from the start pose through the
// mixture, and replace the map, the window's path, the particles' frame and the landmark
// statistics where the ranges refute the dead-reckoned path (likelihood-ratio gain >= gate^2).
//
// Dead-reckoning fallback (fallback_deadreckoning; dead_reckoning_fallback.cpp): where the learned
// outlier weight w1 ends the run at its bound (kMaxOutlierWeight), fewer than 1 - w1 of the ranges
// fit: from the start pose a map fitted to those same ranges (below the breakdown point), with
// surveyed beacons the path (the cloud lost the vehicle). The TRAJECTORY is then the odometry
// composed from the start pose; from the start pose the map is multilaterated from it. With
// surveyed beacons, a run that held the heading-rate bias at 0 is first re-run with it estimated
// (a drifting gyro is the other explanation of a lost cloud at sparse rates).
//
// Published trajectory (smooth_trajectory, default sparse: anchor = beacons where the ranges are
// too sparse for the heading-rate bias rule): POSE streams the filtered cloud's
// weighted mean; the TRAJECTORY at the end may be that path smoothed by a Rauch-Tung-Striebel
// backward pass (roam/estimation/pose_smoother.hpp) over the cloud's Gaussian summary
// N(m_t, P_t) after each update, predicted through the shared motion model with the step's own
// calibrated increment and noise (kappa included), the predicted mean's translation shrunk by
// exp(-var_th / 2) (E[R(th)] under the cloud's heading spread): the ranges after t reach x_t
// through the filtered poses after it. Each P_t is floored by one step of the motion noise (a
// cloud resampled onto few ancestors would otherwise stop the pass). The frame correction rotates
// path and covariances together; the calibrated re-run rebuilds both; an applied early-window
// solve's poses are already the window's smoothed solution, so the pass stops at the window's end.
// trajectory_repass (trajectory_repass.cpp): the pose filter re-run over every input against the
// final theta first, and the backward pass over that run.
//
// Initialisation: anchor = start_pose: particles start at the known pose; a landmark is placed by
// multilateration from its first ranges (scale/offset-corrected) and the particle-mean positions
// once they are spread enough (range-bearing: at its first observation, m = p + r (cos, sin)(th + b));
// its statistic starts as the average statistic of those observations.
// anchor = beacons: BEACONS give every landmark's prior (mean and covariance).
#pragma once

#include <array>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "particle_motion.hpp"
#include "observation_model.hpp"
#include "online_em_config.hpp"
#include "roam/estimation/bias_observability.hpp"
#include "roam/estimation/pose_smoother.hpp"
#include "roam/estimation/standstill.hpp"
#include "roam/estimation/window_solve.hpp"
#include "roam/estimator.hpp"

namespace roam {
namespace online_em {

using estimation::solveWindow;
using estimation::WindowProblem;
using estimation::WindowRange;
using estimation::WindowSolution;

class OnlineEmSlam : public Estimator {
 public:
  // Throws ConfigError naming the key if the config breaks a declared check (checkConfig).
  explicit OnlineEmSlam(const OnlineEmConfig& config);

  void setInitialPose(const Pose& start) override;
  void setBeacons(const Map& surveyed) override;
  void addOdometry(const Odometry& odometry) override;
  void addRange(const Range& range) override;
  void finish() override;
  bool trajectory(bool force, Path* path) override;

  // The current map (initialised landmarks, by id) and range model.
  Map currentMap() const;
  double rangeScale() const { return range_scale_; }
  double rangeOffset() const { return range_offset_m_; }
  // A surveyed beacon's own range offset o_b (0 if it has none or is unknown).
  double beaconRangeOffset(int id) const;
  const estimation::OdometryCalibration& odometryCalibration() const { return calibration_; }
  const Path& filteredPath() const { return path_; }
  // The filtered path RTS-smoothed (smooth_trajectory; estimation::smoothPoseChain): each pose's
  // cloud covariance floored by one step of the motion noise, the backward pass stopping at the
  // end of an applied early-window solve (the window's poses are the solve's already).
  Path smoothedPath() const;
  double outlierWeight() const { return 1.0 - mixture_weight0_; }
  double inlierSigmaScale() const { return inlier_sigma0_; }
  const ParticlePoses& particles() const { return particles_; }
  const Eigen::ArrayXd& weights() const { return weights_; }

 private:
  // The multilateration checks a start-pose landmark must pass (tryInitialise), each with its key.
  enum class InitCheck { kTooFew, kNarrowAngle, kShortSpread, kNoConsensus };
  static std::string neverInitialisedReason(InitCheck check);
  struct Landmark {
    int id = 0;
    bool initialised = false;
    Eigen::Vector2d position_m = Eigen::Vector2d::Zero();
    Eigen::Matrix2d covariance = Eigen::Matrix2d::Constant(kNaN);
    int64_t count = 0;  // observations in its statistic (the n of gamma_n)
    bool has_prior = false;
    Eigen::Vector2d prior_mean_m = Eigen::Vector2d::Zero();
    Eigen::Matrix2d prior_information = Eigen::Matrix2d::Zero();
    // The beacon's own range offset o_b (surveyed beacons, beacon_range_offset_sigma_m > 0).
    bool has_offset = false;
    double range_offset_m = 0.0;
    // Running averages over its ranges of P(inlier) and P(inlier) sr^2 / (sr^2 + cloud variance).
    int64_t offset_ranges = 0;
    double mean_inlier = 0.0, mean_inlier_noise_fraction = 0.0;
    // Ranges waiting for multilateration: mean robot pose and the observation.
    std::vector<Eigen::Vector3d> pending_poses;
    std::vector<RangeObservation> pending_observations;
    // The check its last multilateration attempt failed (the reason its ranges are rejected if
    // it never initialises).
    InitCheck failed_check = InitCheck::kTooFew;
  };
  // An observation of an initialised landmark at this step, with its interpolation fraction
  // and the sampled component of each particle.
  struct StepObservation {
    int landmark = 0;
    RangeObservation y;
    double fraction = 1.0;
    std::vector<int> component;         // sampled indicators: the component of each particle
    std::vector<double> wide_probability;  // marginal indicators: P(I = 1 | particle, y)
  };

  void start(const Pose& pose);
  int landmarkIndex(int id);
  Eigen::Vector4d phi(int landmark) const;
  void interpolate(int k, double fraction, double* x_m, double* y_m, double* heading_rad) const;
  void resample();
  void smoothStatistics(std::vector<StepObservation>& observations);
  void tryInitialise(int landmark);
  // A landmark's position from ranges taken at the given positions (sr: the range's sigma): the
  // shared consensus of triples with the inlier band init_outlier_gate_sigmas * sr (at least 1 m,
  // for dead-reckoned positions), or with gate 0 the linear solution on all. False if unsolved.
  bool multilaterateLandmark(const std::vector<std::array<double, 2>>& points, const std::vector<double>& ranges_m,
                             double sr, std::array<double, 2>* beacon_m) const;
  // log of the two-component mixture likelihood, and P(I = 1 | pose, y).
  double mixtureLogLikelihood(const RangeObservation& y, double x_m, double y_m, double heading_rad,
                              const Eigen::Vector4d& phi_i, double* wide_probability) const;
  void mStep();
  void mixtureMStep();
  void calibrationMStep();
  void setDistanceScale(double s);
  void correctFrame();
  // |b| >= k sigma_b (k > 0; false while sigma_b is unknown): rerun_end_bias_sigmas, and the
  // bias retry's test (dead_reckoning_fallback.cpp).
  bool biasSignificant(double k_sigmas) const;
  void applyFrameMotion(double angle_rad, const Eigen::Vector2d& translation_m);
  void rerun();
  void solveEarlyWindow();
  void processOdometry(const Odometry& odometry);
  void publish(int64_t utime);
  // The cloud's weighted mean and covariance (heading: circular mean, spread about it).
  static Pose summarise(const ParticlePoses& particles, const Eigen::ArrayXd& weights, int64_t utime);
  // trajectory_repass: the pose-only particle filter run again over every input against the
  // final theta, its cloud summaries and transitions (empty if it cannot match path_).
  Path repassPath(std::vector<estimation::PoseTransition>* transitions) const;

  OnlineEmConfig config_;
  ParticleMotion motion_;
  ObservationModel observation_;
  std::mt19937_64 rng_;

  bool started_ = false;
  int64_t last_utime_ = 0;
  ParticlePoses particles_, previous_, ancestors_;
  std::vector<int> ancestor_index_;
  Eigen::ArrayXd weights_, previous_weights_;
  Eigen::MatrixXd statistics_;  // N x (kStatSize * landmarks): rho, per particle and landmark
  Eigen::MatrixXd log_kernel_, kernel_, transported_;

  std::vector<Landmark> landmarks_;
  std::map<int, int> index_of_id_;
  // Live ranges of each beacon id not yet in the map: accepted when its landmark initialises,
  // rejected at the end of the run if it never does (the reason names the check it failed).
  std::map<int, int64_t> pending_live_ranges_;
  double range_scale_ = 1.0, range_offset_m_ = 0.0;
  estimation::OdometryCalibration calibration_;
  Eigen::MatrixXd calibration_statistics_;  // N x 2: c_t^k (J^T W z, smoothed and averaged)
  Eigen::Matrix2d calibration_information_ = Eigen::Matrix2d::Zero();  // averaged J^T W J
  Eigen::MatrixXd step_calibration_vector_;
  int64_t motion_steps_ = 0;
  // The early window of the start-pose frame: its odometry and step lengths, open until the
  // second landmark is initialised; the frame motion applied so far.
  Pose start_pose_;
  std::vector<Odometry> window_odometry_;
  std::vector<double> window_dt_s_;
  std::vector<bool> window_standing_;  // the window's steps the vehicle stood still through
  estimation::Standstill standstill_;  // the forward pass's standstill detector
  bool window_open_ = true;
  double frame_angle_rad_ = 0.0;
  Eigen::Vector2d frame_translation_m_ = Eigen::Vector2d::Zero();
  std::vector<Range> queued_ranges_;
  // The window's range-only ranges (solveEarlyWindow) and their observations.
  std::vector<WindowRange> window_ranges_;
  std::vector<RangeObservation> window_observations_;
  bool window_solve_pending_ = false;
  // Calibrated re-run: the inputs in arrival order until it runs, and its state.
  struct Input {
    bool is_odometry = true;
    Odometry odometry;
    Range range;
  };
  std::vector<Input> inputs_;
  std::vector<Input> all_inputs_;  // every input, for trajectory_repass and the bias retry
  bool keepsInputs() const;
  bool recording_ = false, rerun_pending_ = false, replaying_ = false;
  double heading_rate_bias_sigma_rad_s_ = kNaN;
  estimation::OdometryCalibration window_calibration_;  // the early window was dead-reckoned with it
  bool window_stands_calibrated_ = false;               // ... and with the standing rule (after a re-run)
  int64_t observing_steps_ = 0;
  // Heading-rate bias observability (heading_rate_bias_max_drift_rad): the first ranges' times.
  estimation::BiasObservability bias_rate_{0.0, 0.0};
  bool biasEstimated() const { return bias_rate_.decision() == estimation::BiasObservability::Decision::kEstimate; }
  // The TRAJECTORY is smoothed (smooth_trajectory; sparse: where the ranges are too sparse for
  // the bias rule), and the steps it needs are being kept (until sparse is decided, all).
  bool smoothsTrajectory() const;
  bool recordsForSmoothing() const;
  // An input the re-pass (trajectory_repass) will need, kept while recordsForSmoothing().
  void keepForRepass(const Input& input);
  bool biasUndecided() const { return bias_rate_.decision() == estimation::BiasObservability::Decision::kUndecided; }
  void checkBiasObservable(int64_t range_utime);
  // Whether the step is one the vehicle stood still through (stationary_speed_mps): the
  // detector's standstill, turning slower than stationary_max_turn_rate_rad_s.
  bool standingStill(estimation::Standstill* standstill, const Odometry& odometry, double dt_s) const;
  // Adaptive motion noise (adapt_motion_noise): running averages of pi (e^2 - sr^2 - v_map)
  // and pi v / kappa^2 over the ranges, and the scale kappa.
  void adaptMotionNoise(const std::vector<StepObservation>& observations);
  void trackOffsetNoiseFraction(const std::vector<StepObservation>& observations);
  double motion_noise_scale_ = 1.0;
  double mean_excess_m2_ = 0.0, mean_cloud_m2_ = 0.0, mean_predicted_m2_ = 0.0, weight_square_sum_ = 0.0;
  int64_t noise_ranges_ = 0;
  // Mixture in theta: the outlier span, the current (w0, sigma0) and the running averages of
  // P(outlier), (1 - P(outlier)) e^2 / sr^2 and (1 - P(outlier)) over the ranges.
  double max_range_m_ = 0.0;
  double mixture_weight0_ = 0.8, inlier_sigma0_ = 1.0;
  double mean_outlier_ = 0.0, mean_inlier_e2_ = 0.0, mean_inlier_ = 0.0;
  double learned_outlier_weight_ = 0.0;  // w1 before its bound (kMaxOutlierWeight)
  int64_t mixture_ranges_ = 0;
  Path path_;  // filtered means, one per step (the start pose first)
  // Dead-reckoning fallback (fallback_deadreckoning, dead_reckoning_fallback.cpp): the odometry
  // composed from the start pose (uncalibrated: nothing the ranges say is trusted there), and
  // each range applied with the index of the dead-reckoned pose of its step.
  struct DeadReckonedRange {
    size_t pose = 0;
    int beacon_id = 0;
    double range_m = 0.0, sigma_m = 0.0;
  };
  bool fallbackEnabled() const;
  void recordDeadReckoning(const Odometry& odometry);
  void recordDeadReckonedRanges(const std::vector<Range>& ranges);
  void fallBackToDeadReckoning();
  Path deadReckonedPath() const;  // the published TRAJECTORY once fallen back
  // Before falling back with surveyed beacons: a run that held the heading-rate bias at 0 (the
  // sparse-rate rule) is re-run once on every input with the bias estimated, and that run is
  // published where its outlier weight ends under the bound and its bias is significant (a
  // drifting gyro explains the loss; dead_reckoning_fallback.cpp).
  bool retriesWithBiasEstimated() const;
  bool retryWithBiasEstimated();
  Map surveyed_;                                // as given (anchor = beacons)
  std::unique_ptr<OnlineEmSlam> bias_retry_;    // the re-run whose path is published
  // One per step (32 bytes, not a Pose's 104: the fallback is rare and the run may be long).
  struct DeadReckonedPose {
    int64_t utime = 0;
    double x_m = 0.0, y_m = 0.0, heading_rad = 0.0;
  };
  std::vector<DeadReckonedPose> dead_reckoned_;
  std::vector<DeadReckonedRange> dead_reckoned_ranges_;
  bool fallen_back_ = false;
  // The step from path_[k] to path_[k + 1]: its calibrated increment and noise (smoothedPath).
  std::vector<estimation::PoseTransition> transitions_;
  size_t smooth_first_ = 0;  // poses before it are not smoothed (the early window's solve)
  double sum_effective_predecessors_ = 0.0;
  int64_t smoothing_steps_ = 0;
  double min_ess_ = kNaN;
  int64_t degenerate_weight_steps_ = 0;  // steps where no particle had a finite likelihood
};

}  // namespace online_em
}  // namespace roam
