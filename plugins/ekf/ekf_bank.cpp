// The EKF with surveyed beacons as a bank of translation-noise models (model: ekf_bank.hpp).
#include "ekf_bank.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>

#include <boost/math/distributions/chi_squared.hpp>

namespace roam {
namespace ekf {

EkfBank::EkfBank(const EkfConfig& config) : config_(config) {
  const int count = config.translation_noise_models;
  if (count < 1) throw std::invalid_argument("translation_noise_models must be at least 1");
  const bool twins = config.gyro_bias_twins && config.estimate_odometry_calibration && config.gyro_bias_max_drift_rad > 0.0;
  for (const bool bias_always : {false, true}) {
    if (bias_always && !twins) break;
    for (int k = 0; k < count; ++k) {
      const double factor = count == 1 ? 1.0 : std::pow(config.translation_noise_max_factor, static_cast<double>(k) / (count - 1));
      EkfConfig member = config;
      member.odo_distance_sigma_rel *= factor;
      member.odo_distance_sigma_m *= factor;
      if (bias_always) member.gyro_bias_max_drift_rad = 0.0;
      models_.push_back({factor, std::make_unique<EkfSlam>(member), bias_always});
    }
  }
  if (twins) twin_penalty_nats_ = 0.5 * boost::math::quantile(boost::math::chi_squared(1.0), config.gate_probability);
}

bool EkfBank::hasTwins() const {
  return std::any_of(models_.begin(), models_.end(), [](const Model& m) { return m.bias_always; });
}

double EkfBank::score(const Model& model) const {
  return model.filter->predictiveLogLikelihood() - (model.bias_always ? twin_penalty_nats_ : 0.0);
}

void EkfBank::setTeam(const std::vector<std::string>& robots) {
  models_.resize(1);  // the first model: factor 1, the bias rule as configured
  best_ = 0;
  toEveryModel([&](EkfSlam& filter) { filter.setTeam(robots); });
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
  // Once the rule estimates the bias, the twins are the held models over again: dropped (unless
  // every held model was dropped first, far behind them).
  const auto original = std::find_if(models_.begin(), models_.end(), [](const Model& m) { return !m.bias_always; });
  if (hasTwins() && original != models_.end() && !original->filter->headingRateBiasUndecided() &&
      !original->filter->headingRateBiasHeld()) {
    if (models_[best_].bias_always) previous = nullptr;  // the published model goes
    std::vector<Model> held;
    for (Model& model : models_)
      if (!model.bias_always) held.push_back(std::move(model));
    models_ = std::move(held);
    best_ = 0;
  }
  // The best: the highest score, the smaller factor on a tie (the configured noise first, the
  // held bias before its twin).
  size_t best = 0;
  for (size_t k = 1; k < models_.size(); ++k)
    if (score(models_[k]) > score(models_[best])) best = k;
  const double best_sum = score(models_[best]);
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
      if (k != best && score(models_[k]) < best_sum - config_.translation_noise_drop_nats) continue;
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
    if (k != best_) runner_up = std::max(runner_up, score(models_[k]));
  setDiagnostic("translation_noise_margin_nats", std::isfinite(runner_up) ? best_sum - runner_up : config_.translation_noise_drop_nats);
  setDiagnostic("heading_rate_bias_models", hasTwins() ? 2.0 : 1.0);
  if (state() == EstimatorState::kFinished && models_[best_].bias_always)
    note("the heading-rate bias estimated at these sparse rates predicts the ranges better than held at 0 "
         "(gyro_bias_max_drift_rad): published with it");
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
