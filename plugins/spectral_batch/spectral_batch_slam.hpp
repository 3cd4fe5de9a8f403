// Spectral + batch range-only SLAM: a sparse nonlinear least-squares smoother over every pose and
// beacon, solved with Ceres and seeded by the spectral solution (Boots & Gordon, ICML 2013,
// Sec. 5: "spectral SLAM as an initialization procedure for nonlinear batch optimization") or by
// dead reckoning (their "Batch Opt." row, with the same solver).
//
// Model. Unknowns: poses world_T_robot_k = (x, y, heading) at the start (k = 0) and at the end
// of every odometry step, beacons (x, y), and an optional shared range calibration (scale s,
// offset o). Odometry step k is a between-pose residual in robot frame k (along track, lateral,
// heading increment; sigmas in batch_config.hpp). A range is predicted as s |m - p(t)| + o at the
// robot position INTERPOLATED LINEARLY along the odometry step that contains its time t (ranges
// before the start use the start pose; at the end of input, ranges after the last pose use the
// last pose; in live mode they wait for the next step). Residuals in batch_residuals.hpp, solve
// with an annealed robust loss in batch_problem.hpp.
//
// Gauge: anchor = start_pose holds pose 0 at INITIAL_POSE (or the origin if none came);
// anchor = beacons holds the surveyed beacons of BEACONS (beacons not surveyed stay free). From the
// start pose at sparse range rates, with the odometry's covariance stated, the heading noise is the
// stated one and the bias is held (sparse_heading_as_stated, batch_config.hpp).
//
// Initial guess (first solve): init = spectral takes the spectral core's path (positions and its
// headings, one pose per odometry step plus the start) and map; init = deadreckoning integrates
// odometry from the start pose. Beacons not given by the seed (or the survey) are multilaterated
// from the guessed path. If the spectral seed is unavailable (too little data, wrong length or an
// error) dead reckoning is used and diagnostic "init_spectral" is 0.
//
// Output. This is a smoother: POSE per odometry step is the latest solve's last pose propagated
// by the odometry since (dead reckoning before the first solve). resolve_interval_s > 0: live mode,
// re-solving over all data so far every interval of data time, warm-started from the previous
// solution (new poses by odometry from its last pose); TRAJECTORY and MAP after every solve and at
// finish(), which always solves over everything (re-seeded from the spectral solution over all
// data if the live solves began before the spectral core had a path). Solver summary in
// diagnostics().
#pragma once

#include <array>
#include <map>
#include <memory>
#include <vector>

#include "batch_config.hpp"
#include "batch_problem.hpp"
#include "team_batch.hpp"
#include "roam/estimation/motion_model.hpp"
#include "roam/estimator.hpp"

namespace roam {
namespace spectral_batch {

class SpectralBatchSlam : public Estimator {
 public:
  // Throws ConfigError naming the key on a bad config (std::invalid_argument: init = spectral
  // without the spectral core).
  explicit SpectralBatchSlam(const SpectralBatchConfig& config);
  ~SpectralBatchSlam() override;

  // A team run: every later input goes to the team solve (team_batch.hpp).
  void setTeam(const std::vector<std::string>& robots) override;
  void setInitialPose(const Pose& start) override;
  void setBeacons(const Map& surveyed) override;
  void addOdometry(const Odometry& odometry) override;
  void addRange(const Range& range) override;
  void finish() override;
  bool trajectory(bool force, Path* path) override;

  // The latest solve (all zero before the first).
  const spectral_batch::Summary& lastSummary() const { return summary_; }
  double rangeScale() const { return calibration_[0]; }
  double rangeOffset_m() const { return calibration_[1]; }
  estimation::OdometryCalibration odometryCalibration() const {
    return {odometry_calibration_[0], odometry_calibration_[1]};
  }
  int solves() const { return solves_; }
  // The latest solved map (empty before the first solve).
  Map map() const;

