// Cartesian range-only EKF SLAM: roam's "ekf" estimator.
//
// Model: the state is [x, y, theta, (scale, offset), (s, b), m1x, m1y, (o1), ...] (EkfFilter); each odometry
// step predicts the pose with noise
//   var_d      = (odo_distance_sigma_rel d)^2 + odo_distance_sigma_m^2,
//   var_dtheta = (odo_heading_sigma_rel |dtheta|)^2 + odo_heading_sigma_per_sqrt_m^2 d
//                + odo_heading_sigma_rad^2,
// and each range updates it (range-bearing when has_bearing is set), Mahalanobis-gated at
// gate_probability. Timing: a range is held until the odometry step that contains its time
// arrives, then applied part-way through that step: the robot moves straight along its heading
// during a step and turns at its end (the motion model), so the pose at fraction a of the step
// is p + a d (cos theta, sin theta) — exact for the model, not an approximation — and the
// step's distance noise is split a : (1 - a). The pose is published once per odometry step.
//
// Gauge: anchor = start_pose fixes the frame by the INITIAL_POSE (zero covariance);
// anchor = beacons puts the surveyed positions in the state with sigma beacon_sigma_m (and a
// loose prior on the start pose, which the EKF needs as a linearisation point).
//
// Beacon initialisation (range-only beacons are not observable from one range): ranges to an
// unknown beacon are buffered with the filtered pose they were taken at. Once the multilateration
// (roam/estimation/multilateration.hpp) is unambiguous and well constrained, the filter is rolled back to the
// state before that beacon's first buffered range, the beacon is inserted there with a weak
// prior (the batch solution's mean, its covariance times init_prior_inflation), and every step
// since is re-run, re-applying the buffered ranges. The beacon thus enters with the correlations
// with pose, heading and range bias that the filter would have had if it had known the beacon
// from the start, linearised at a good estimate; a beacon inserted from a frozen batch estimate
// instead fixes its error into the frame. With range-bias states the batch estimates scale and
// offset too (prior: the filter's marginal); for the first beacon, while the bias is still at its
// prior, the snapshot's bias mean is re-centred on the batch estimate (its width unchanged), so
// the re-run linearises s |m - p| + b about a consistent pair. A solve is used only once each of
// its ranges is predicted by the others (deleted residual within the gate, also with the solve's
// most informative range left out): one outlier at the end of a narrow arc cannot place the
// beacon. The published TRAJECTORY is the
// filtered path after these re-runs, smoothed backwards (smooth_trajectory, ekf_smoother.hpp);
// POSE messages are the filter's and those already published are not revised. History
// is kept only while a beacon is pending (bounded by init_max_ranges and init_window_s).
// Start pose: once every beacon seen so far is in the state, the window from the start is solved
// jointly (path and map, ekf_window_init.cpp) and, where its ranges refute the dead-reckoned
// path, the insertions move to its map and the history is re-run (init_window_solve).
#pragma once

#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "ekf_config.hpp"
#include "ekf_filter.hpp"
#include "ekf_joint_bias.hpp"
#include "ekf_team.hpp"
#include "roam/estimation/bias_observability.hpp"
#include "roam/estimation/motion_model.hpp"
#include "roam/estimation/multilateration.hpp"
#include "roam/estimation/standstill.hpp"
#include "roam/estimator.hpp"

namespace roam {
namespace ekf {

using estimation::MultilaterationConfig;
using estimation::MultilaterationResult;
using estimation::RangeBiasPrior;
using estimation::Sighting;

// A range's log-likelihood under an outlier mixture: (1 - w) N(innovation; 0, S) + w / span, the
// outliers uniform over span (m). Scores the starvation trial's two runs and the bank's models.
double rangeLogLikelihood(double innovation_m, double innovation_var_m2, double outlier_weight, double span_m);

class EkfSlam : public Estimator {
 public:
  explicit EkfSlam(const EkfConfig& config);

  // A team run: every later input goes to the centralised team filter (ekf_team.hpp), which this
  // one-robot filter's machinery never sees.
  void setTeam(const std::vector<std::string>& robots) override;
  void setInitialPose(const Pose& start) override;
  void setBeacons(const Map& surveyed) override;
  void addOdometry(const Odometry& odometry) override;
  void addRange(const Range& range) override;
  void finish() override;
  bool trajectory(bool force, Path* path) override;

