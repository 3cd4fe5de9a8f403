#include "plugin_library.hpp"

#include <dlfcn.h>
#include <pwd.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>

namespace roam {
namespace runtime {
namespace fs = std::filesystem;

namespace {

double threadCpuSeconds() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

std::string ownerName(uid_t uid) {
  const passwd* entry = ::getpwuid(uid);
  return entry != nullptr ? std::string(entry->pw_name) : "uid " + std::to_string(uid);
}

}  // namespace

void PluginLibrary::checkTrusted(const std::string& path, const char* what) {
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) return;  // missing: the caller says so
  const uid_t me = ::getuid();
  if (info.st_uid != me && info.st_uid != 0) {
    throw PluginError(path + ": " + what + " owned by " + ownerName(info.st_uid) +
                      ", not by you or root: whoever owns it can change the code roam-run runs; "
                      "use a plugin folder of your own (or chown it)");
  }
  if ((info.st_mode & (S_IWGRP | S_IWOTH)) != 0) {
    char mode[8];
    std::snprintf(mode, sizeof mode, "%04o", static_cast<unsigned>(info.st_mode & 07777));
    throw PluginError(path + ": " + what + " writable by " +
                      ((info.st_mode & S_IWOTH) ? "others" : "its group") + " (mode " + mode +
                      "): anyone who can write it can change the code roam-run runs; fix with: chmod go-w " +
                      path);
  }
}

std::vector<std::string> PluginLibrary::available(const std::string& folder) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    const std::string file = entry.path().filename().string();
    const std::string prefix = "libroam_", suffix = ".so";
    if (file.size() > prefix.size() + suffix.size() && file.rfind(prefix, 0) == 0 &&
        file.compare(file.size() - suffix.size(), suffix.size(), suffix) == 0) {
      names.push_back(file.substr(prefix.size(), file.size() - prefix.size() - suffix.size()));
    }
  }
  std::sort(names.begin(), names.end());
  return names;
}

std::vector<std::string> PluginLibrary::searchFolders(const std::string& search_path) {
  std::vector<std::string> folders;
  size_t begin = 0;
  while (begin <= search_path.size()) {
    const size_t end = std::min(search_path.find(':', begin), search_path.size());
    if (end > begin) folders.push_back(search_path.substr(begin, end - begin));
    begin = end + 1;
  }
  return folders;
}

std::shared_ptr<PluginLibrary> PluginLibrary::open(const std::string& search_path, const std::string& name) {
  const auto folders = searchFolders(search_path);
  std::string path;
  for (const std::string& folder : folders) {
    checkTrusted(folder, "plugin folder");
    std::error_code not_there;  // e.g. a name too long for the file system: no such plugin either
    const std::string candidate = (fs::path(folder) / ("libroam_" + name + ".so")).string();
    if (fs::exists(candidate, not_there)) {
      path = candidate;
      break;
    }
  }
  if (path.empty()) {
    const std::string folder = search_path;
    std::vector<std::string> names;
    for (const std::string& each : folders) {
      for (const std::string& found : available(each)) names.push_back(found);
    }
    std::sort(names.begin(), names.end());
    names.erase(std::unique(names.begin(), names.end()), names.end());
    std::string message = "no plugin '" + name + "' in " + folder;
    const std::string hint = closestMatch(name, names);
    if (!hint.empty()) {
      message += " (did you mean '" + hint + "'?)";
    } else if (names.empty()) {
      message += " (the folder holds no plugins: is plugin_path right?)";
    } else {
      message += " (available:";
      for (const auto& other : names) message += " " + other;
      message += ")";
    }
    throw PluginError(message);
  }
  auto library = openFile(path);
  if (library->descriptor().name == nullptr || name != library->descriptor().name) {
    throw PluginError(path + ": the plugin calls itself '" +
                      std::string(library->descriptor().name ? library->descriptor().name : "") +
                      "', expected '" + name + "'");
  }
  return library;
}

