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
//
// A path the ranges do not support: an estimator that accepted ranges departs from dead
// reckoning to explain them. Its path and dead reckoning are scored on the same ranges
// (roam/range_fit.hpp, mean |range residual|) twice: the path's shape, every beacon placed where
// it fits that path best (kPathFit, kDeadReckoningFit); and, where surveyed beacons were ranged,
// the path against the survey with the range scale and offset that fit best (kPathSurveyFit,
// kDeadReckoningSurveyFit). A path that explains the ranges worse than dead reckoning does by
// either, beyond chance (worseBeyondChance), is supported by no measurement it was given: dead
// reckoning from the start pose is published in its place, with a note giving the figures.
// STATUS carries them either way.
// Ranges outside either path's time span, and those of a beacon ranged fewer than three times
// within it, are not counted; of more than kSelfCheckMaxRanges, every k-th is.
//
// A team's answer (TeamSelfCheck; a team plugin's trajectory, every robot's poses): the same rule,
// judged per robot and between robots. Each robot's path against its own dead reckoning (its
// start pose, the odometry steps the estimator accepted of it) on its ranges to beacons, exactly
// as above (one SelfCheck per robot, its figures keyed "self-check (R): ..."); and the team's
// paths against the robots' dead reckoning on the ranges between robots (robotRangeFit: both
// robots' positions at the range's time, the range scale and offset fitted within the priors),
// the same paired test. Decision: if any of these finds the team's paths worse beyond chance,
// every robot's dead reckoning is published in the team's place (kTeamWorseNote, with the figures
// that failed). The whole team, not the robots concerned: the paths are one answer, solved
// together through the ranges between robots, so one robot's path worse than its odometry is
// evidence against the solve that placed the others; and a mixture of dead reckoning and solved
// paths is an answer no test scored (the ranges between a replaced and a kept robot are explained
// by neither). The tests are several (one per robot, one between robots), so a team no better
// than its dead reckoning is replaced somewhat more often than a robot alone would be; replacing
// an answer no better than dead reckoning by dead reckoning costs little. A team whose paths are
// far better than dead reckoning is not at risk: each test needs its paths worse.
// No usable range, per robot: a robot that has neither a range to a beacon nor a range to or
// from another robot accepted publishes its dead reckoning, exactly (kNoRangeNote names it); the
// others are judged as above. A robot with ranges to other robots only has used ranges. A range
// counts as accepted for its robot (and a range between robots for both) unless the estimator
// rejected it when given it, or accepted no range at all (one that decides later, as the EKF's
// history does, is taken at its word: the residual tests still judge its paths). A robot with no
// start pose has no dead reckoning and is left as it is.
//
// Anchor observability: with anchor = beacons, the surveyed beacons fix the frame only if at
// least three of them, not on one line, were ranged; fewer leave its rotation (one) or its
// reflection (two, or any number on one line) free, and a note says so.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "roam/estimator.hpp"
#include "roam/range_fit.hpp"
#include "roam/types.hpp"

namespace roam {

// Beyond chance: the mean of the paired differences |e_path| - |e_dead_reckoning|, range by range
// in time order, is over kSelfCheckStandardErrors of its standard error, estimated by batch means
// over kSelfCheckBatches consecutive batches (ranges close in time err together, and batch means
// count that; 20 batches is the method's usual number). Two standard errors: a path is replaced
// where its worse fit has about a 2 % chance of being noise.
constexpr size_t kSelfCheckBatches = 20;
constexpr size_t kSelfCheckMaxRanges = 20000;
constexpr double kSelfCheckStandardErrors = 2.0;
bool worseBeyondChance(const std::vector<double>& path_m, const std::vector<double>& dead_reckoning_m);

// "" where `anchor` is not "beacons" or the surveyed beacons ranged fix the frame, else the note.
std::string anchorNote(const std::string& anchor, const Map& surveyed, const std::vector<RangeRecord>& ranges);

class SelfCheck {
 public:
  static constexpr const char* kNote =
      "note: used no range (none accepted): the path published is dead reckoning from the start pose";
  // Prefix of the note of a path replaced because dead reckoning explains the ranges better.
  static constexpr const char* kWorseNote = "note: self-check: its path explained the ranges worse";
  static constexpr const char* kPathFit = "self-check: mean |range residual| of its path (m)";
  static constexpr const char* kDeadReckoningFit = "self-check: mean |range residual| of dead reckoning (m)";
  static constexpr const char* kPathSurveyFit = "self-check: mean |range residual| of its path, surveyed beacons (m)";
  static constexpr const char* kDeadReckoningSurveyFit =
      "self-check: mean |range residual| of dead reckoning, surveyed beacons (m)";
  static constexpr const char* kRangesScored = "self-check: ranges scored";
  static constexpr const char* kAnchorNote = "note: anchor = beacons";