  bool started() const { return started_; }
  const EkfTeam* team() const { return team_.get(); }
  // The sparse-rate rule on the heading-rate bias (gyro_bias_max_drift_rad): still to decide (the
  // first 20 ranges), or decided to hold it at 0.
  bool headingRateBiasUndecided() const { return bias_undecided_; }
  bool headingRateBiasHeld() const { return bias_fixed_; }
  const EkfFilter& filter() const { return filter_; }
  const Path& path() const { return path_; }  // filtered path, one pose per step
  Map currentMap() const;
  // Beacons waiting for initialisation, with their buffered range counts.
  std::map<int, int> pendingBeacons() const;
  // Each delayed initialisation: when it happened and the batch solve it started from.
  struct Initialisation {
    int id;
    int64_t utime;        // when the solve was accepted
    int64_t first_utime;  // the step the beacon entered at (its first buffered range)
    int num_ranges;
    MultilaterationResult solve;
    std::vector<Sighting> sightings;  // the ones the solve used
  };
  const std::vector<Initialisation>& initialisations() const { return initialisations_; }
  // The sum over the live ranges to beacons in the state (with surveyed beacons: to surveyed
  // beacons) of their log-likelihood before their update (rangeLogLikelihood, with half the ranges
  // outliers over the longest range so far): how well this filter predicted the ranges (the
  // prediction-error decomposition of the run's likelihood). Re-runs do not change it. What the
  // bank of translation-noise models compares (ekf_bank.hpp).
  double predictiveLogLikelihood() const { return predictive_log_likelihood_; }
  static constexpr double kScoreOutlierWeight = 0.5;
  // The history held for re-runs: its steps, and how many of them keep a state snapshot (a state
  // and covariance each, the history's memory: rerunMayStartAt).
  size_t historySteps() const { return history_.size(); }
  size_t historySnapshots() const;

 private:
  struct Insert {
    int id;
    Eigen::Vector2d world_m;
    Eigen::Matrix2d cov_m2;
  };
  // The noise the filter has adapted and its count towards a starvation recovery: with the
  // filter, what a re-run from a step starts from.
  struct Adaptation {
    int gated_in_row = 0;  // ranges to known beacons gated since the last applied one
    double min_gated_innovation_m = 0.0;
    // Each beacon's run of gated ranges since its last applied range: their innovations (range -
    // predicted, m) and the run's first range's time.
    struct GatedRun {
      std::vector<double> innovations_m;
      int64_t since_utime = 0;
    };
    std::map<int, GatedRun> gated_runs;
    // Each surveyed beacon's last applied range: its innovation, predicted variance, the beacon's
    // position less the robot's, and time (recover_consistent_fit).
    struct Applied {
      double innovation_m;
      double innovation_var_m2;
      Eigen::Vector2d beacon_from_robot_m;
      int64_t utime;
    };
    std::map<int, Applied> last_applied;
    double motion_noise_scale = 1.0;  // multiplies the odometry covariance (starvation raises it)
    double range_noise_scale = 1.0;   // multiplies the range variance (adaptRangeNoise)
    double nis_average = 1.0;         // running average of applied ranges' NIS
  };
  // What became of a range to a beacon in the state.
  enum class Verdict { kApplied, kGated, kDegenerate };
  // A starvation widening on trial (ekf_recovery.cpp): the filter runs on without it while the
  // ranges since the trigger are scored, then the steps since are re-run with it.
  struct RecoveryTrial {
    bool active = false;
    bool recording = false;   // scoring: from the trigger (the run without) or the widening (the re-run)
    int64_t step = -1;        // the step whose range completed the run of gated ranges
    int64_t step_utime = 0;   // that step's start
    double outlier_weight = 0.5;  // the scoring mixture, fixed at the trigger: outlier weight,
    double span_m = 1.0;          // and the outliers' uniform span (the longest range so far)
    double log_likelihood = 0.0;
    std::vector<Verdict> verdicts;  // of the scored ranges: counted once the trial is decided
  };
  // One odometry step with the ranges applied within it, and the filter before it.
  struct Step {
    int64_t index = 0;
    Odometry odometry;
    std::vector<Range> ranges;
    std::vector<Insert> inserts;  // beacons entering the state at the start of this step
    std::vector<Insert> moves;    // lost beacons taken out and re-entered at the start of this step
    EkfFilter before;
    int64_t before_utime = 0;
    size_t path_size = 0;
    bool standstill = false;  // a confirmed standstill (confirmStandstill): zero-rate update
    Adaptation before_adaptation;
  };

