#include "batch_config.hpp"

#include "roam/estimation/range_model.hpp"

namespace roam {
namespace spectral_batch {

double effectiveLossScale(const SpectralBatchConfig& c) {
  if (c.loss_scale > 0.0) return c.loss_scale;
  if (c.loss == SpectralBatchConfig::Loss::kHuber) return estimation::kHuber95;
  if (c.loss == SpectralBatchConfig::Loss::kCauchy) return estimation::kCauchy95;
  if (c.loss == SpectralBatchConfig::Loss::kTukey) return estimation::kTukey95;
  return 1.0;  // none: unused
}

void addSpectralBatchOptions(Options& o, SpectralBatchConfig* c) {
  using C = SpectralBatchConfig;
  o.add("init", &c->init, {{"spectral", C::Init::kSpectral}, {"deadreckoning", C::Init::kDeadReckoning}}, "initial guess: spectral | deadreckoning");
  o.add("anchor", &c->anchor, {{"start_pose", C::Anchor::kStartPose}, {"beacons", C::Anchor::kBeacons}}, "gauge: start_pose | beacons");
  o.add("seed_heading_align_m", &c->seed_heading_align_m,
        "init = spectral: seed headings = odometry headings rotated onto the spectral positions over "
        "this much travel (0: spectral headings)").min(0.0);
  o.add("loss", &c->loss, {{"huber", C::Loss::kHuber}, {"cauchy", C::Loss::kCauchy}, {"tukey", C::Loss::kTukey}, {"none", C::Loss::kNone}},
        "robust loss on ranges: huber | cauchy | tukey | none");
  o.add("loss_scale", &c->loss_scale, "robust loss scale in sigmas (0: the loss's 95 % efficiency constant)").min(0.0);
  o.add("loss_anneal_stages", &c->loss_anneal_stages, "solves with a narrowing robust loss").min(1).max(10);
  o.add("loss_anneal_factor", &c->loss_anneal_factor, "loss scale ratio between annealing stages").min(1.0);
  o.add("loss_anneal_check", &c->loss_anneal_check, "each annealed solve is also made from the same start at the final loss scale alone, and the lower cost is kept");
  o.add("estimate_range_scale", &c->estimate_range_scale, "estimate a shared range scale");
  o.add("estimate_range_offset", &c->estimate_range_offset, "estimate a shared range offset");
  o.add("estimate_odometry_calibration", &c->estimate_odometry_calibration,
        "estimate the odometry distance scale and heading-rate (gyro) bias");
  o.add("heading_rate_bias_max_drift_rad", &c->heading_rate_bias_max_drift_rad,
        "ranges sparser than this heading turn (rad) over three fixes under the bias prior are sparse (<= 0: never)");
  o.add("sparse_heading_as_stated", &c->sparse_heading_as_stated,
        "anchor = start_pose, sparse ranges: the odometry heading noise as the log states it, bias held at 0");
  o.add("estimate_noise_scale", &c->estimate_noise_scale,
        "widen the odometry noise by profile likelihood where the stated noise is too small");
  o.add("gauge", &c->gauge, {{"window", C::Gauge::kWindow}, {"pinned", C::Gauge::kPinned}},
        "anchor = start_pose: rotation gauge: the gauge_align_m window | pose 0 held at the start heading");
  o.add("start_pose_sigma_m", &c->start_pose_sigma_m, "anchor = beacons: prior sigma of pose 0 at INITIAL_POSE (0: none)").min(0.0);
  o.add("start_heading_sigma_rad", &c->start_heading_sigma_rad, "anchor = beacons: prior heading sigma of pose 0").min(0.0, false);
  o.add("gauge_align_m", &c->gauge_align_m,
        "anchor = start_pose: align the final rotation to calibrated odometry over this much travel (0: off)").min(0.0);
  o.add("dead_reckoning_seed", &c->dead_reckoning_seed,
        {{"when_in_doubt", C::DeadReckoningSeed::kWhenInDoubt}, {"always", C::DeadReckoningSeed::kAlways}},
        "final solve: also solve from dead reckoning when_in_doubt (the first solve misfits) | always");
  o.add("doubt_inlier_fraction", &c->doubt_inlier_fraction,
        "dead_reckoning_seed = when_in_doubt: a first solve with fewer inliers than this fraction is in doubt").min(0.0).max(1.0);
  o.add("min_inlier_fraction", &c->min_inlier_fraction,
        "no beacon fixed: fail when fewer ranges than this fraction are inliers (0: off)").min(0.0).max(1.0);
  o.add("fallback_deadreckoning", &c->fallback_deadreckoning,
        "an untrusted final solve publishes dead reckoning (with the reason) instead of failing");
  o.add("estimate_beacon_offsets", &c->estimate_beacon_offsets, "estimate a range offset per beacon");
  o.add("range_scale_sigma", &c->range_scale_sigma, "prior sigma of the range scale about 1 (0: none)").min(0.0);
  o.add("resolve_interval_s", &c->resolve_interval_s, "live re-solve interval of data time (0: at the end only)").min(0.0);
  o.add("linear_solver", &c->linear_solver,
        {{"sparse_normal_cholesky", C::LinearSolver::kSparseNormalCholesky}, {"dense_qr", C::LinearSolver::kDenseQr},
         {"sparse_schur", C::LinearSolver::kSparseSchur}, {"iterative_schur", C::LinearSolver::kIterativeSchur},
         {"cgnr", C::LinearSolver::kCgnr}},
        "Ceres linear solver");
  o.add("max_iterations", &c->max_iterations, "Ceres iterations per annealing stage").min(1);
  o.add("function_tolerance", &c->function_tolerance, "Ceres relative cost change to stop").min(0.0);
  o.add("gradient_tolerance", &c->gradient_tolerance, "Ceres gradient max-norm to stop").min(0.0);
  o.add("parameter_tolerance", &c->parameter_tolerance, "Ceres relative step size to stop").min(0.0);
  o.add("num_threads", &c->num_threads, "Ceres threads").min(1);
  o.add("verbose", &c->verbose, "print the solver summary on stderr after every solve");
  addSensorNoiseOptions(o, c, OdometryFloors::kPositive);  // its smoother weighs each step by its noise
}

}  // namespace spectral_batch
}  // namespace roam
