// The EKF with surveyed beacons as a bank of translation-noise models: the "ekf" plugin with
// anchor = beacons and translation_noise_models > 1.
//
// Model: K filters (EkfSlam), identical but for the odometry's translation noise, whose sigma is
// f_k times configured, f_k = translation_noise_max_factor^(k / (K - 1)), k = 0 ... K - 1 (1, 2.15,
// 4.64, 10 for the defaults: 2 % to 20 % of the distance). Each sees every input. Each scores
// every range to a beacon in its state by the range's likelihood before its update (the
// prediction-error decomposition of the run's likelihood given f_k, with an outlier mixture:
// EkfSlam::predictiveLogLikelihood), and the model with the highest sum is the one published:
// its poses, map, TRAJECTORY and STATUS, with its factor in STATUS (translation_noise_factor).
// Multiple-model adaptive estimation (Magill 1965; Maybeck, Stochastic Models, Estimation and
// Control, vol. 2, ch. 10) with the model held fixed over the run: the posterior over f given
// the ranges under a flat prior over the grid.
//
// Why: a stated odometry noise is a floor, not the truth. An AUV's dead reckoning drifts by 15-20 %
// of the distance (GOATS 16 states 2 cm per 5 m edge for ~1 m), and a filter told 2 % is
// overconfident: the ranges that should correct it are gated, or bend its heading instead. A
// filter told 20 % on a robot whose odometry is good to 2 % weighs every range too much. The
// ranges say which: a filter whose noise is right predicts them best.
//
// A model whose sum falls translation_noise_drop_nats behind the best is dropped (its memory
// freed); POSE messages already published are not revised when the best model changes.
//
// The heading-rate bias as a second dimension of the bank. Where the ranges are sparse, the rule
// gyro_bias_max_drift_rad holds the bias at 0: on a vehicle whose heading does not drift (an AUV's
// compass) a bias learned from sparse, outlier-heavy ranges takes up noise and can drive the filter
// off (AUV-like runs, surveyed beacons, seeds 2001-2020: 2.17 -> 4.43 m mean with it estimated, worst
// 3.7 x dead reckoning). On a slow UWB robot ranging every 6.7 s with a 0.005 rad/s gyro the same
// rule loses the vehicle (19.7 m, dead reckoning 21.9; estimated: 0.18). So each translation-noise
// model has a twin that estimates the bias at any rate (gyro_bias_max_drift_rad = 0), and the
// ranges choose between them as between the noise models. A twin adds one free quantity, so its
// sum is scored less half the 1-dof chi-square quantile at gate_probability (5.4 nats at 0.999: a
// likelihood-ratio test against the best held model), and twins are dropped as soon as the rule
// decides that the bias is estimated (every run at UWB rates: there the twins would be the same
// filter).
#pragma once

#include <memory>
#include <vector>

#include "ekf_config.hpp"
#include "ekf_slam.hpp"
#include "roam/estimator.hpp"

namespace roam {
namespace ekf {

class EkfBank : public Estimator {
 public:
  explicit EkfBank(const EkfConfig& config);

  // A team run: the configured model alone, as the team filter (EkfSlam::setTeam); no bank.
  void setTeam(const std::vector<std::string>& robots) override;

  void setInitialPose(const Pose& start) override;
  void setBeacons(const Map& surveyed) override;
  void addOdometry(const Odometry& odometry) override;
  void addRange(const Range& range) override;
  void finish() override;
  bool trajectory(bool force, Path* path) override;

  // The translation-noise sigma factor of each model still in the bank (a twin repeats its held
  // model's), and of the best; whether the best is a twin.
  std::vector<double> factors() const;
  double bestFactor() const { return models_[best_].factor; }
  bool bestIsBiasTwin() const { return models_[best_].bias_always; }
  const EkfSlam& best() const { return *models_[best_].filter; }

 private:
  struct Model {
    double factor;
    std::unique_ptr<EkfSlam> filter;
    bool bias_always = false;  // the twin that estimates the heading-rate bias at any rate
  };
  // The model's sum as the bank compares it: a twin pays for its free bias.
  double score(const Model& model) const;
  double twin_penalty_nats_ = 0.0;
  bool hasTwins() const;
  // One input to every model, then follow().
  template <typename Input>
  void toEveryModel(Input input) {
    for (Model& model : models_) input(*model.filter);
    follow();
  }
  // After each input: drop the models too far behind, pick the best, pass its output on.
  void follow();

  EkfConfig config_;
  std::vector<Model> models_;
  size_t best_ = 0;
};

}  // namespace ekf
}  // namespace roam
