// The C++ side of a plugin: an estimator core fed with plain structs.
//
// A plugin derives from roam::Estimator, overrides the add*() inputs, and reports
// its estimates with emitPose()/emitMap() and its path with trajectory(). The shim in
// plugin_shim.hpp adapts it to the C ABI; tests use the class directly, without a bus.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "roam/types.hpp"

namespace roam {

enum class EstimatorState { kInitializing = 0, kTracking = 1, kFinished = 2, kFailed = 3 };

class Estimator {
 public:
  virtual ~Estimator() = default;

  // A team estimator (a plugin defined with ROAM_DEFINE_TEAM_PLUGIN) is told its robots once,
  // before any input; every input then carries its `robot` (an index into `robots`), a range to
  // another robot its `other_robot`, and each start pose its robot. An estimator of one robot
  // never gets this call (a team run gives each robot an instance of its own).
  virtual void setTeam(const std::vector<std::string>& robots);

  // The known start pose (channel INITIAL_POSE): the anchor of `anchor = start_pose`.
  virtual void setInitialPose(const Pose& /*start*/) {}
  // Surveyed beacon positions (channel BEACONS); used only if the config says so.
  virtual void setBeacons(const Map& /*surveyed*/) {}
  virtual void addOdometry(const Odometry& odometry) = 0;
  virtual void addRange(const Range& range) = 0;
  // End of input: smoothers run their final solve here.
  virtual void finish() { state_ = EstimatorState::kFinished; }

  // The whole path; false if there is none yet. `force` is set at the end of input and on
  // the host's periodic request; an estimator may refuse (false) an expensive path otherwise.
  virtual bool trajectory(bool force, Path* path) {
    (void)force;
    (void)path;
    return false;
  }

  // Poses emitted since the last call, oldest first.
  Path takePoses();
  // The map if it changed since the last call.
  bool takeMap(Map* map);

  EstimatorState state() const { return state_; }
  int64_t odometryAccepted() const { return odometry_accepted_; }
  int64_t odometryRejected() const { return odometry_rejected_; }
  int64_t rangesAccepted() const { return ranges_accepted_; }
  int64_t rangesRejected() const { return ranges_rejected_; }
  const std::string& lastRejection() const { return last_rejection_; }
  // Named rejection counts ("range: not finite" -> 3).
  const std::map<std::string, int64_t>& rejections() const { return rejections_; }
  // Estimator-specific diagnostics (effective sample size, solver cost, ...).
  const std::map<std::string, double>& diagnostics() const { return diagnostics_; }

  // Counts an input that was not used, with the reason (public: the shim's input checks
  // reject non-finite values before the estimator sees them).
  void rejectOdometry(const std::string& reason);
  void rejectRange(const std::string& reason);
  // Counts another input that was not used ("initial pose", "not finite"), by name only: it is
  // neither odometry nor a range.
  void rejectInput(const std::string& input, const std::string& reason);

 protected:
  void emitPose(const Pose& pose) { pending_poses_.push_back(pose); }
  void emitMap(const Map& map) {
    map_ = map;
    map_changed_ = true;
  }
  void acceptOdometry() { ++odometry_accepted_; }
  void acceptRange() { ++ranges_accepted_; }
  void setState(EstimatorState state) { state_ = state; }
  void setDiagnostic(const std::string& key, double value) { diagnostics_[key] = value; }
  // A choice the estimator made about this run that the user should hear at its end (a
  // calibration it held, a mode it fell back to), naming the config key that decides it:
  // carried in STATUS as the diagnostic "note: <text>" (value 1); roam-run prints each note
  // after the run with the key it names.
  void note(const std::string& text) { diagnostics_["note: " + text] = 1.0; }
  // The note of an estimator configured with anchor = beacons whose BEACONS held no beacon (a run
  // with no survey): it placed every beacon from its ranges, so its frame is the start pose's.
  void noteNoSurvey() {
    note("anchor = beacons, but BEACONS held no beacon: every beacon was placed from its ranges, and the "
         "frame is the start pose's");
  }
  // For an estimator that runs others and reports one of them (the EKF's bank of translation-noise
  // models): its state, counts, rejections and diagnostics become `member`'s, plus the inputs this
  // estimator itself was told to reject (the shim's input checks), which no member saw.
  void reportAs(const Estimator& member);

 private:
  EstimatorState state_ = EstimatorState::kInitializing;
  Path pending_poses_;
  Map map_;
  bool map_changed_ = false;
  int64_t odometry_accepted_ = 0;
  int64_t odometry_rejected_ = 0;
  int64_t ranges_accepted_ = 0;
  int64_t ranges_rejected_ = 0;
  std::string last_rejection_;
  std::map<std::string, int64_t> rejections_;
  std::map<std::string, double> diagnostics_;
  // Every reject* call's count (an estimator that reports a member rejects nothing itself, so
  // there these are the shim's input checks): what reportAs keeps on top of the member's.
  struct OutsideRejections {
    int64_t odometry = 0, ranges = 0;
    std::string last;
    std::map<std::string, int64_t> named;
  } outside_;
};

}  // namespace roam