std::shared_ptr<PluginLibrary> PluginLibrary::openFile(const std::string& path) {
  const fs::path folder = fs::path(path).parent_path();
  checkTrusted(folder.empty() ? "." : folder.string(), "plugin folder");
  checkTrusted(path, "plugin");
  std::shared_ptr<PluginLibrary> library(new PluginLibrary());
  library->path_ = path;
  dlerror();
  library->handle_ = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (library->handle_ == nullptr) {
    const char* why = dlerror();
    throw PluginError(path + ": cannot load: " + (why ? why : "unknown dlopen error"));
  }
  dlerror();
  void* symbol = dlsym(library->handle_, ROAM_PLUGIN_ENTRY_SYMBOL);
  if (symbol == nullptr) {
    throw PluginError(path + ": not a roam plugin: no '" ROAM_PLUGIN_ENTRY_SYMBOL "' symbol");
  }
  auto entry = reinterpret_cast<roam_plugin_entry_fn>(symbol);
  const roam_plugin_descriptor* descriptor = entry();
  if (descriptor == nullptr) throw PluginError(path + ": " ROAM_PLUGIN_ENTRY_SYMBOL "() returned NULL");
  // Check the version and size before reading anything else of the descriptor.
  if (descriptor->abi_version != ROAM_PLUGIN_ABI_VERSION) {
    throw PluginError(path + ": plugin ABI version " + std::to_string(descriptor->abi_version) +
                      ", but this roam-run speaks version " +
                      std::to_string(ROAM_PLUGIN_ABI_VERSION) + ": rebuild the plugin");
  }
  if (descriptor->descriptor_size != sizeof(roam_plugin_descriptor)) {
    throw PluginError(path + ": plugin descriptor is " + std::to_string(descriptor->descriptor_size) +
                      " bytes, expected " + std::to_string(sizeof(roam_plugin_descriptor)) +
                      ": rebuild the plugin against this roam");
  }
  const roam_struct_layout expected[ROAM_ABI_NUM_STRUCTS] = ROAM_ABI_LAYOUTS;
  const char* const names[ROAM_ABI_NUM_STRUCTS] = ROAM_ABI_STRUCT_NAMES;
  for (int i = 0; i < ROAM_ABI_NUM_STRUCTS; ++i) {
    const roam_struct_layout& got = descriptor->layouts[i];
    if (got.size != expected[i].size || got.align != expected[i].align) {
      throw PluginError(path + ": the plugin's " + names[i] + " is " + std::to_string(got.size) +
                        " bytes aligned to " + std::to_string(got.align) + ", this roam-run's is " +
                        std::to_string(expected[i].size) + " aligned to " +
                        std::to_string(expected[i].align) +
                        ": rebuild the plugin against this roam's plugin_abi.h");
    }
  }
  const void* functions[] = {
      reinterpret_cast<const void*>(descriptor->create),
      reinterpret_cast<const void*>(descriptor->destroy),
      reinterpret_cast<const void*>(descriptor->describe_config),
      reinterpret_cast<const void*>(descriptor->set_initial_pose),
      reinterpret_cast<const void*>(descriptor->set_beacons),
      reinterpret_cast<const void*>(descriptor->add_odometry),
      reinterpret_cast<const void*>(descriptor->add_range),
      reinterpret_cast<const void*>(descriptor->finish),
      reinterpret_cast<const void*>(descriptor->poll_poses),
      reinterpret_cast<const void*>(descriptor->poll_map),
      reinterpret_cast<const void*>(descriptor->poll_trajectory),
      reinterpret_cast<const void*>(descriptor->get_status),
      reinterpret_cast<const void*>(descriptor->last_error)};
  for (const void* function : functions) {
    if (function == nullptr) throw PluginError(path + ": plugin descriptor has a NULL function");
  }
  if (descriptor->name == nullptr) throw PluginError(path + ": plugin descriptor has no name");
  library->descriptor_ = descriptor;
  return library;
}

PluginLibrary::~PluginLibrary() {
  if (handle_ != nullptr) dlclose(handle_);
}

PluginInstance::PluginInstance(std::shared_ptr<PluginLibrary> library, std::string name,
                               const KeyValues& config, CallLimits limits)
    : library_(std::move(library)), d_(&library_->descriptor()), name_(std::move(name)),
      plugin_name_(d_->name), limits_(limits) {
  std::vector<roam_kv> kvs;
  for (const auto& [key, value] : config) kvs.push_back(roam_kv{key.c_str(), value.c_str()});
  roam_error error{};
  const double start = threadCpuSeconds();
  handle_ = d_->create(kvs.data(), static_cast<int32_t>(kvs.size()), &error);
  record_.cpu_total_s += threadCpuSeconds() - start;
  if (handle_ == nullptr) {
    error.key[sizeof(error.key) - 1] = '\0';
    error.message[sizeof(error.message) - 1] = '\0';
    throw PluginConfigError(error.key, error.message[0] ? error.message : "create failed (no message)");
  }
}

PluginInstance::~PluginInstance() {
  if (handle_ != nullptr) d_->destroy(handle_);
}

