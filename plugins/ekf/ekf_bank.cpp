// The EKF with surveyed beacons as a bank of translation-noise models (model: ekf_bank.hpp).
#include "ekf_bank.hpp"

#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace roam {
namespace ekf {

EkfBank::EkfBank(const EkfConfig& config) : config_(config) {
  const int count = config.translation_noise_models;
  if (count < 1) throw std::invalid_argument("translation_noise_models must be at least 1");
  for (int k = 0; k < count; ++k) {
    const double factor = count == 1 ? 1.0 : std::pow(config.translation_noise_max_factor, static_cast<double>(k) / (count - 1));
    EkfConfig member = config;
    member.odo_distance_sigma_rel *= factor;
    member.odo_distance_sigma_m *= factor;
    models_.push_back({factor, std::make_unique<EkfSlam>(member)});
  }
}

void EkfBank::setInitialPose(const Pose& start) {
  toEveryModel([&](EkfSlam& filter) { filter.setInitialPose(start); });
}

void EkfBank::setBeacons(const Map& surveyed) {
  toEveryModel([&](EkfSlam& filter) { filter.setBeacons(surveyed); });
}

void EkfBank::addOdometry(const Odometry& odometry) {
  toEveryModel([&](EkfSlam& filter) { filter.addOdometry(odometry); });
}

void EkfBank::addRange(const Range& range) {
  toEveryModel([&](EkfSlam& filter) { filter.addRange(range); });
}

void EkfBank::finish() {
  toEveryModel([](EkfSlam& filter) { filter.finish(); });
}

bool EkfBank::trajectory(bool force, Path* path) { return models_[best_].filter->trajectory(force, path); }

std::vector<double> EkfBank::factors() const {
  std::vector<double> out;
  for (const Model& model : models_) out.push_back(model.factor);
  return out;
}

void EkfBank::follow() {
  const EkfSlam* previous = models_[best_].filter.get();
  // The best: the highest sum, the smaller factor on a tie (the configured noise first).
  size_t best = 0;
  for (size_t k = 1; k < models_.size(); ++k)
    if (models_[k].filter->predictiveLogLikelihood() > models_[best].filter->predictiveLogLikelihood()) best = k;
  const double best_sum = models_[best].filter->predictiveLogLikelihood();
  // Pass the best model's poses and map on; the others' are drained (and dropped).
  Map map;
  for (size_t k = 0; k < models_.size(); ++k) {
    Path poses = models_[k].filter->takePoses();
    const bool changed = models_[k].filter->takeMap(&map);
    if (k != best) continue;
    for (const Pose& pose : poses) emitPose(pose);
    if (changed) emitMap(map);
  }
  if (models_[best].filter.get() != previous && models_[best].filter->started()) emitMap(models_[best].filter->currentMap());
  if (config_.translation_noise_drop_nats > 0.0) {
    std::vector<Model> kept;
    size_t kept_best = 0;
    for (size_t k = 0; k < models_.size(); ++k) {
      if (k != best && models_[k].filter->predictiveLogLikelihood() < best_sum - config_.translation_noise_drop_nats) continue;
      if (k == best) kept_best = kept.size();
      kept.push_back(std::move(models_[k]));
    }
    models_ = std::move(kept);
    best = kept_best;
  }
  best_ = best;
  const EkfSlam& chosen = *models_[best_].filter;
  reportAs(chosen);
  setDiagnostic("translation_noise_factor", models_[best_].factor);
  setDiagnostic("translation_noise_models", static_cast<double>(models_.size()));
  double runner_up = -std::numeric_limits<double>::infinity();
  for (size_t k = 0; k < models_.size(); ++k)
    if (k != best_) runner_up = std::max(runner_up, models_[k].filter->predictiveLogLikelihood());
  setDiagnostic("translation_noise_margin_nats", std::isfinite(runner_up) ? best_sum - runner_up : config_.translation_noise_drop_nats);
  if (state() == EstimatorState::kFinished && models_[best_].factor > 1.0) {
    std::ostringstream text;
    text << std::setprecision(3) << "the odometry's translation noise that predicts the ranges best is " << models_[best_].factor
         << " x configured (" << 100.0 * config_.odo_distance_sigma_rel * models_[best_].factor
         << " % of the distance, configured " << 100.0 * config_.odo_distance_sigma_rel
         << " %, odo_distance_sigma_rel); published with it";
    note(text.str());
  }
}

}  // namespace ekf
}  // namespace roam
