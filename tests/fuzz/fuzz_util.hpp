// Shared by the fuzz targets: scratch files, the plugin folder, and the targets' own checks.
#pragma once

#include <dlfcn.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace roam {
namespace fuzz {

// A scratch folder of this process (targets run one input at a time, so one folder will do).
inline const std::filesystem::path& scratchDir() {
  static const std::filesystem::path dir = [] {
    const auto path = std::filesystem::temp_directory_path() /
                      ("roam-fuzz-" + std::to_string(static_cast<long>(getpid())));
    std::filesystem::create_directories(path);
    std::atexit([] {
      std::error_code ec;
      std::filesystem::remove_all(std::filesystem::temp_directory_path() /
                                      ("roam-fuzz-" + std::to_string(static_cast<long>(getpid()))),
                                  ec);
    });
    return path;
  }();
  return dir;
}

// Writes `size` bytes to <scratch>/<name> and returns the path.
inline std::string writeScratch(const std::string& name, const uint8_t* data, size_t size) {
  const std::string path = (scratchDir() / name).string();
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path;
}

// The build tree's plugin folder (lib/roam/plugins), or $ROAM_FUZZ_PLUGIN_PATH.
inline std::string pluginDir() {
  const char* from_env = std::getenv("ROAM_FUZZ_PLUGIN_PATH");
  return from_env != nullptr ? from_env : ROAM_BINARY_DIR "/lib/roam/plugins";
}

// Maps every plugin of the plugin folder for good (RTLD_NODELETE), once per process. libFuzzer
// keeps pointers to each module's coverage counters; a plugin unloaded when its last
// PluginLibrary goes (dlclose) would leave them dangling and crash the fuzzer itself.
inline void pinPlugins() {
  static const bool pinned = [] {
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(pluginDir(), ec)) {
      const std::string file = entry.path().filename().string();
      if (file.rfind("libroam_", 0) == 0 && entry.path().extension() == ".so") {
        dlopen(entry.path().c_str(), RTLD_NOW | RTLD_LOCAL | RTLD_NODELETE);
      }
    }
    return true;
  }();
  (void)pinned;
}

// A finding: print what was expected and abort (libFuzzer saves the input).
[[noreturn]] inline void finding(const std::string& what) {
  std::fprintf(stderr, "roam fuzz finding: %s\n", what.c_str());
  std::fflush(stderr);
  std::abort();
}

#define ROAM_FUZZ_CHECK(condition, what)                    \
  do {                                                      \
    if (!(condition)) ::roam::fuzz::finding(what);          \
  } while (0)

}  // namespace fuzz
}  // namespace roam
