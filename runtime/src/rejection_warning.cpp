#include "rejection_warning.hpp"

#include <cmath>
#include <cstdio>

namespace roam {
namespace runtime {
namespace {

std::string warningFor(const std::string& estimator, const char* input, const char* reason_prefix, int64_t rejected,
                       int64_t total, const EstimatorInstance::Status& status, const KeyValues& config) {
  if (total <= 0 || static_cast<double>(rejected) <= kRejectionWarningFraction * static_cast<double>(total)) return "";
  std::string top_reason;
  double top_count = 0.0;
  const std::string prefix = reason_prefix;
  for (size_t i = 0; i < status.keys.size() && i < status.values.size(); ++i) {
    if (status.keys[i].rfind(prefix, 0) == 0 && status.values[i] > top_count) {
      top_count = status.values[i];
      top_reason = status.keys[i].substr(prefix.size());
    }
  }
  const std::string key = configKeyNamedIn(top_reason, config);
  char head[256];
  std::snprintf(head, sizeof head, "warning: %s rejected %lld of %lld %s (%.0f %%)", estimator.c_str(),
                static_cast<long long>(rejected), static_cast<long long>(total), input,
                100.0 * static_cast<double>(rejected) / static_cast<double>(total));
  std::string line = head;
  if (!top_reason.empty()) {
    line += ", most as '" + top_reason + "' (" + std::to_string(std::llround(top_count)) + ")";
  }
  line += key.empty() ? ": the data may not suit this estimator (see its README)" : ": look at key " + key;
  return line;
}

}  // namespace

std::string configKeyNamedIn(const std::string& text, const KeyValues& config) {
  std::string key;
  for (const auto& [name, value] : config) {
    if (name.size() > key.size() && text.find(name) != std::string::npos) key = name;
  }
  return key;
}

std::vector<std::string> rejectionWarnings(const std::string& estimator, const EstimatorInstance::Status& status,
                                           const KeyValues& effective_config) {
  std::vector<std::string> lines;
  const std::string odometry =
      warningFor(estimator, "odometry steps", "rejected odometry: ", status.odometry_rejected,
                 status.odometry_accepted + status.odometry_rejected, status, effective_config);
  const std::string ranges = warningFor(estimator, "ranges", "rejected range: ", status.ranges_rejected,
                                        status.ranges_accepted + status.ranges_rejected, status, effective_config);
  if (!odometry.empty()) lines.push_back(odometry);
  if (!ranges.empty()) lines.push_back(ranges);
  return lines;
}

}  // namespace runtime
}  // namespace roam
