// The SDK's self-check: one rule for every estimator, applied by the shim (plugin_shim.hpp) to
// what each estimator publishes, so no plugin keeps a criterion of its own for it.
//
// No usable range: an estimator that accepted no range (none in the input, or every one
// rejected) has nothing but the odometry it was given. Whatever its motion model adds to it (a
// gyro bias read from a standstill, particles' spread, a filter's process noise) is no
// evidence; its answer is dead reckoning, exactly: the start pose composed with every odometry
// step it accepted, by roam's one motion model (roam/se2.hpp). Its path at the end of the run is
// replaced by that, and STATUS says so (the diagnostic kNote). An estimator that refused to
// answer still refuses; one that never had a start pose before its first step is left as it is
// (dead reckoning has no frame then).
#pragma once

#include <cstdint>

#include "roam/estimator.hpp"
#include "roam/types.hpp"

namespace roam {

class SelfCheck {
 public:
  static constexpr const char* kNote =
      "note: used no range (none accepted): the path published is dead reckoning from the start pose";

  // The start pose the estimator was given; the first one before any odometry counts.
  void startPose(const Pose& start);
  // An odometry step the estimator was handed: `accepted` if its accepted count grew.
  void odometry(const Odometry& step, bool accepted);
  // The end of input (the estimator's finish() is called).
  void finished() { finished_ = true; }
  // The path to publish at the end of the run for `estimator`'s own `path` (replaced by dead
  // reckoning under the rule above). True if it was replaced.
  bool apply(const Estimator& estimator, Path* path);
  bool replaced() const { return replaced_; }

 private:
  bool have_start_ = false;
  bool odometry_before_start_ = false;
  Path dead_reckoned_;
  bool finished_ = false;
  bool replaced_ = false;
};

}  // namespace roam
