// The host: feeds input events to every estimator instance and turns their outputs into LCM
// messages for a sink (an output log, the bus, or both).
//
// Odometry and ranges are fed in utime order (odometry first at equal stamps): each is held until
// an input stamped reorder_window_s later has arrived (or the input ends), so a range that reaches
// the log or the bus after odometry stamped later than it (a radio's or a modem's latency) still
// meets its own odometry step. Inputs arriving in that order are fed as they arrive; one that
// arrives later than the window is fed on arrival and counted (InputCounters::late). Replay and
// live mode hold by data time alike, so both feed the same order.
//
// Inputs are decoded and checked here, the same for every estimator: an event that does
// not decode, a message whose utime goes backwards on its channel, or an exact duplicate is
// skipped and counted. Estimators see message utimes only (never the receive time).
//
// A team run ([team] robots): each robot's inputs arrive on <CHANNEL>_<robot> and are fed with
// that robot's index; ranges between robots (ROBOT_RANGE_<robot>) go to team estimators only. An
// instance of a one-robot plugin made for robot r (EstimatorSection::robot) is fed robot r's
// inputs alone, as robot 0, so it runs exactly as on that robot's own log.
#pragma once

#include <algorithm>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "config.hpp"
#include "cpu_histogram.hpp"
#include "plugin_library.hpp"

namespace roam {
namespace runtime {

// Where encoded messages go.
class Sink {
 public:
  virtual ~Sink() = default;
  virtual void write(const std::string& channel, int64_t utime, const void* data, int size) = 0;
};

struct EstimatorSlot {
  EstimatorSection section;
  std::unique_ptr<EstimatorInstance> instance;
  int64_t poses_published = 0;
  int64_t last_status_utime = INT64_MIN;
  int64_t last_trajectory_utime = INT64_MIN;
  bool failure_reported = false;
  // CPU inside the plugin per update: one input message fed to it and the outputs polled after
  // it; and the end of input (finish, last outputs, the final trajectory).
  CpuHistogram odometry_cpu, range_cpu;
  double finish_cpu_s = 0.0;
};

struct InputCounters {
  int64_t events = 0;
  int64_t odometry = 0;
  int64_t ranges = 0;
  int64_t robot_ranges = 0;  // ranges between two robots of a team
  std::map<int, int64_t> ranges_by_robot;  // a team's ranges to beacons, by robot index
  int64_t robot_ranges_unknown = 0;  // ranges naming no other robot of [team] robots (skipped)
  int64_t undecodable = 0;
  int64_t out_of_order = 0;
  int64_t duplicates = 0;
  int64_t odometry_gaps = 0;  // gaps in the odometry clock beyond max_odometry_gap_s
  // Odometry and ranges that arrived after an input stamped later had been fed (beyond
  // reorder_window_s): fed on arrival, out of time order; and how far the latest of them
  // arrived behind the newest input (s, data time).
  int64_t late = 0;
  double late_max_s = 0.0;
  std::map<std::string, int64_t> undecodable_by_channel;
};

class Host {
 public:
  // Outputs go to `output_sink`; each input event is first copied to `input_sink` if not null
  // (replay copies the input events into the result log; live mode leaves them on the bus).
  Host(const RunConfig& config, std::vector<EstimatorSlot> estimators, Sink* output_sink,
       Sink* input_sink);

  // One input event, as read from a log or received from the bus.
  void onEvent(const std::string& channel, int64_t event_utime, const void* data, int size);
  // A warning naming reorder_window_s where inputs arrived later than it; "" if none did.
  std::string lateInputWarning() const;
  // Live mode: ask smoothers for their path if trajectory_interval_s has passed.
  void maybeRequestTrajectories();
  // End of input: finish every estimator, publish final poses, maps, paths and statuses.
  void finish();

