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
  std::map<std::string, size_t> index;  // suffix -> estimators[]
  auto estimator = [&](const std::string& suffix, const std::string& name) -> EstimatorOutputs& {
    auto it = index.find(suffix);
    if (it == index.end()) {
      it = index.emplace(suffix, result.estimators.size()).first;
      result.estimators.push_back(EstimatorOutputs{});
      result.estimators.back().suffix = suffix;
      result.estimators.back().name = suffix;
    }
    EstimatorOutputs& out = result.estimators[it->second];
    if (!name.empty()) out.name = name;
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
        estimator(c.substr(std::strlen(channels::POSE_PREFIX)), m.estimator).poses.push_back(shim::fromC(fromMessage(m)));
    } else if (startsWith(c, channels::TRAJECTORY_PREFIX)) {
      roam::trajectory_t m;
      if ((ok = decode(*event, &m))) {
        try {
          estimator(c.substr(std::strlen(channels::TRAJECTORY_PREFIX)), m.estimator).trajectory = shim::fromC(fromMessage(m));
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
