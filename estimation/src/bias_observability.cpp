#include "roam/estimation/bias_observability.hpp"

#include <cstdio>

namespace roam {
namespace estimation {

BiasObservability::BiasObservability(double prior_sigma_rad_s, double max_drift_rad)
    : prior_sigma_rad_s_(prior_sigma_rad_s),
      max_drift_rad_(max_drift_rad),
      decision_(max_drift_rad > 0.0 ? Decision::kUndecided : Decision::kEstimate) {}

BiasObservability::Decision BiasObservability::addRange(int64_t utime) {
  if (decision_ != Decision::kUndecided) return decision_;
  fix_utimes_.insert(utime);
  if (++ranges_ < kRanges || fix_utimes_.size() < 3) return decision_;
  decision_ = driftRad() <= max_drift_rad_ ? Decision::kEstimate : Decision::kHold;
  return decision_;
}

double BiasObservability::intervalS() const {
  if (fix_utimes_.size() < 2) return 0.0;
  const double span_s = 1e-6 * static_cast<double>(*fix_utimes_.rbegin() - *fix_utimes_.begin());
  return span_s / static_cast<double>(fix_utimes_.size() - 1);
}

bool BiasObservability::denseSoFar() const {
  return fix_utimes_.size() >= 3 && driftRad() <= max_drift_rad_;
}

std::string BiasObservability::heldNote(const std::string& max_drift_key) const {
  char text[512];
  std::snprintf(text, sizeof text,
                "held the heading-rate bias at 0: its first %d ranges fixed the position %.2f s apart, over "
                "three fixes the bias prior turns the heading %.3f rad, more than %s (%.3f); for a drifting gyro with "
                "clean ranges set it to 0",
                ranges_, intervalS(), driftRad(), max_drift_key.c_str(), max_drift_rad_);
  return text;
}

}  // namespace estimation
}  // namespace roam
