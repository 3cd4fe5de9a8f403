#include "host.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <tuple>

#include "roam/estimator_status_t.hpp"
#include "roam/messages.hpp"
#include "roam/safe_decode.hpp"

namespace roam {
namespace runtime {
namespace {
// Seconds from `earlier` to `later` (microseconds), without the signed overflow of
// `later - earlier` when a damaged log holds utimes near the ends of int64.
double secondsBetween(int64_t later, int64_t earlier) {
  return (static_cast<double>(later) - static_cast<double>(earlier)) * 1e-6;
}
}  // namespace

Host::Host(const RunConfig& config, std::vector<EstimatorSlot> estimators, Sink* output_sink,
           Sink* input_sink)
    : config_(config), estimators_(std::move(estimators)), sink_(output_sink),
      input_sink_(input_sink) {
  if (!config_.isTeam()) {
    inputs_[config_.odometry_channel] = {InputKind::kOdometry, 0};
    inputs_[config_.range_channel] = {InputKind::kRange, 0};
    inputs_[config_.initial_pose_channel] = {InputKind::kInitialPose, 0};
  } else {
    for (size_t r = 0; r < config_.team.size(); ++r) {
      const int robot = static_cast<int>(r);
      inputs_[config_.odometry_channel + "_" + config_.team[r]] = {InputKind::kOdometry, robot};
      inputs_[config_.range_channel + "_" + config_.team[r]] = {InputKind::kRange, robot};
      inputs_[std::string(channels::ROBOT_RANGE) + "_" + config_.team[r]] = {InputKind::kRobotRange, robot};
      const auto& starts = config_.team_starts;
      if (std::find(starts.begin(), starts.end(), config_.team[r]) != starts.end())
        inputs_[config_.initial_pose_channel + "_" + config_.team[r]] = {InputKind::kInitialPose, robot};
    }
  }
  inputs_[config_.beacons_channel] = {InputKind::kBeacons, 0};
}

const Host::Input* Host::input(const std::string& channel) const {
  const auto it = inputs_.find(channel);
  return it == inputs_.end() ? nullptr : &it->second;
}

bool Host::feeds(const EstimatorSlot& slot, int robot, int* as_robot) {
  if (slot.section.robot < 0) {
    *as_robot = robot;
    return true;
  }
  *as_robot = 0;
  return slot.section.robot == robot;
}

std::string Host::outputFor(const EstimatorSlot& slot, const std::string& channel, int robot) const {
  if (!config_.isTeam() || slot.section.robot >= 0 || robot < 0 || robot >= static_cast<int>(config_.team.size()))
    return channel;
  return channel + "_" + config_.team[static_cast<size_t>(robot)];
}

template <typename Message>
void Host::publish(const std::string& channel, const Message& message) {
  const int size = message.getEncodedSize();
  buffer_.resize(static_cast<size_t>(size));
  message.encode(buffer_.data(), 0, size);
  sink_->write(channel, data_utime_, buffer_.data(), size);
}

bool Host::acceptInOrder(const std::string& channel, int64_t utime, const void* data, int size) {
  ChannelHistory& history = history_[channel];
  const auto* bytes = static_cast<const uint8_t*>(data);
  if (utime == history.last_utime && history.last_payload.size() == static_cast<size_t>(size) &&
      std::memcmp(history.last_payload.data(), bytes, static_cast<size_t>(size)) == 0) {
    ++counters_.duplicates;
    return false;
  }
  if (utime < history.last_utime) {
    ++counters_.out_of_order;
    if (!history.warned) {
      std::fprintf(stderr, "roam-run: warning: %s: utime went backwards (%lld after %lld); "
                   "such messages are skipped and counted\n", channel.c_str(),
                   static_cast<long long>(utime), static_cast<long long>(history.last_utime));
      history.warned = true;
    }
    return false;
  }
  history.last_utime = utime;
  history.last_payload.assign(bytes, bytes + size);
  if (!have_data_utime_ || utime > data_utime_) data_utime_ = utime;
  have_data_utime_ = true;
  return true;
}

namespace {
template <typename Message>
bool decode(const void* data, int size, Message* message) {
  return decodeMessage(data, size, message) >= 0;  // never throws on damaged bytes
}
}  // namespace

void Host::onEvent(const std::string& channel, int64_t event_utime, const void* data, int size) {
  ++counters_.events;
  if (input_sink_ != nullptr) input_sink_->write(channel, event_utime, data, size);
  const Input* in = input(channel);
  const bool odometry = in != nullptr && in->kind == InputKind::kOdometry;
  if (in == nullptr || (!odometry && in->kind != InputKind::kRange && in->kind != InputKind::kRobotRange)) {
    dispatch(channel, data, size);
    return;
  }
  int64_t utime = 0;
  roam::robot_range_t robot_range;
  const bool decoded = in->kind == InputKind::kRobotRange ? decodeMessage(data, size, &robot_range) >= 0
                                                          : decodeInputUtime(odometry, data, size, &utime);
  if (in->kind == InputKind::kRobotRange) utime = robot_range.utime;
  if (!decoded) {  // counted as undecodable when fed
    dispatch(channel, data, size);
    return;
  }
  newest_received_utime_ = std::max(newest_received_utime_, utime);
  if (utime < newest_fed_utime_) {
    // Later than the window: fed now, out of time order, and counted with how far it arrived
    // behind the newest input (if fed: going back on its own channel too, or a duplicate, it is
    // skipped and counted as such).
    const int64_t fed_before = counters_.odometry + counters_.ranges;
    dispatch(channel, data, size);
    if (counters_.odometry + counters_.ranges > fed_before) {
      ++counters_.late;
      counters_.late_max_s = std::max(counters_.late_max_s, secondsBetween(newest_received_utime_, utime));
    }
    return;
  }
  if (config_.reorder_window_s <= 0.0) {
    dispatch(channel, data, size);
    return;
  }
  Held held;
  held.utime = utime;
  held.arrival = arrivals_++;
  held.odometry = odometry;
  held.channel = channel;
  const auto* bytes = static_cast<const uint8_t*>(data);
  held.data.assign(bytes, bytes + size);
  // At equal stamps odometry first: a step stamped t is the motion up to t, and a range stamped t
  // was measured at its end (as roam-sim, roam-import and Plaza 1's logs order them).
  const auto before = [](const Held& a, const Held& b) {
    return std::make_tuple(a.utime, !a.odometry, a.arrival) < std::make_tuple(b.utime, !b.odometry, b.arrival);
  };
  held_.insert(std::upper_bound(held_.begin(), held_.end(), held, before), std::move(held));
  const auto window_us = static_cast<int64_t>(std::llround(config_.reorder_window_s * 1e6));
  releaseHeld(newest_received_utime_ < INT64_MIN + window_us ? INT64_MIN : newest_received_utime_ - window_us);
}

void Host::releaseHeld(int64_t utime) {
  while (!held_.empty() && held_.front().utime <= utime) {
    const Held held = std::move(held_.front());
    held_.pop_front();
    dispatch(held.channel, held.data.data(), static_cast<int>(held.data.size()));
  }
}

std::string Host::lateInputWarning() const {
  if (counters_.late == 0) return "";
  char text[512];
  std::snprintf(text, sizeof text,
                "warning: %lld odometry and range messages arrived up to %.3f s (data time) behind the newest input, "
                "beyond reorder_window_s (%g s): they were fed on arrival, after inputs stamped later (a range "
                "applied to a later pose); look at key reorder_window_s",
                static_cast<long long>(counters_.late), counters_.late_max_s, config_.reorder_window_s);
  return text;
}

void Host::dispatch(const std::string& channel, const void* data, int size) {
  cpu_before_.resize(estimators_.size());
  fed_.assign(estimators_.size(), 0);
  for (size_t i = 0; i < estimators_.size(); ++i) {
    cpu_before_[i] = estimators_[i].instance->failed() ? -1.0 : estimators_[i].instance->cpuTotalSeconds();
  }
  CpuHistogram EstimatorSlot::*update = nullptr;  // the per-update statistics this event counts in
  const Input* in = input(channel);
  if (in == nullptr) return;  // GROUND_TRUTH and anything else: not for the estimators
  switch (in->kind) {
    case InputKind::kOdometry:
      if (feedOdometry(channel, in->robot, data, size)) update = &EstimatorSlot::odometry_cpu;
      break;
    case InputKind::kRange:
      if (feedRange(channel, in->robot, data, size)) update = &EstimatorSlot::range_cpu;
      break;
    case InputKind::kRobotRange:
      if (feedRobotRange(channel, in->robot, data, size)) update = &EstimatorSlot::range_cpu;
      break;
    case InputKind::kInitialPose:
      feedInitialPose(channel, in->robot, data, size);
      break;
    case InputKind::kBeacons:
      feedBeacons(channel, data, size);
      break;
  }
  for (auto& slot : estimators_) publishOutputs(slot, false);
  if (update == nullptr) return;
  for (size_t i = 0; i < estimators_.size(); ++i) {
    if (cpu_before_[i] < 0.0 || !fed_[i]) continue;  // failed before this event, or another robot's: it got nothing
    (estimators_[i].*update).add(estimators_[i].instance->cpuTotalSeconds() - cpu_before_[i]);
  }
}

bool Host::feedOdometry(const std::string& channel, int robot, const void* data, int size) {
  roam::odometry_t message;
  if (!decode(data, size, &message)) {
    ++counters_.undecodable;
    ++counters_.undecodable_by_channel[channel];
    return false;
  }
  if (!acceptInOrder(channel, message.utime, data, size)) return false;
  ++counters_.odometry;
  auto last = last_odometry_utime_.try_emplace(channel, INT64_MIN).first;
  if (last->second != INT64_MIN && secondsBetween(message.utime, last->second) > config_.max_odometry_gap_s) {
    ++counters_.odometry_gaps;
  }
  last->second = message.utime;
  newest_fed_utime_ = std::max(newest_fed_utime_, message.utime);
  roam_odometry odometry = fromMessage(message);
  for (size_t i = 0; i < estimators_.size(); ++i) {
    if (!feeds(estimators_[i], robot, &odometry.robot)) continue;
    estimators_[i].instance->addOdometry(odometry);
    fed_[i] = 1;
  }
  return true;
}

bool Host::feedRange(const std::string& channel, int robot, const void* data, int size) {
  roam::range_t message;
  if (!decode(data, size, &message)) {
    ++counters_.undecodable;
    ++counters_.undecodable_by_channel[channel];
    return false;
  }
  if (!acceptInOrder(channel, message.utime, data, size)) return false;
  ++counters_.ranges;
  ++counters_.ranges_by_robot[robot];
  newest_fed_utime_ = std::max(newest_fed_utime_, message.utime);
  roam_range range = fromMessage(message);
  for (size_t i = 0; i < estimators_.size(); ++i) {
    if (!feeds(estimators_[i], robot, &range.robot)) continue;
    estimators_[i].instance->addRange(range);
    fed_[i] = 1;
  }
  return true;
}

bool Host::feedRobotRange(const std::string& channel, int robot, const void* data, int size) {
  roam::robot_range_t message;
  if (!decode(data, size, &message)) {
    ++counters_.undecodable;
    ++counters_.undecodable_by_channel[channel];
    return false;
  }
  if (!acceptInOrder(channel, message.utime, data, size)) return false;
  const auto other = std::find(config_.team.begin(), config_.team.end(), message.other_robot);
  if (other == config_.team.end() || other - config_.team.begin() == robot) {
    ++counters_.robot_ranges_unknown;  // names no other member of the team: nobody can use it
    return false;
  }
  ++counters_.robot_ranges;
  newest_fed_utime_ = std::max(newest_fed_utime_, message.utime);
  roam_range range{};
  range.utime = message.utime;
  range.range_m = message.range;
  range.sigma_m = message.sigma;
  range.robot = robot;
  range.to_robot = static_cast<int32_t>(other - config_.team.begin()) + 1;
  for (size_t i = 0; i < estimators_.size(); ++i) {
    if (estimators_[i].section.robot >= 0) continue;  // team estimators only
    estimators_[i].instance->addRange(range);
    fed_[i] = 1;
  }
  return true;
}

void Host::feedInitialPose(const std::string& channel, int robot, const void* data, int size) {
  roam::pose_t message;
  if (!decode(data, size, &message)) {
    ++counters_.undecodable;
    ++counters_.undecodable_by_channel[channel];
    return;
  }
  if (!acceptInOrder(channel, message.utime, data, size)) return;
  roam_pose pose = fromMessage(message);
  for (auto& slot : estimators_) {
    if (feeds(slot, robot, &pose.robot)) slot.instance->setInitialPose(pose);
  }
}

void Host::feedBeacons(const std::string& channel, const void* data, int size) {
  roam::map_t message;
  if (!decode(data, size, &message)) {
    ++counters_.undecodable;
    ++counters_.undecodable_by_channel[channel];
    return;
  }
  if (!acceptInOrder(channel, message.utime, data, size)) return;
  const std::vector<roam_beacon> beacons = fromMessage(message);
  for (auto& slot : estimators_) slot.instance->setBeacons(beacons);
}

void Host::publishOutputs(EstimatorSlot& slot, bool force_status) {
  EstimatorInstance& instance = *slot.instance;
  if (!instance.failed()) {
    std::vector<roam_pose> poses;
    if (instance.pollPoses(&poses)) {
      for (const auto& pose : poses) {
        publish(outputFor(slot, slot.section.pose_channel, pose.robot), toMessage(pose, slot.section.name));
        ++slot.poses_published;
      }
    }
    bool changed = false;
    std::vector<roam_beacon> beacons;
    if (instance.pollMap(&changed, &beacons) && changed) {
      publish(slot.section.map_channel, toMessage(beacons, data_utime_, slot.section.name));
    }
  }
  if (instance.failed() && !slot.failure_reported) {
    reportFailure(slot);
    return;
  }
  const bool due = slot.last_status_utime == INT64_MIN ||
                   secondsBetween(data_utime_, slot.last_status_utime) >=
                       config_.status_interval_s;
  if (force_status || due) publishStatus(slot);
}

void Host::reportFailure(EstimatorSlot& slot) {
  slot.failure_reported = true;
  std::fprintf(stderr, "roam-run: estimator '%s' (plugin %s) failed: %s; it gets no more data\n",
               slot.section.name.c_str(), slot.instance->pluginName().c_str(),
               slot.instance->error().c_str());
  publishStatus(slot);
}

void Host::publishTrajectory(EstimatorSlot& slot, bool force) {
  if (slot.instance->failed()) return;
  bool available = false;
  std::vector<roam_pose> poses;
  if (slot.instance->pollTrajectory(force, &available, &poses) && available) {
    if (!config_.isTeam() || slot.section.robot >= 0) {
      publish(slot.section.trajectory_channel, toMessage(poses, data_utime_, slot.section.name));
    } else {
      // A team estimator's path: one message per robot, each robot's poses in their order.
      std::map<int, std::vector<roam_pose>> by_robot;
      for (const auto& pose : poses) by_robot[pose.robot].push_back(pose);
      for (const auto& [robot, path] : by_robot) {
        publish(outputFor(slot, slot.section.trajectory_channel, robot), toMessage(path, data_utime_, slot.section.name));
      }
    }
    slot.last_trajectory_utime = data_utime_;
  }
  if (slot.instance->failed() && !slot.failure_reported) reportFailure(slot);
}

void Host::publishStatus(EstimatorSlot& slot) {
  EstimatorInstance& instance = *slot.instance;
  const EstimatorInstance::Status status = instance.status();
  roam::estimator_status_t message;
  message.utime = data_utime_;
  message.estimator = slot.section.name;
  message.plugin = instance.pluginName();
  message.state = static_cast<int8_t>(status.state);
  message.odometry_accepted = status.odometry_accepted;
  message.odometry_rejected = status.odometry_rejected;
  message.ranges_accepted = status.ranges_accepted;
  message.ranges_rejected = status.ranges_rejected;
  message.last_rejection = status.last_rejection;
  message.cpu_total_s = instance.cpuTotalSeconds();
  message.cpu_last_update_s = instance.cpuLastSeconds();
  message.last_error = instance.error();
  message.keys = status.keys;
  message.values = status.values;
  // What the host skipped before any estimator saw it, and fed late (the same for every estimator).
  const std::pair<const char*, int64_t> skipped[] = {
      {"input skipped: undecodable", counters_.undecodable},
      {"input skipped: out of order", counters_.out_of_order},
      {"input skipped: duplicates", counters_.duplicates},
      {"input fed late: beyond reorder_window_s", counters_.late}};
  for (const auto& [key, count] : skipped) {
    message.keys.push_back(key);
    message.values.push_back(static_cast<double>(count));
  }
  message.num_values = static_cast<int32_t>(message.keys.size());
  publish(slot.section.status_channel, message);
  slot.last_status_utime = data_utime_;
}

void Host::maybeRequestTrajectories() {
  if (config_.trajectory_interval_s <= 0.0) return;
  for (auto& slot : estimators_) {
    if (slot.last_trajectory_utime == INT64_MIN) slot.last_trajectory_utime = data_utime_;
    if (secondsBetween(data_utime_, slot.last_trajectory_utime) >=
        config_.trajectory_interval_s) {
      publishTrajectory(slot, true);
      slot.last_trajectory_utime = data_utime_;
    }
  }
}

void Host::finish() {
  releaseHeld(INT64_MAX);  // what the reorder window still held
  // Every estimator's end of input is started before any output is read, so estimators on
  // workers or in child processes solve at the same time; outputs are published in order.
  std::vector<double> before_s;
  for (auto& slot : estimators_) {
    before_s.push_back(slot.instance->cpuTotalSeconds());
    if (!slot.instance->failed()) slot.instance->finish();
  }
  // Workers take their queues from the front; this thread takes what no worker has started yet
  // from the back (estimators are given to workers round robin, so one worker's queue may hold
  // several batch solves while the other's is empty). Each job still runs exactly once and the
  // outputs are published in order below, so the log is the same whoever ran what.
  for (size_t i = estimators_.size(); i-- > 0;) estimators_[i].instance->runQueuedHere();
  for (size_t i = 0; i < estimators_.size(); ++i) {
    EstimatorSlot& slot = estimators_[i];
    publishOutputs(slot, false);
    publishTrajectory(slot, true);
    slot.finish_cpu_s = slot.instance->cpuTotalSeconds() - before_s[i];
    publishStatus(slot);
  }
}

bool Host::anyFailed() const {
  for (const auto& slot : estimators_) {
    if (slot.instance->failed()) return true;
  }
  return false;
}

namespace {
// "812 ns", "3.41 us", "12.0 ms", "1.52 s": three significant figures.
std::string duration(double seconds) {
  static const std::pair<double, const char*> units[] = {{1.0, "s"}, {1e-3, "ms"}, {1e-6, "us"}, {1e-9, "ns"}};
  for (const auto& [scale, unit] : units) {
    if (seconds >= scale || scale == 1e-9) {
      const double value = seconds / scale;
      char text[32];
      std::snprintf(text, sizeof text, value >= 100.0 ? "%.0f %s" : value >= 10.0 ? "%.1f %s" : "%.2f %s", value, unit);
      return text;
    }
  }
  return "";
}

std::string updateStats(const char* what, const CpuHistogram& cpu) {
  if (cpu.count() == 0) return std::string(what) + " -";
  return std::string(what) + " median " + duration(cpu.quantile(0.5)) + ", p99 " + duration(cpu.quantile(0.99)) +
         ", max " + duration(cpu.max_s()) + " (" + std::to_string(cpu.count()) + ")";
}
}  // namespace

// "  cpu per update: odometry median 2.10 us, p99 8.40 us, max 31.0 us (9657); range …; finish 0.512 s"
std::string Host::cpuPerUpdateLine(const EstimatorSlot& slot) {
  return "  cpu per update: " + updateStats("odometry", slot.odometry_cpu) + "; " +
         updateStats("range", slot.range_cpu) + "; finish " + duration(slot.finish_cpu_s);
}

std::vector<std::string> Host::summary() const {
  std::vector<std::string> lines;
  char line[512];
  for (const auto& slot : estimators_) {
    const EstimatorInstance::Status status = slot.instance->status();
    const char* state = slot.instance->failed() ? "FAILED" : "ok";
    std::snprintf(line, sizeof(line),
                  "%-22s %-15s %-6s poses %7lld  odometry %lld/%lld rejected  ranges %lld/%lld rejected  cpu %.3f s",
                  slot.section.name.c_str(), slot.instance->pluginName().c_str(), state,
                  static_cast<long long>(slot.poses_published),
                  static_cast<long long>(status.odometry_rejected),
                  static_cast<long long>(status.odometry_accepted + status.odometry_rejected),
                  static_cast<long long>(status.ranges_rejected),
                  static_cast<long long>(status.ranges_accepted + status.ranges_rejected),
                  slot.instance->cpuTotalSeconds());
    std::string text = line;
    if (!status.last_rejection.empty()) text += "  (last rejection: " + status.last_rejection + ")";
    if (slot.instance->failed()) text += "  error: " + slot.instance->error();
    lines.push_back(text);
    lines.push_back(cpuPerUpdateLine(slot));
  }
  std::ostringstream input;
  input << "input: " << counters_.events << " events, " << counters_.odometry << " odometry, "
        << counters_.ranges << " ranges";
  if (config_.isTeam()) input << ", " << counters_.robot_ranges << " ranges between robots";
  if (counters_.robot_ranges_unknown)
    input << ", " << counters_.robot_ranges_unknown << " ranges to a robot not in [team] robots (skipped)";
  if (counters_.undecodable) {
    input << ", " << counters_.undecodable << " undecodable (skipped:";
    for (const auto& [channel, count] : counters_.undecodable_by_channel) {
      input << " " << channel << "=" << count;
    }
    input << ")";
  }
  if (counters_.out_of_order) input << ", " << counters_.out_of_order << " out of order (skipped)";
  if (counters_.duplicates) input << ", " << counters_.duplicates << " duplicates (skipped)";
  if (counters_.odometry_gaps) input << ", " << counters_.odometry_gaps << " gaps in the odometry clock";
  if (counters_.late) input << ", " << counters_.late << " fed late (beyond reorder_window_s)";
  lines.push_back(input.str());
  return lines;
}

}  // namespace runtime
}  // namespace roam