  // The estimator's `anchor` key (effective config), if it has one.
  void anchor(const std::string& value) { anchor_ = value; }
  // Surveyed beacons (BEACONS) the estimator was given.
  void surveyed(const Map& beacons) { surveyed_ = beacons; }
  // A range the SDK's checks passed to the estimator (whether it used it or not).
  void range(const Range& range);

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

  // One robot of a team (TeamSelfCheck): its figures keyed "self-check (NAME): ...", its verdict
  // the team's to act on; it publishes nothing itself.
  void member(const std::string& name) { member_ = name; }
  // The end-of-run decision (once) on `path`, for an estimator that accepted `ranges_accepted`.
  void decide(int64_t ranges_accepted, const Path& path);
  bool usedNoRange() const { return no_range_; }
  bool worse() const { return !why_.empty(); }  // worse than dead reckoning beyond chance
  const std::string& why() const { return why_; }  // the figures that found it worse
  bool hasDeadReckoning() const { return have_start_ && !odometry_before_start_; }
  const Path& deadReckoning() const { return dead_reckoned_; }
  // What the check found, as STATUS diagnostics: the figures above and any note ("note: ..." -> 1).
  const std::vector<std::pair<std::string, double>>& diagnostics() const { return diagnostics_; }

 private:
  bool have_start_ = false;
  bool odometry_before_start_ = false;
  Path dead_reckoned_;
  bool finished_ = false;
  bool replaced_ = false;
  bool decided_ = false;  // the end-of-run checks ran (once)
  bool use_dead_reckoning_ = false;
  bool no_range_ = false;
  std::string why_;
  std::string member_;
  std::string anchor_;
  Map surveyed_;
  std::vector<RangeRecord> ranges_;
  std::vector<std::pair<std::string, double>> diagnostics_;

  std::string key(const char* figure) const;
};

// The self-check of a team plugin's answer (the rule above), fed by the shim as SelfCheck is.
class TeamSelfCheck {
 public:
  static constexpr const char* kTeamWorseNote = "note: self-check: the team's paths explained the ranges worse";
  static constexpr const char* kNoRangeNote = "note: used no range (none accepted): the path published is dead reckoning";
  static constexpr const char* kRobotPathFit = "self-check: mean |range residual| of its paths, ranges between robots (m)";
  static constexpr const char* kRobotDeadReckoningFit =
      "self-check: mean |range residual| of dead reckoning, ranges between robots (m)";
  static constexpr const char* kRobotRangesScored = "self-check: ranges between robots scored";
  // A robot's figure: "self-check: X" -> "self-check (NAME): X".
  static std::string memberKey(const char* figure, const std::string& robot);
  // Fewer ranges between robots than this are not scored: the scale and offset fitted with them
  // explain two exactly from any paths.
  static constexpr size_t kMinRobotRanges = 3;

  void team(const std::vector<std::string>& robots);
  void anchor(const std::string& value) { anchor_ = value; }
  void surveyed(const Map& beacons);
  void startPose(const Pose& start);  // start.robot's
  void odometry(const Odometry& step, bool accepted);
  // A range the SDK's checks passed; `rejected` if the estimator rejected it when given it.
  void range(const Range& range, bool rejected);
  void finished() { finished_ = true; }
  // The team's path to publish (every robot's poses): under the rule above. True if any robot's
  // poses were replaced.
  bool apply(const Estimator& estimator, Path* path);
  const std::vector<std::pair<std::string, double>>& diagnostics() const { return diagnostics_; }

 private:
  std::vector<std::string> robots_;
  std::vector<SelfCheck> members_;
  std::vector<int64_t> usable_ranges_;  // per robot
  std::vector<RobotRangeRecord> robot_ranges_;
  std::vector<RangeRecord> beacon_ranges_;  // every robot's, for the anchor's note
  std::string anchor_;
  Map surveyed_;
  bool finished_ = false;
  bool decided_ = false;
  std::vector<bool> replace_;  // per robot: publish its dead reckoning
  std::vector<std::pair<std::string, double>> diagnostics_;

  void decide(const Estimator& estimator, const Path& path);
};

}  // namespace roam