  void start(const Pose& pose);
  void insertSurveyed();
  void runStep(const Step& step, bool live);
  void advance(Step step, bool live);  // snapshot, runStep, keep in history_, initialise ready beacons
  void runSnapshotted(Step* step, bool live, bool rerun_start);  // runStep, keeping the snapshot where needed
  bool rerunMayStartAt(int64_t step_index) const;  // does the step's snapshot need keeping
  void handleRange(const Range& range, int64_t step_index, bool live);
  Sighting sightingNow(const Range& range, double sigma_m, int64_t step_index) const;  // at the filter's pose
  // A beacon placed from the ranges whose ranges keep being gated (lost_beacon_gated_ranges,
  // ekf_beacon_init.cpp): re-solved from them, and moved at the next step where they refute it.
  void noteLostBeacon(int id, Sighting sighting);
  void forgetLostBeacons();  // a re-run rewrote the filter the gated runs were judged against
  void initialiseReadyBeacons();
  std::vector<Sighting> consensusSightings(const std::vector<Sighting>& sightings, const RangeBiasPrior& bias) const;
  static constexpr int kTrimIterations = 5;
  MultilaterationResult trimmedSolve(const std::vector<Sighting>& sightings, const RangeBiasPrior& bias,
                                     std::vector<Sighting>* used) const;
  bool biasConsistent(const MultilaterationResult& solve, const RangeBiasPrior& bias) const;
  MultilaterationResult dropDeletedOutliers(MultilaterationResult solve, const RangeBiasPrior& bias, std::vector<Sighting>* used) const;
  size_t mostInformative(const MultilaterationResult& solve, const std::vector<Sighting>& used, const RangeBiasPrior& bias) const;
  double deletedResidualZ2(const std::vector<Sighting>& used, size_t i, size_t also_out, const RangeBiasPrior& bias) const;
  // The early window from the start solved jointly once every beacon seen so far is in the
  // state (ekf_window_init.cpp): the insertions moved to its map and the history re-run.
  void solveEarlyWindow();
  void rollbackAndInsert(int id, const MultilaterationResult& solve, std::vector<Sighting> used);
  void replayFrom(int64_t offset, int64_t first_step);
  // The calibrated re-run (anchor = start_pose) once the bias is known; live, it waits for every
  // pending beacon. pending_may_not_wait: the end of input (a beacon still pending will get no
  // sighting more), or the history it needs about to be freed: a pending beacon no longer holds
  // it back.
  void rerunWithCalibration(bool pending_may_not_wait = false);
  // The history from step 0 is older than init_window_s: prune frees it unless a re-run is made.
  bool rerunHistoryExpiring() const;
  void reinitialiseFromStart();  // re-filters the kept history with every beacon initialised afresh
  bool confirmStandstill(const Odometry& odometry, double dt_s);
  bool stationaryBiasUpdate(const Odometry& odometry, double dt_s, double var_turn_rad2);
  void prune();
  void truncatePath(size_t size);  // path_ (and nodes_) back to their first `size` poses
  void pushPose(SmootherNode node);
  Pose currentPose(int64_t utime) const;
  void publishDiagnostics();
  estimation::MotionNoise motionNoise(const Odometry& odometry) const;
  Eigen::Matrix3d scaledMotionNoise(const Eigen::Matrix3d& Q) const;
  EkfFilter::CalibrationPrior calibrationPrior() const;
  // The starvation recovery (ekf_recovery.cpp).
  // A range to a known beacon that the gate turned away: its innovation, predicted variance,
  // the range's sigma and time.
  struct GatedRange {
    int beacon_id;
    double innovation_m;
    double innovation_var_m2;
    double sigma_m;
    int64_t utime;
  };
  void noteGated(const GatedRange& gated, int64_t step_index, bool live);
  bool consistentlyGated(const GatedRange& gated);
  bool onePositionErrorExplains(const GatedRange& gated) const;
  bool isSurveyed(int beacon_id) const;  // anchor = beacons and in BEACONS
  void widenStarved();
  void startRecoveryTrial(int64_t step_index);
  void scoreRange(double innovation_m, double innovation_var_m2);
  void countRange(Verdict verdict, bool live, bool recording);
  void commitVerdict(Verdict verdict);
  bool recoveryTrialDue() const;
  void decideRecoveryTrial();
  void abandonRecoveryTrial();  // a re-run rewrote the trial's steps: the running filter's verdicts stand
  void checkBiasObservable(int64_t range_utime);
  bool biasEstimated(int64_t step_index) const;  // b is a live state in this step
  void adaptRangeNoise(double nis);
  RangeBiasPrior rangeBiasPrior() const;  // the filter's range scale and offset as a prior
  JointBiasResult jointHeadingBias() const;

