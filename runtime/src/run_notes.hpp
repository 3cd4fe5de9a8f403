// The end-of-run notes: choices an estimator made about the run that its user should hear (a
// calibration it held at its prior, a mode it fell back to), each with the config key that
// decides it, so a user whose robot is not the one the defaults were chosen for knows where to
// look even when nothing was rejected.
#pragma once

#include <string>
#include <vector>

#include "estimator_instance.hpp"

namespace roam {
namespace runtime {

// One line per status value "note: <text>" (Estimator::note), in the status' order, e.g.
//   note: ekf held the heading-rate bias at 0 (...more than gyro_bias_max_drift_rad): look at key
//   gyro_bias_max_drift_rad
// The key is the longest of the estimator's effective config keys the text names; a note that
// names none is printed without one.
std::vector<std::string> runNotes(const std::string& estimator, const EstimatorInstance::Status& status,
                                  const KeyValues& effective_config);

// The estimators that had no range to work with, said at the end of every run: with none in the
// input (on `range_channel`), one line naming every estimator that ran on odometry alone; with
// ranges in the input, one line per estimator that took part in ranging (it accepted or
// rejected some) but accepted none. An estimator that
// takes no ranges (dead reckoning: none accepted, none rejected) is not named.
struct EstimatorRangeUse {
  std::string name;
  EstimatorInstance::Status status;
};
std::vector<std::string> rangeUseNotes(int64_t input_ranges, const std::string& range_channel,
                                       const std::vector<EstimatorRangeUse>& estimators);

}  // namespace runtime
}  // namespace roam
