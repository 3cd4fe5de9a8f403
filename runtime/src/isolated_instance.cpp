#include "isolated_instance.hpp"

#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "isolation_protocol.hpp"

namespace roam {
namespace runtime {
namespace {

std::string describeExit(int status) {
  if (WIFSIGNALED(status)) {
    const int signal = WTERMSIG(status);
    const char* abbreviation = sigabbrev_np(signal);
    return "killed by signal " + (abbreviation ? "SIG" + std::string(abbreviation) : std::to_string(signal)) +
           " (" + strsignal(signal) + ")";
  }
  if (WIFEXITED(status)) return "exited with status " + std::to_string(WEXITSTATUS(status));
  return "stopped";
}

std::string utimeText(const char* call, int64_t utime) {
  return std::string(call) + " of the message at utime " + std::to_string(utime);
}

std::string seconds(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g s", value);
  return text;
}

}  // namespace

IsolatedInstance::IsolatedInstance(std::shared_ptr<PluginLibrary> library, std::string name,
                                   const KeyValues& config, IsolationLimits limits)
    : name_(std::move(name)), plugin_name_(library->descriptor().name), limits_(limits) {
  int fds[2];
  if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds) != 0) {
    throw PluginError(std::string("isolation: cannot make a socket pair: ") + std::strerror(errno));
  }
  std::fflush(nullptr);  // the child must not write out roam-run's buffered output again
  pid_ = ::fork();
  if (pid_ < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    throw PluginError(std::string("isolation: cannot start a process: ") + std::strerror(errno));
  }
  if (pid_ == 0) {
    ::close(fds[0]);
    isolation::serveChild(fds[1], library, name_, config, limits_.max_memory_mb);
  }
  ::close(fds[1]);
  fd_ = fds[0];
  alive_ = true;
  const double deadline = limits_.calls.max_update_s > 0.0 ? wire::nowSeconds() + limits_.calls.max_update_s : 0.0;
  const wire::IoResult got = wire::receiveFrame(fd_, &frame_, deadline);
  if (got != wire::IoResult::kOk) {
    if (got == wire::IoResult::kTimedOut) ::kill(pid_, SIGKILL);
    const std::string how = reapAndDescribe(true);
    throw PluginError("the estimator's process was " + how + " while creating the instance");
  }
  wire::Reader in(frame_.data(), frame_.size());
  if (in.pod<uint8_t>() == 0) {
    const std::string key = in.str();
    const std::string message = in.str();
    throw PluginConfigError(key, message);
  }
  const auto keys = in.strs();
  const auto values = in.strs();
  record_.cpu_total_s = in.pod<double>();
  for (size_t i = 0; i < keys.size() && i < values.size(); ++i) effective_.emplace_back(keys[i], values[i]);
}

IsolatedInstance::~IsolatedInstance() {
  if (fd_ >= 0) ::close(fd_);  // the child reads the end of its input and exits
  if (!alive_) return;
  for (int waited_ms = 0; waited_ms < 2000; waited_ms += 10) {
    int status = 0;
    if (::waitpid(pid_, &status, WNOHANG) != 0) return;
    ::usleep(10000);
  }
  ::kill(pid_, SIGKILL);
  ::waitpid(pid_, nullptr, 0);
}

std::string IsolatedInstance::reapAndDescribe(bool wait) {
  alive_ = false;
  int status = 0;
  if (::waitpid(pid_, &status, wait ? 0 : WNOHANG) <= 0) return "lost";
  return describeExit(status);
}

void IsolatedInstance::childGone(const std::string& how) {
  pending_ = false;
  record_.fail("the estimator's process was " + how + " during " + in_flight_);
}

bool IsolatedInstance::send(const std::vector<uint8_t>& request, std::string what) {
  settle();
  if (!alive_) return false;
  in_flight_ = std::move(what);
  if (wire::sendFrame(fd_, request) != wire::IoResult::kOk) {
    childGone(reapAndDescribe(true));
    return false;
  }
  pending_ = true;
  sent_at_s_ = wire::nowSeconds();
  return true;
}

