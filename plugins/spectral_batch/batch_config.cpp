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
  o.add("loss", &c->loss, {{"huber", C::Loss::kHuber}, {"cauchy", C::Loss::kCauchy}, {"tukey", C::Loss::kTukey}, {"none", C::Loss::kNone}},
        "robust loss on ranges: huber | cauchy | tukey | none");
  o.add("estimate_range_scale", &c->estimate_range_scale, "estimate a shared range scale");
  o.add("estimate_range_offset", &c->estimate_range_offset, "estimate a shared range offset");
  o.add("estimate_odometry_calibration", &c->estimate_odometry_calibration,
        "estimate the odometry distance scale and heading-rate (gyro) bias");
  o.add("heading_rate_bias_max_drift_rad", &c->heading_rate_bias_max_drift_rad,
        "ranges sparser than this heading turn (rad) over three fixes under the bias prior are sparse (<= 0: never)");
  o.add("gauge", &c->gauge, {{"window", C::Gauge::kWindow}, {"pinned", C::Gauge::kPinned}},
        "anchor = start_pose: rotation gauge: the gauge_align_m window | pose 0 held at the start heading");
  o.add("start_pose_sigma_m", &c->start_pose_sigma_m, "anchor = beacons: prior sigma of pose 0 at INITIAL_POSE (0: none)").min(0.0);
  o.add("start_heading_sigma_rad", &c->start_heading_sigma_rad, "anchor = beacons: prior heading sigma of pose 0").min(0.0, false);
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
  o.add("num_threads", &c->num_threads, "Ceres threads").min(1);
  o.add("verbose", &c->verbose, "print the solver summary on stderr after every solve");
  addSensorNoiseOptions(o, c, OdometryFloors::kPositive);  // its smoother weighs each step by its noise
}

}  // namespace spectral_batch
}  // namespace roam
