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

}  // namespace runtime
}  // namespace roam
