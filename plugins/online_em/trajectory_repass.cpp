// trajectory_repass: the pose filter of online_em_slam.hpp (steps 1 of Algorithm 1: systematic
// resampling, the prior kernel, the ranges through the mixture) run once more over every input
// with theta fixed at its final value: the map (landmarks never placed are not scored), the
// range scale and offsets, the odometry calibration, the mixture and the motion-noise scale
// kappa. No statistics, no M-step: O(N) per step against the forward pass's N x N kernel. Its
// own generator (the configured seed, offset), so the forward pass is untouched and repeats are
// bit-identical.
#include <algorithm>
#include <cmath>
#include <limits>

#include "online_em_slam.hpp"

namespace roam {
namespace online_em {

Path OnlineEmSlam::repassPath(std::vector<estimation::PoseTransition>* transitions) const {
  transitions->clear();
  if (all_inputs_.empty()) return {};
  const int n = config_.num_particles;
  ParticleMotion motion(config_);
  estimation::Standstill standstill = standstill_;  // the forward pass's rule, from the first step
  standstill.reset();
  motion.setTranslationNoiseScale(motion_noise_scale_);
  motion.enableScaleSpread(false);
  motion.shareHeadingNoiseOverLongSteps(bias_rate_.estimateSoFar());  // as the forward pass ended
  std::mt19937_64 rng(static_cast<uint64_t>(config_.seed) + 0x9e3779b97f4a7c15ULL);
  ParticlePoses particles, previous;
  particles.resize(n);
  previous.resize(n);
  particles.x_m.setConstant(start_pose_.x_m);
  particles.y_m.setConstant(start_pose_.y_m);
  particles.heading_rad.setConstant(start_pose_.heading_rad);
  Eigen::ArrayXd weights = Eigen::ArrayXd::Constant(n, 1.0 / n);
  std::vector<int> ancestor(n, 0);
  std::vector<double> cumulative(n);
  Path path{summarise(particles, weights, start_pose_.utime)};
  int64_t last_utime = start_pose_.utime;
  std::vector<Range> queued, later;
  for (const Input& input : all_inputs_) {
    if (!input.is_odometry) {
      queued.push_back(input.range);
      continue;
    }
    const Odometry& odometry = input.odometry;
    if (odometry.utime < last_utime) continue;  // rejected by the forward pass as well
    const double dt_s = 1e-6 * static_cast<double>(odometry.utime - last_utime);
    // Systematic resampling from the weights of the step before.
    double sum = 0.0;
    for (int j = 0; j < n; ++j) cumulative[j] = (sum += weights[j]);
    const double offset = std::uniform_real_distribution<double>(0.0, sum)(rng) / n;
    for (int l = 0; l < n; ++l) {
      const double u = offset + sum * l / n;
      ancestor[l] = std::min(n - 1, static_cast<int>(std::upper_bound(cumulative.begin(), cumulative.end(), u) -
                                                     cumulative.begin()));
    }
    previous = particles;
    motion.setControl(odometry, dt_s, calibration_, standingStill(&standstill, odometry, dt_s));
    transitions->push_back({motion.increment(), motion.incrementCovariance()});
    for (int l = 0; l < n; ++l) motion.sample(previous, ancestor[l], &particles, l, rng);
    Eigen::ArrayXd log_weight = Eigen::ArrayXd::Zero(n);
    later.clear();
    for (const Range& r : queued) {
      if (r.utime > odometry.utime) {
        later.push_back(r);
        continue;
      }
      const auto found = index_of_id_.find(r.beacon_id);
      if (found == index_of_id_.end() || !landmarks_[found->second].initialised) continue;
      RangeObservation y;
      y.range_m = r.range_m;
      y.sigma_m = r.sigma_m;
      y.has_bearing = r.has_bearing;
      y.bearing_rad = r.bearing_rad;
      const double fraction = odometry.utime > last_utime
                                  ? std::clamp(static_cast<double>(r.utime - last_utime) /
                                                   static_cast<double>(odometry.utime - last_utime), 0.0, 1.0)
                                  : 1.0;
      const Eigen::Vector4d phi_i = phi(found->second);
      for (int k = 0; k < n; ++k) {
        const int a = ancestor[k];
        const double x = previous.x_m[a] + fraction * (particles.x_m[k] - previous.x_m[a]);
        const double yy = previous.y_m[a] + fraction * (particles.y_m[k] - previous.y_m[a]);
        const double th = previous.heading_rad[a] + fraction * (particles.heading_rad[k] - previous.heading_rad[a]);
        double wide_probability = 0.0;
        log_weight[k] += mixtureLogLikelihood(y, x, yy, th, phi_i, &wide_probability);
      }
    }
    queued.swap(later);
    // Normalised; no finite likelihood (or NaN): uniform, as the forward pass.
    const Eigen::ArrayXd lw = log_weight.isNaN().select(-std::numeric_limits<double>::infinity(), log_weight);
    const double top = lw.maxCoeff();
    if (std::isfinite(top)) {
      weights = (lw - top).exp();
      weights /= weights.sum();
    } else {
      weights.setConstant(1.0 / n);
    }
    path.push_back(summarise(particles, weights, odometry.utime));
    last_utime = odometry.utime;
  }
  if (path.size() != path_.size()) {
    transitions->clear();
    return {};
  }
  return path;
}

}  // namespace online_em
}  // namespace roam
