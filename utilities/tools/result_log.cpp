#include "result_log.hpp"

#include <sys/stat.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <lcm/lcm-cpp.hpp>
#include <map>
#include <stdexcept>

#include "roam/estimator_status_t.hpp"
#include "roam/estimation/motion_model.hpp"
#include "roam/messages.hpp"
#include "roam/plugin_shim.hpp"
#include "roam/safe_decode.hpp"

namespace roam {
namespace {

bool startsWith(const std::string& text, const char* prefix) { return text.rfind(prefix, 0) == 0; }

template <typename Message>
bool decode(const lcm::LogEvent& event, Message* message) {
  return event.datalen >= 0 && decodeMessage(event.data, event.datalen, message) == event.datalen;
}

// The robot whose suffix "_<R>" ends `suffix` after at least one character, the longest such;
// "" if none.
std::string robotOfSuffix(const std::string& suffix, const std::map<std::string, Path>& robots) {
  std::string best;
  for (const auto& [robot, truth] : robots) {
    const std::string tail = "_" + robot;
    if (suffix.size() > tail.size() && suffix.compare(suffix.size() - tail.size(), tail.size(), tail) == 0 &&
        robot.size() > best.size())
      best = robot;
  }
  return best;
}

// The estimator fields a single channel suffix gathered, regrouped for a team: paths of
// <NAME>_<R> go to NAME's robot R, maps and status stay with their own suffix. A one-robot
// plugin's instance for robot R (roam-run names it NAME_<R>: paths, map and status all on
// <NAME>_<R>) is one robot of NAME: its status counts and CPU add up into NAME's, its
// diagnostics are kept as "<R>: key", and its map is NAME's only where no robot's came before.
struct SuffixNames {
  std::string from_paths, from_team;  // the messages' `estimator` field, by channel kind
};

std::vector<EstimatorOutputs> groupTeam(std::vector<EstimatorOutputs> raw, const std::map<std::string, SuffixNames>& names,
                                        const std::map<std::string, Path>& robots) {
  std::vector<EstimatorOutputs> grouped;
  std::map<std::string, size_t> at;
  auto entry = [&](const std::string& suffix) -> EstimatorOutputs& {
    const auto it = at.emplace(suffix, grouped.size()).first;
    if (it->second == grouped.size()) {
      grouped.emplace_back();
      grouped.back().suffix = grouped.back().name = suffix;
    }
    return grouped[it->second];
  };
  for (EstimatorOutputs& e : raw) {
    const SuffixNames& name = names.at(e.suffix);
    const bool has_path = e.trajectory || !e.poses.empty();
    const bool has_team = e.map || !e.state.empty();
    const std::string robot = robotOfSuffix(e.suffix, robots);
    const std::string robot_tail = "_" + robot;
    const auto endsWithRobot = [&](const std::string& text) {
      return text.size() > robot_tail.size() && text.compare(text.size() - robot_tail.size(), robot_tail.size(), robot_tail) == 0;
    };
    const std::string& instance_name = name.from_paths.empty() ? name.from_team : name.from_paths;
    const bool one_robot_instance = !robot.empty() && endsWithRobot(instance_name);
    if ((has_path || one_robot_instance) && !robot.empty()) {
      EstimatorOutputs& team = entry(e.suffix.substr(0, e.suffix.size() - robot.size() - 1));
      if (!instance_name.empty() && team.name == team.suffix) {
        team.name = one_robot_instance ? instance_name.substr(0, instance_name.size() - robot_tail.size()) : instance_name;
      }
      if (has_path) team.robots[robot] = RobotOutputs{std::move(e.poses), std::move(e.trajectory)};
      if (one_robot_instance) {
        if (e.cpu_total_s) team.cpu_total_s = team.cpu_total_s.value_or(0.0) + *e.cpu_total_s;
        if (team.state.empty() || e.state == "failed") team.state = e.state;
        if (!e.last_error.empty()) team.last_error = robot + ": " + e.last_error;
        team.odometry_accepted += e.odometry_accepted;
        team.odometry_rejected += e.odometry_rejected;
        team.ranges_accepted += e.ranges_accepted;
        team.ranges_rejected += e.ranges_rejected;
        for (const auto& [key, value] : e.diagnostics) team.diagnostics.emplace_back(robot + ": " + key, value);
        if (!team.map && e.map) team.map = std::move(e.map);
        continue;
      }
    }
    if (has_team || (has_path && robot.empty()) || (!has_path && !has_team)) {
      EstimatorOutputs& team = entry(e.suffix);
      if (!name.from_team.empty()) team.name = name.from_team;
      else if (robot.empty() && !name.from_paths.empty()) team.name = name.from_paths;
      if (robot.empty()) {
        team.poses = std::move(e.poses);
        team.trajectory = std::move(e.trajectory);
      }
      team.map = std::move(e.map);
      team.cpu_total_s = e.cpu_total_s;
      team.state = e.state;
      team.last_error = e.last_error;
      team.odometry_accepted = e.odometry_accepted;
      team.odometry_rejected = e.odometry_rejected;
      team.ranges_accepted = e.ranges_accepted;
      team.ranges_rejected = e.ranges_rejected;
      team.diagnostics = std::move(e.diagnostics);
    }
  }
  return grouped;
}

}  // namespace

const char* stateName(int8_t state) {
  switch (state) {
    case roam::estimator_status_t::INITIALIZING: return "initializing";
    case roam::estimator_status_t::TRACKING: return "tracking";
    case roam::estimator_status_t::FINISHED: return "finished";
    case roam::estimator_status_t::FAILED: return "failed";
  }
  return "unknown";
}


const Path* EstimatorOutputs::robotPath(const std::string& robot) const {
  const auto it = robots.find(robot);
  return it == robots.end() ? nullptr : &it->second.scoredPath();
}

std::vector<std::string> ResultLog::robotNames() const {
  std::vector<std::string> names;
  for (const auto& [robot, truth] : team_ground_truth) names.push_back(robot);
  return names;
}

const EstimatorOutputs* ResultLog::find(const std::string& name_or_suffix) const {
  for (const auto& e : estimators) {
    if (e.name == name_or_suffix) return &e;
  }
  const std::string suffix = upperCase(name_or_suffix);
  for (const auto& e : estimators) {
    if (e.suffix == suffix) return &e;
  }
  return nullptr;
}

ResultLog readResultLog(const std::string& path) {
  struct stat info {};
  if (stat(path.c_str(), &info) != 0) {
    throw std::runtime_error(path + ": cannot open (" + std::strerror(errno) + ")");
  }
  if (!S_ISREG(info.st_mode)) throw std::runtime_error(path + ": not a file");
  lcm::LogFile log(path, "r");
  if (!log.good()) throw std::runtime_error(path + ": cannot open as an LCM log");

  ResultLog result;
  result.path = path;
  const std::string team_truth_prefix = teamChannel(channels::GROUND_TRUTH, "");  // "GROUND_TRUTH_"
  std::map<std::string, size_t> index;  // suffix -> estimators[]
  std::map<std::string, SuffixNames> names;  // suffix -> its messages' estimator names
  auto estimator = [&](const std::string& suffix, const std::string& name, bool path_channel = false) -> EstimatorOutputs& {
    auto it = index.find(suffix);
    if (it == index.end()) {
      it = index.emplace(suffix, result.estimators.size()).first;
      result.estimators.push_back(EstimatorOutputs{});
      result.estimators.back().suffix = suffix;
      result.estimators.back().name = suffix;
    }
    EstimatorOutputs& out = result.estimators[it->second];
    if (!name.empty()) {
      out.name = name;
      (path_channel ? names[suffix].from_paths : names[suffix].from_team) = name;
    }
    names[suffix];  // every suffix has an entry
    return out;
  };

  long end_offset = 0;
  bool any = false;
  while (const lcm::LogEvent* event = log.readNextEvent()) {
    any = true;
    ++result.events;
    end_offset = std::ftell(log.getFilePtr());
    const std::string& c = event->channel;
    bool ok = true;
    if (c == channels::GROUND_TRUTH) {
      roam::pose_t m;
      if ((ok = decode(*event, &m))) result.ground_truth.push_back(shim::fromC(fromMessage(m)));
    } else if (c.size() > team_truth_prefix.size() && startsWith(c, team_truth_prefix.c_str())) {
      roam::pose_t m;
      if ((ok = decode(*event, &m)))
        result.team_ground_truth[c.substr(team_truth_prefix.size())].push_back(shim::fromC(fromMessage(m)));
    } else if (c == channels::INITIAL_POSE) {
      roam::pose_t m;
      if ((ok = decode(*event, &m)) && !result.start) result.start = shim::fromC(fromMessage(m));
    } else if (c == channels::BEACONS) {
      roam::map_t m;
      if ((ok = decode(*event, &m))) result.beacons = shim::fromC(fromMessage(m));
    } else if (c == channels::ODOMETRY) {
      roam::odometry_t m;
      if ((ok = decode(*event, &m))) result.odometry.push_back(shim::fromC(fromMessage(m)));
    } else if (c == channels::RANGE) {
      roam::range_t m;
      if ((ok = decode(*event, &m))) result.ranges.push_back(shim::fromC(fromMessage(m)));
    } else if (startsWith(c, channels::POSE_PREFIX)) {
      roam::pose_t m;
      if ((ok = decode(*event, &m)))
        estimator(c.substr(std::strlen(channels::POSE_PREFIX)), m.estimator, true).poses.push_back(shim::fromC(fromMessage(m)));
    } else if (startsWith(c, channels::TRAJECTORY_PREFIX)) {
      roam::trajectory_t m;
      if ((ok = decode(*event, &m))) {
        try {
          estimator(c.substr(std::strlen(channels::TRAJECTORY_PREFIX)), m.estimator, true).trajectory = shim::fromC(fromMessage(m));
        } catch (const std::exception&) {
          ok = false;
        }
      }
    } else if (startsWith(c, channels::MAP_PREFIX)) {
      roam::map_t m;
      if ((ok = decode(*event, &m)))
        estimator(c.substr(std::strlen(channels::MAP_PREFIX)), m.estimator).map = shim::fromC(fromMessage(m));
    } else if (startsWith(c, channels::STATUS_PREFIX)) {
      roam::estimator_status_t m;
      if ((ok = decode(*event, &m))) {
        EstimatorOutputs& out = estimator(c.substr(std::strlen(channels::STATUS_PREFIX)), m.estimator);
        out.cpu_total_s = m.cpu_total_s;
        out.state = stateName(m.state);
        out.last_error = m.last_error;
        out.odometry_accepted = m.odometry_accepted;
        out.odometry_rejected = m.odometry_rejected;
        out.ranges_accepted = m.ranges_accepted;
        out.ranges_rejected = m.ranges_rejected;
        out.diagnostics.clear();
        for (size_t i = 0; i < m.keys.size() && i < m.values.size(); ++i) out.diagnostics.emplace_back(m.keys[i], m.values[i]);
      }
    }
    if (!ok) ++result.skipped;
  }
  // A cut or corrupt tail: the reader stops before the end of the file.
  if (end_offset < static_cast<long>(info.st_size)) {
    if (!any && info.st_size > 0) throw std::runtime_error(path + ": not an LCM log (no event could be read)");
    ++result.skipped;
  }
  if (result.isTeam()) result.estimators = groupTeam(std::move(result.estimators), names, result.team_ground_truth);
  return result;
}

Path integrateOdometry(const Pose& start, const std::vector<Odometry>& odometry) {
  Path path;
  path.reserve(odometry.size() + 1);
  Pose pose = start;
  pose.covariance.fill(kNaN);
  path.push_back(pose);
  for (const Odometry& step : odometry) {
    pose = estimation::step(pose, step);
    path.push_back(pose);
  }
  return path;
}

}  // namespace roam