  const InputCounters& counters() const { return counters_; }
  const std::vector<EstimatorSlot>& estimators() const { return estimators_; }
  int64_t dataUtime() const { return data_utime_; }
  // The newest data time received, held for reordering or not (live mode's quiet-bus report).
  int64_t receivedUtime() const { return std::max(data_utime_, newest_received_utime_); }
  // Two summary lines per estimator (counts and total CPU; CPU per update), and the input
  // counters.
  std::vector<std::string> summary() const;
  // The second line: CPU per odometry and per range update (median, 99th percentile, max, count)
  // and at the end of input. An update is one message fed to the estimator and its outputs polled.
  static std::string cpuPerUpdateLine(const EstimatorSlot& slot);
  bool anyFailed() const;

 private:
  // One event to the estimators now (what onEvent did before the reordering).
  void dispatch(const std::string& channel, const void* data, int size);
  // Feeds the held inputs stamped at or before `utime`, in (utime, odometry first, arrival) order.
  void releaseHeld(int64_t utime);
  // An input channel: what it carries, and whose (the robot's index; 0 for a robot alone).
  enum class InputKind { kOdometry, kRange, kRobotRange, kInitialPose, kBeacons };
  struct Input {
    InputKind kind;
    int robot = 0;
  };
  const Input* input(const std::string& channel) const;
  // Each returns whether the message reached the estimators (false: skipped and counted).
  bool feedOdometry(const std::string& channel, int robot, const void* data, int size);
  bool feedRange(const std::string& channel, int robot, const void* data, int size);
  bool feedRobotRange(const std::string& channel, int robot, const void* data, int size);
  void feedInitialPose(const std::string& channel, int robot, const void* data, int size);
  void feedBeacons(const std::string& channel, const void* data, int size);
  // Whether `slot` is given robot `robot`'s input, and the robot index it is given as.
  static bool feeds(const EstimatorSlot& slot, int robot, int* as_robot);
  // A team estimator's output channel for one robot: `channel` + "_<robot>"; others: `channel`.
  std::string outputFor(const EstimatorSlot& slot, const std::string& channel, int robot) const;
  // Checks time order and duplicates on a channel; false if the message must be skipped.
  bool acceptInOrder(const std::string& channel, int64_t utime, const void* data, int size);
  void publishOutputs(EstimatorSlot& slot, bool force_status);
  void publishTrajectory(EstimatorSlot& slot, bool force);
  void publishStatus(EstimatorSlot& slot);
  void reportFailure(EstimatorSlot& slot);
  template <typename Message>
  void publish(const std::string& channel, const Message& message);

  RunConfig config_;
  std::vector<EstimatorSlot> estimators_;
  Sink* sink_;
  Sink* input_sink_;
  InputCounters counters_;
  int64_t data_utime_ = 0;
  bool have_data_utime_ = false;
  std::map<std::string, Input> inputs_;  // by channel
  std::map<std::string, int64_t> last_odometry_utime_;  // by channel
  struct ChannelHistory {
    int64_t last_utime = INT64_MIN;
    std::vector<uint8_t> last_payload;
    bool warned = false;
  };
  std::map<std::string, ChannelHistory> history_;
  // Odometry and ranges held for reordering, sorted by (utime, odometry first, arrival); the
  // newest utime received and the newest fed.
  struct Held {
    int64_t utime = 0;
    uint64_t arrival = 0;
    bool odometry = false;
    std::string channel;
    std::vector<uint8_t> data;
  };
  std::deque<Held> held_;
  uint64_t arrivals_ = 0;
  int64_t newest_received_utime_ = INT64_MIN;
  int64_t newest_fed_utime_ = INT64_MIN;
  std::vector<uint8_t> buffer_;
  std::vector<double> cpu_before_;  // per estimator, at the start of an event
  std::vector<char> fed_;           // per estimator: this event's input was given to it
};

}  // namespace runtime
}  // namespace roam

namespace roam {
namespace runtime {
// Discards everything (a replay with no output log).
class NullSink : public Sink {
 public:
  void write(const std::string&, int64_t, const void*, int) override {}
};
}  // namespace runtime
}  // namespace roam