void IsolatedInstance::settle() {
  if (!pending_) return;
  const double limit_s = finishing_ ? limits_.calls.max_finish_s : limits_.calls.max_update_s;
  const wire::IoResult got = wire::receiveFrame(fd_, &frame_, limit_s > 0.0 ? sent_at_s_ + limit_s : 0.0);
  if (got == wire::IoResult::kTimedOut) {
    ::kill(pid_, SIGKILL);
    reapAndDescribe(true);
    pending_ = false;
    record_.fail("no answer within " + std::string(finishing_ ? "max_finish_s" : "max_update_s") + " = " +
               seconds(limit_s) + " during " + in_flight_ + ": its process was ended");
    return;
  }
  if (got == wire::IoResult::kClosed) {
    childGone(reapAndDescribe(true));
    return;
  }
  pending_ = false;
  isolation::Answer answer;
  wire::Reader in(frame_.data(), frame_.size());
  if (!isolation::read(in, &answer)) {
    record_.fail("isolation: a malformed answer to " + in_flight_);
    return;
  }
  record_.cpu_total_s = answer.cpu_total_s;
  record_.cpu_last_s = answer.cpu_last_s;
  record_.wall_last_s = answer.wall_last_s;
  if (answer.polled) {
    poses_.insert(poses_.end(), answer.poses.begin(), answer.poses.end());
    poses_fresh_ = map_fresh_ = true;
    if (answer.map_changed) {
      map_changed_ = true;
      beacons_ = std::move(answer.beacons);
    }
  }
  trajectory_available_ = answer.trajectory_available;
  trajectory_ = std::move(answer.trajectory);
  if (answer.has_status) last_status_ = std::move(answer.status);
  if (answer.failed) record_.fail(answer.error);
}

InstanceRecord& IsolatedInstance::record() {
  settle();
  return record_;
}

bool IsolatedInstance::setTeam(const std::vector<std::string>& robots) {
  if (failed()) return false;
  wire::Writer out;
  out.pod<uint8_t>(isolation::kTeam).strs(robots);
  return send(out.bytes(), "set_team (" + std::to_string(robots.size()) + " robots)");
}

bool IsolatedInstance::setInitialPose(const roam_pose& pose) {
  if (failed()) return false;
  wire::Writer out;
  out.pod<uint8_t>(isolation::kInitialPose).pod(pose);
  return send(out.bytes(), utimeText("set_initial_pose", pose.utime));
}

bool IsolatedInstance::setBeacons(const std::vector<roam_beacon>& beacons) {
  if (failed()) return false;
  wire::Writer out;
  out.pod<uint8_t>(isolation::kBeacons).pods(beacons);
  return send(out.bytes(), "set_beacons (" + std::to_string(beacons.size()) + " beacons)");
}

bool IsolatedInstance::addOdometry(const roam_odometry& odometry) {
  if (failed()) return false;
  wire::Writer out;
  out.pod<uint8_t>(isolation::kOdometry).pod(odometry);
  return send(out.bytes(), utimeText("add_odometry", odometry.utime));
}

bool IsolatedInstance::addRange(const roam_range& range) {
  if (failed()) return false;
  wire::Writer out;
  out.pod<uint8_t>(isolation::kRange).pod(range);
  return send(out.bytes(), utimeText("add_range", range.utime));
}

bool IsolatedInstance::finish() {
  settle();
  finishing_ = true;
  if (record_.failed) return false;
  wire::Writer out;
  out.pod<uint8_t>(isolation::kFinish);
  return send(out.bytes(), "finish");
}

bool IsolatedInstance::pollPoses(std::vector<roam_pose>* poses) {
  poses->clear();
  if (failed()) return false;
  if (!poses_fresh_) {
    wire::Writer out;
    out.pod<uint8_t>(isolation::kPoll);
    send(out.bytes(), "poll_poses");
    if (failed()) return false;
  }
  poses->swap(poses_);
  poses_.clear();
  poses_fresh_ = false;
  return true;
}

bool IsolatedInstance::pollMap(bool* changed, std::vector<roam_beacon>* beacons) {
  beacons->clear();
  *changed = false;
  if (failed()) return false;
  if (!map_fresh_) {
    wire::Writer out;
    out.pod<uint8_t>(isolation::kPoll);
    send(out.bytes(), "poll_map");
    if (failed()) return false;
  }
  if (map_changed_) {
    *changed = true;
    beacons->swap(beacons_);
  }
  map_changed_ = map_fresh_ = false;
  beacons_.clear();
  return true;
}

bool IsolatedInstance::pollTrajectory(bool force, bool* available, std::vector<roam_pose>* poses) {
  poses->clear();
  *available = false;
  if (failed()) return false;
  wire::Writer out;
  out.pod<uint8_t>(isolation::kTrajectory).pod<uint8_t>(force ? 1 : 0);
  send(out.bytes(), "poll_trajectory");
  if (failed()) return false;
  *available = trajectory_available_;
  poses->swap(trajectory_);
  trajectory_.clear();
  return true;
}

EstimatorInstance::Status IsolatedInstance::status() {
  settle();
  if (alive_) {
    wire::Writer out;
    out.pod<uint8_t>(isolation::kStatus);
    send(out.bytes(), "get_status");
    settle();
  }
  Status out = last_status_;
  if (record_.failed) out.state = ROAM_STATE_FAILED;
  return out;
}

}  // namespace runtime
}  // namespace roam