 private:
  void start(const Pose& start);
  // A range tied to the pose chain: pose k, alpha along step k.
  struct Tie {
    int pose;
    double alpha;
    const Range* range;
  };
  struct Candidate {
    spectral_batch::Problem problem;
    spectral_batch::State state;
    spectral_batch::Summary summary;
    std::map<int, int> index_of;  // beacon id -> beacon block
  };
  std::vector<Tie> tieRanges(bool final) const;
  double rangeSigma(const Range& range) const;
  // One solve (or, evaluate_only, the cost of the guess with the final loss) from these poses;
  // beacons from the seed map, the previous solve (use_previous, also the calibrations) or
  // robust multilateration from the poses.
  Candidate solveFrom(std::vector<std::array<double, 3>> poses, const Map* seed_map, bool use_previous,
                      bool fix_first_heading, const std::vector<Tie>& tied, bool evaluate_only,
                      double odometry_noise_factor,
                      const std::array<double, 2>& odometry_calibration) const;
  // The heading-rate bias whose dead reckoning best explains the ranges (robust cost), scanned
  // over +-3 prior sigmas (coarse to fine).
  double scanHeadingRateBias(const std::vector<Tie>& tied) const;
  // anchor = start_pose: rotates the solution about pose 0 onto the calibrated odometry of the
  // first gauge_align_m of travel (the rotation gauge).
  void alignRotationToOdometry(spectral_batch::State* state);
  // Rotates poses and beacons about pose 0 by angle_rad (a gauge move: no residual changes).
  void rotateAboutStart(spectral_batch::State* state, double angle_rad);
  // dead_reckoning_seed = when_in_doubt: whether a first solve misfits the model (its odometry
  // cost above half its ranges' count, or too few inliers), so that the dead-reckoning seed is
  // solved too; the reason, when verbose, goes to stderr.
  bool inDoubt(const Candidate& first) const;
  // The candidate's cost (final loss) with this odometry noise scale.
  double costWithNoise(const Candidate& candidate, double odometry_noise_factor) const;
  // gauge = pinned: turn the solution so that pose 0 has the start heading and re-solve with it
  // held (a dead-reckoning seed is solved so already).
  void pinStartHeading(Candidate* candidate);
  void solveNow(bool final);
  // Sets heading_as_stated_ from the ranges so far (sparse_heading_as_stated); final: with its note.
  void decideHeadingAsStated(bool final);
  // The final solve is not trusted (why): fail (fallback_deadreckoning = false), or publish dead
  // reckoning (alone: its poses and multilaterated beacons) with the reason in STATUS.
  void refuse(Candidate alone, const std::string& why);
  std::vector<std::array<double, 3>> initialPoses(bool final);
  Path currentPath() const;

  SpectralBatchConfig config_;
  std::unique_ptr<Estimator> spectral_;  // the seed (init = spectral), fed every input
  std::unique_ptr<TeamBatch> team_;      // a team run's solve (setTeam), instead of all below
  void finishTeam();
  bool started_ = false;
  bool have_initial_pose_ = false;  // INITIAL_POSE came (not the origin by default)
  std::array<double, 3> start_pose_{0.0, 0.0, 0.0};  // world_T_robot at pose_utime_[0]
  Map surveyed_;
  std::vector<Odometry> odometry_;    // step k ends at pose_utime_[k + 1]
  std::vector<int64_t> pose_utime_;   // pose_utime_[0] is the start
  std::vector<double> dt_s_;          // duration of step k
  std::vector<Range> ranges_;         // every accepted range, in arrival order

  // The latest solution: poses 0 .. solved_poses_.size() - 1, beacons by id, calibration.
  std::vector<std::array<double, 3>> solved_poses_;
  std::map<int, std::array<double, 2>> solved_beacons_;
  std::array<double, 2> calibration_{1.0, 0.0};
  std::array<double, 2> odometry_calibration_{1.0, 0.0};  // distance scale, heading-rate bias
  std::map<int, double> beacon_offsets_m_;
  std::array<double, 3> current_pose_{0.0, 0.0, 0.0};  // the latest estimate, propagated
  int64_t last_solve_utime_ = 0;
  bool new_solution_ = false;
  bool seeded_by_spectral_ = false;  // the solution descends from the spectral seed
  std::array<double, 2> shifted_seed_m_{0.0, 0.0};  // translation applied to the spectral seed
  bool spectral_map_taken_ = false;
  int solves_ = 0;
  bool heading_as_stated_ = false;  // this solve: decideHeadingAsStated
  double odometry_alone_cost_ = 0.0;
  double best_cost_ = 0.0;
  double odometry_noise_factor_ = 1.0;  // the odometry's noise scale: the latest estimate
  spectral_batch::Summary summary_;
};

}  // namespace spectral_batch
}  // namespace roam