  EkfConfig config_;
  std::unique_ptr<EkfTeam> team_;  // a team run (setTeam); null for one robot
  // A team run: the team filter's poses, counts and notes passed on.
  void publishTeam();
  MultilaterationConfig init_config_;
  double gate_range_chi2_ = 0.0;          // 1 dof
  double gate_range_bearing_chi2_ = 0.0;  // 2 dof
  EkfFilter filter_;
  bool started_ = false;
  int64_t state_utime_ = 0;
  int64_t next_step_ = 0;
  std::vector<Range> waiting_;  // ranges for the next odometry step
  std::deque<Step> history_;    // steps since the first sighting of a pending beacon
  int64_t last_sighting_step_ = -1;  // the step that last buffered a range to a pending beacon
  std::map<int, std::vector<Sighting>> pending_;
  // Live ranges gated in a row to each beacon placed from the ranges (noteLostBeacon), the last
  // solve of them, and the moves that solve asked for (made at the start of the next step).
  std::map<int, std::vector<Sighting>> lost_;
  std::map<int, MultilaterationResult> lost_last_solve_;
  std::map<int, size_t> lost_last_try_;
  std::map<int, std::deque<Sighting>> applied_sightings_;  // each such beacon's last applied ranges (the vote)
  std::vector<Insert> moves_;
  int beacons_moved_ = 0;
  int64_t joint_bias_misfits_ = 0;  // joint heading-bias solves refused for their chi2
  // Live ranges to each beacon not yet initialised: counted accepted when it enters the state,
  // rejected at the end (with the check that kept it out) if it never does.
  std::map<int, int64_t> pending_live_ranges_;
  std::set<int> touched_;  // pending beacons with new sightings since the last check
  Map surveyed_;
  Path path_;
  // smooth_trajectory: the filter at each pose of path_ and the operations between them, and
  // those after the last pose (finish()); cut with path_ on every re-run.
  std::vector<SmootherNode> nodes_;
  std::vector<SmootherOperation> trailing_;
  size_t first_smoothed_ = 0;  // nodes_ before it were released (smooth_max_memory_mb)
  size_t smoother_bytes_ = 0;  // what nodes_ from first_smoothed_ on hold
  // The last TRAJECTORY before the end of input (smooth_live_lag_s) and the nodes_ it was
  // smoothed from: a re-run or a new start cuts nodes_ and bumps the generation.
  Path live_smoothed_;
  uint64_t smoother_generation_ = 0, live_smoothed_generation_ = 0;
  bool map_dirty_ = false;
  std::vector<Initialisation> initialisations_;
  // Each pending beacon's last batch-solve status (STATUS: why it is not initialised).
  std::map<int, MultilaterationResult::Status> init_status_;
  std::map<int, MultilaterationResult> last_solve_;  // each pending beacon's previous solve
  std::map<int, size_t> last_trim_size_;             // its buffer's size at the last trimmed solve
  int64_t replays_ = 0;
  bool window_tried_ = false;     // the early window solve (once per run):
  double window_gain_ = 0.0;      // its likelihood-ratio gain,
  double window_turn_rad_ = 0.0;  // its heading correction at the window's end,
  bool window_applied_ = false;   // and whether it was used
  double window_gate_ = 0.0;      // the gain it had to reach
  double inlier_scatter_ = 0.0;   // the window's inlier scatter over the stated sigma
  // Buffered ranges (beacon, time) its batch solution did not explain: not re-applied.
  std::set<std::pair<int, int64_t>> excluded_ranges_;
  std::set<std::pair<int, int64_t>> first_pass_excluded_;  // excluded_ranges_ of the pass before a fresh re-run
  int64_t excluded_ranges_total_ = 0;
  int64_t gated_ = 0;
  Adaptation adapt_;
  double predictive_log_likelihood_ = 0.0;
  int64_t recoveries_ = 0;
  int64_t recoveries_declined_ = 0;   // widenings whose trial the run without them won
  int64_t consistent_runs_declined_ = 0;  // repeated innovations no one position error explains
  int64_t offsets_reopened_ = 0;           // repeated shortfalls that re-opened a beacon's offset
  RecoveryTrial trial_;
  bool trial_rerun_ = false;          // re-running the trial's steps with the widening
  bool finishing_ = false;            // finish(): a starvation run widens at once
  int64_t known_ranges_live_ = 0;     // live ranges to beacons in the state,
  int64_t known_ranges_gated_live_ = 0;  // and of them gated (the trial's outlier weight)
  double max_range_m_ = 0.0;          // the longest range so far (the trial's outlier span)
  // Bias observability (checkBiasObservable): the first ranges' times, and the decision.
  estimation::BiasObservability bias_rate_{0.0, 0.0};
  // Until decided, b is held at 0; estimated from step bias_release_step_ on (re-runs too).
  bool bias_fixed_ = false;
  bool bias_undecided_ = false;
  int64_t bias_release_step_ = -1;
  double rerun_bias_var_ = -1.0;  // b's variance at its release in a fresh re-run (< 0: the prior's)
  bool calib_rerun_pending_ = false;  // history kept from the start for one calibrated re-run
  int64_t calibration_reruns_ = 0;
  int64_t fresh_reruns_ = 0;              // of which re-initialised every beacon (rerunWithCalibration)
  int64_t stationary_updates_ = 0;
  estimation::Standstill standstill_;  // confirmStandstill: the shared standstill rule
};

}  // namespace ekf
}  // namespace roam
