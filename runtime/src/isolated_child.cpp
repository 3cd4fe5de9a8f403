// The child process of an isolated estimator: a fork of roam-run that owns one plugin instance.
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <unistd.h>

#include <climits>
#include <cstdio>

#include "isolation_protocol.hpp"

namespace roam {
namespace runtime {
namespace isolation {
namespace {

// Keeps stdin/out/err and the socket; every other descriptor (the output log, the other
// children's sockets) belongs to roam-run, and a child holding another child's socket would
// hide that child's death.
void closeOtherDescriptors(int keep) {
  if (keep > 3) ::close_range(3, static_cast<unsigned>(keep - 1), 0);
  ::close_range(static_cast<unsigned>(keep + 1), UINT_MAX, 0);
}

// The process's virtual size now (the first field of /proc/self/statm, in pages); 0 if unknown.
double addressSpaceBytes() {
  FILE* statm = std::fopen("/proc/self/statm", "r");
  if (statm == nullptr) return 0.0;
  unsigned long pages = 0;
  const int got = std::fscanf(statm, "%lu", &pages);
  std::fclose(statm);
  return got == 1 ? static_cast<double>(pages) * static_cast<double>(::sysconf(_SC_PAGESIZE)) : 0.0;
}

void pollOutputs(PluginInstance& instance, Answer* answer) {
  answer->polled = true;
  if (instance.failed()) return;
  instance.pollPoses(&answer->poses);
  instance.pollMap(&answer->map_changed, &answer->beacons);
}

}  // namespace

void serveChild(int fd, const std::shared_ptr<PluginLibrary>& library, const std::string& name,
                const KeyValues& config, double max_memory_mb) {
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);  // roam-run gone for any reason: so is the child
  ::signal(SIGINT, SIG_IGN);        // Ctrl-C reaches the whole process group: roam-run decides
  ::signal(SIGTERM, SIG_IGN);
  ::signal(SIGPIPE, SIG_IGN);
  closeOtherDescriptors(fd);
  if (max_memory_mb > 0.0) {
    // On top of the address space the child starts with: a copy of roam-run's, with every plugin
    // of the run loaded (Ceres and OpenBLAS reserve hundreds of MB of it), which is not the
    // estimator's doing.
    const rlim_t bytes = static_cast<rlim_t>(addressSpaceBytes() + max_memory_mb * 1024.0 * 1024.0);
    const rlimit limit{bytes, bytes};
    ::setrlimit(RLIMIT_AS, &limit);
  }
  wire::Writer out;
  std::unique_ptr<PluginInstance> instance;
  try {
    instance = std::make_unique<PluginInstance>(library, name, config);
    KeyValues effective = instance->effectiveConfig();
    std::vector<std::string> keys, values;
    for (auto& [key, value] : effective) {
      keys.push_back(key);
      values.push_back(value);
    }
    out.pod<uint8_t>(1).strs(keys).strs(values).pod(instance->cpuTotalSeconds());
  } catch (const PluginConfigError& error) {
    out.pod<uint8_t>(0).str(error.key()).str(error.what());
  } catch (const std::exception& error) {
    out.pod<uint8_t>(0).str("").str(error.what());
  }
  wire::sendFrame(fd, out.bytes());
  if (!instance) ::_exit(0);

  std::vector<uint8_t> request;
  while (wire::receiveFrame(fd, &request, 0.0) == wire::IoResult::kOk) {
    wire::Reader in(request.data(), request.size());
    const auto kind = in.pod<uint8_t>();
    Answer answer;
    switch (kind) {
      case kTeam:
        instance->setTeam(in.strs());
        pollOutputs(*instance, &answer);
        break;
      case kInitialPose:
        instance->setInitialPose(in.pod<roam_pose>());
        pollOutputs(*instance, &answer);
        break;
      case kBeacons:
        instance->setBeacons(in.pods<roam_beacon>());
        pollOutputs(*instance, &answer);
        break;
      case kOdometry:
        instance->addOdometry(in.pod<roam_odometry>());
        pollOutputs(*instance, &answer);
        break;
      case kRange:
        instance->addRange(in.pod<roam_range>());
        pollOutputs(*instance, &answer);
        break;
      case kFinish:
        instance->finish();
        pollOutputs(*instance, &answer);
        break;
      case kPoll:
        pollOutputs(*instance, &answer);
        break;
      case kTrajectory:
        instance->pollTrajectory(in.pod<uint8_t>() != 0, &answer.trajectory_available, &answer.trajectory);
        break;
      case kStatus:
        answer.has_status = true;
        answer.status = instance->status();
        break;
      default:
        instance->markFailed("isolation: unknown request " + std::to_string(kind));
        break;
    }
    answer.failed = instance->failed();
    answer.error = instance->error();
    answer.cpu_total_s = instance->cpuTotalSeconds();
    answer.cpu_last_s = instance->cpuLastSeconds();
    answer.wall_last_s = instance->wallLastSeconds();
    out.clear();
    write(out, answer);
    if (wire::sendFrame(fd, out.bytes()) != wire::IoResult::kOk) break;
  }
  instance.reset();  // the plugin's own destroy, then leave without roam-run's exit handlers
  ::_exit(0);
}

}  // namespace isolation
}  // namespace runtime
}  // namespace roam
