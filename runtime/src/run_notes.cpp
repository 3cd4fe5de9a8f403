#include "run_notes.hpp"

#include "rejection_warning.hpp"

namespace roam {
namespace runtime {

std::vector<std::string> runNotes(const std::string& estimator, const EstimatorInstance::Status& status,
                                  const KeyValues& effective_config) {
  static const std::string kPrefix = "note: ";
  std::vector<std::string> lines;
  for (const std::string& name : status.keys) {
    if (name.rfind(kPrefix, 0) != 0) continue;
    const std::string text = name.substr(kPrefix.size());
    const std::string key = configKeyNamedIn(text, effective_config);
    lines.push_back("note: " + estimator + " " + text + (key.empty() ? "" : ": look at key " + key));
  }
  return lines;
}

std::vector<std::string> rangeUseNotes(int64_t input_ranges, const std::string& range_channel,
                                       const std::vector<EstimatorRangeUse>& estimators) {
  std::vector<std::string> lines;
  if (input_ranges == 0) {
    std::string names;
    for (const auto& e : estimators)
      if (e.status.odometry_accepted > 0) names += (names.empty() ? "" : ", ") + e.name;
    if (!names.empty())
      lines.push_back("note: the input has no ranges (channel " + range_channel +
                      "): every estimator ran on odometry alone (" + names + ")");
    return lines;
  }
  for (const auto& e : estimators) {
    if (e.status.ranges_accepted == 0 && e.status.ranges_rejected > 0)
      lines.push_back("note: " + e.name + " rejected every one of its " + std::to_string(e.status.ranges_rejected) +
                      " ranges: it had odometry alone");
  }
  return lines;
}

}  // namespace runtime
}  // namespace roam
