// Whether the ranges can see a heading-rate (gyro) bias, from how often they fix the position.
//
// The ranges re-fix the heading about every three position fixes; over that time the bias
// prior turns it by
//   drift_rad = prior_sigma_rad_s x 3 x interval_s,
// interval_s the mean interval between the fixes of the first kRanges ranges. A fix is a range
// time: ranges to several beacons at one time (an AUV's acoustic cycle, a pyfg pose) fix the
// position once, and the heading only changes what the next fix sees after the vehicle has
// moved. Above max_drift_rad the estimators hold the bias at 0 (AUV rates: GOATS 16's first
// ranges 6.17 s apart by fix, 0.185 rad; synthetic AUV runs 3.3 s, 0.099 rad): what they learned
// for it there was outliers and odometry noise, and it rotated the path by tens of metres. At
// UWB rates (Plaza 1, 2 Hz synthetic: <= 0.016 rad; a slow robot ranging every 2 s: 0.06 rad)
// they estimate it (the estimators' threshold: kHeadingRateBiasMaxDrift_rad, 0.08 rad, in
// roam/calibration_priors.hpp). max_drift_rad <= 0: always estimate.
// A rule on the rate alone: a robot with clean ranges fixing its position less often is held as
// well, and says so (heldNote).
#pragma once

#include <cstdint>
#include <set>
#include <string>

namespace roam {
namespace estimation {

class BiasObservability {
 public:
  static constexpr int kRanges = 20;
  enum class Decision { kUndecided, kEstimate, kHold };

  BiasObservability(double prior_sigma_rad_s, double max_drift_rad);
  // The next range's time; returns the decision, made at the kRanges-th range (or the first
  // after it with three fix times) and kept.
  Decision addRange(int64_t utime);
  Decision decision() const { return decision_; }
  // The rule on the ranges so far (at least 3 fix times): a provisional decision.
  bool denseSoFar() const;
  // Estimated, or undecided with the ranges so far dense: what the bias may be used for now.
  bool estimateSoFar() const {
    return decision_ == Decision::kEstimate || (decision_ == Decision::kUndecided && denseSoFar());
  }
  double intervalS() const;
  double driftRad() const { return prior_sigma_rad_s_ * 3.0 * intervalS(); }
  // What a held bias tells the user, naming the threshold's key (and no other, so roam-run's
  // end-of-run note points at it): "held the heading-rate bias at 0: its first 20 ranges fixed
  // the position 3.33 s apart, ...".
  std::string heldNote(const std::string& max_drift_key) const;

 private:
  double prior_sigma_rad_s_, max_drift_rad_;
  Decision decision_;
  int ranges_ = 0;
  std::set<int64_t> fix_utimes_;  // of the ranges up to the decision (its interval, for heldNote)
};

}  // namespace estimation
}  // namespace roam
