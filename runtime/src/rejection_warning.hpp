// The end-of-run warning for an estimator that rejected more than a few percent of an input:
// how many, the most frequent reason, and the config key that reason names, so a user whose
// robot is not the one the defaults were chosen for knows where to look.
#pragma once

#include <string>
#include <vector>

#include "estimator_instance.hpp"

namespace roam {
namespace runtime {

// Over this fraction of an input rejected, the run ends with a warning.
constexpr double kRejectionWarningFraction = 0.05;

// One line per input (odometry, ranges) rejected over kRejectionWarningFraction, e.g.
//   warning: ekf rejected 439 of 572 ranges (77 %), most as 'gated: Mahalanobis distance beyond
//   gate_probability' (439): look at key gate_probability
// The reasons come from the status values "rejected <input>: <reason>" the SDK keeps; the key
// is the longest of the estimator's effective config keys that the reason names ("" if none).
// The longest of the config keys that the text names ("" if none).
std::string configKeyNamedIn(const std::string& text, const KeyValues& config);

std::vector<std::string> rejectionWarnings(const std::string& estimator, const EstimatorInstance::Status& status,
                                           const KeyValues& effective_config);

}  // namespace runtime
}  // namespace roam