template <typename Call>
bool PluginInstance::call(const char* what, Call&& body) {
  if (record_.failed) return false;
  const auto wall_start = std::chrono::steady_clock::now();
  const double start = threadCpuSeconds();
  const int rc = body();
  record_.cpu_last_s = threadCpuSeconds() - start;
  record_.cpu_total_s += record_.cpu_last_s;
  // An update is an input call and the polls after it: polls add to the input's wall time.
  const bool is_poll = std::string(what).rfind("poll_", 0) == 0;
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  record_.wall_last_s = is_poll ? record_.wall_last_s + wall_s : wall_s;
  if (rc != ROAM_OK) {
    const char* message = d_->last_error(handle_);
    record_.fail(std::string(what) + ": " + (message && message[0] ? message : "error with no message"));
    return false;
  }
  const double limit_s = finishing_ ? limits_.max_finish_s : limits_.max_update_s;
  if (limit_s > 0.0 && record_.wall_last_s > limit_s) {
    char text[160];
    std::snprintf(text, sizeof text, "%s: took %.3g s, over %s = %g s", what, record_.wall_last_s,
                  finishing_ ? "max_finish_s" : "max_update_s", limit_s);
    record_.fail(text);
    return false;
  }
  return true;
}

KeyValues PluginInstance::effectiveConfig() {
  KeyValues out;
  const roam_kv* kvs = nullptr;
  int32_t n = 0;
  if (d_->describe_config(handle_, &kvs, &n) == ROAM_OK) {
    for (int32_t i = 0; i < n; ++i) out.emplace_back(kvs[i].key, kvs[i].value);
  }
  return out;
}

bool PluginInstance::setTeam(const std::vector<std::string>& robots) {
  return call("set_team", [&] {
    if (d_->set_team == nullptr) {
      record_.fail("set_team: plugin " + plugin_name_ + " estimates one robot, not a team");
      return ROAM_OK;
    }
    std::vector<const char*> names;
    for (const auto& robot : robots) names.push_back(robot.c_str());
    return d_->set_team(handle_, names.data(), static_cast<int32_t>(names.size()));
  });
}

bool PluginInstance::setInitialPose(const roam_pose& pose) {
  return call("set_initial_pose", [&] { return d_->set_initial_pose(handle_, &pose); });
}

bool PluginInstance::setBeacons(const std::vector<roam_beacon>& beacons) {
  return call("set_beacons", [&] {
    return d_->set_beacons(handle_, beacons.data(), static_cast<int32_t>(beacons.size()));
  });
}

bool PluginInstance::addOdometry(const roam_odometry& odometry) {
  return call("add_odometry", [&] { return d_->add_odometry(handle_, &odometry); });
}

bool PluginInstance::addRange(const roam_range& range) {
  return call("add_range", [&] { return d_->add_range(handle_, &range); });
}

bool PluginInstance::finish() {
  finishing_ = true;
  return call("finish", [&] { return d_->finish(handle_); });
}

bool PluginInstance::pollPoses(std::vector<roam_pose>* poses) {
  poses->clear();
  return call("poll_poses", [&] {
    const roam_pose* data = nullptr;
    int32_t n = 0;
    const int rc = d_->poll_poses(handle_, &data, &n);
    if (rc == ROAM_OK && n > 0) poses->assign(data, data + n);
    return rc;
  });
}

bool PluginInstance::pollMap(bool* changed, std::vector<roam_beacon>* beacons) {
  beacons->clear();
  *changed = false;
  return call("poll_map", [&] {
    const roam_beacon* data = nullptr;
    int32_t n = 0, flag = 0;
    const int rc = d_->poll_map(handle_, &flag, &data, &n);
    if (rc == ROAM_OK && flag) {
      *changed = true;
      if (n > 0) beacons->assign(data, data + n);
    }
    return rc;
  });
}

bool PluginInstance::pollTrajectory(bool force, bool* available, std::vector<roam_pose>* poses) {
  poses->clear();
  *available = false;
  return call("poll_trajectory", [&] {
    const roam_pose* data = nullptr;
    int32_t n = 0, flag = 0;
    const int rc = d_->poll_trajectory(handle_, force ? 1 : 0, &flag, &data, &n);
    if (rc == ROAM_OK && flag) {
      *available = true;
      if (n > 0) poses->assign(data, data + n);
    }
    return rc;
  });
}

PluginInstance::Status PluginInstance::status() {
  Status out;
  roam_status status{};
  if (d_->get_status(handle_, &status) == ROAM_OK) {
    out.state = status.state;
    out.odometry_accepted = status.odometry_accepted;
    out.odometry_rejected = status.odometry_rejected;
    out.ranges_accepted = status.ranges_accepted;
    out.ranges_rejected = status.ranges_rejected;
    out.last_rejection = status.last_rejection ? status.last_rejection : "";
    for (int32_t i = 0; i < status.num_values; ++i) {
      out.keys.push_back(status.keys[i] ? status.keys[i] : "");
      out.values.push_back(status.values[i]);
    }
  }
  if (record_.failed) out.state = ROAM_STATE_FAILED;
  return out;
}

}  // namespace runtime
}  // namespace roam
