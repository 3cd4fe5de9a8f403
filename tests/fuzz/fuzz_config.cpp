// Fuzz target: roam-run's start-up path on an arbitrary config file.
//
// The bytes are the INI file; if they hold a line "%%", the lines after it are --set overrides.
// As roam-run does: loadConfig, then open each named plugin (from the build's plugin folder,
// whatever plugin_path says) and create its instance from the section's keys.
// Expected: success, or a ConfigError / PluginError / PluginConfigError whose message is one
// line. Anything else (another exception, a crash, a sanitizer report) is a finding.
#include <cstdint>
#include <string>
#include <vector>

#include "config.hpp"
#include "fuzz_util.hpp"
#include "plugin_library.hpp"

using namespace roam::runtime;

namespace {

void checkOneLine(const std::string& message) {
  ROAM_FUZZ_CHECK(!message.empty(), "an empty error message");
  ROAM_FUZZ_CHECK(message.find('\n') == std::string::npos, "a multi-line error message: " + message);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  roam::fuzz::pinPlugins();
  std::string text(reinterpret_cast<const char*>(data), size);
  std::vector<std::string> overrides;
  const auto split = text.find("\n%%\n");
  if (split != std::string::npos) {
    std::string rest = text.substr(split + 4);
    text.resize(split + 1);
    size_t begin = 0;
    while (begin <= rest.size()) {
      const auto end = rest.find('\n', begin);
      overrides.push_back(rest.substr(begin, end == std::string::npos ? std::string::npos : end - begin));
      if (end == std::string::npos) break;
      begin = end + 1;
    }
  }
  const std::string path = roam::fuzz::writeScratch("run.ini", reinterpret_cast<const uint8_t*>(text.data()),
                                                    text.size());
  RunConfig config;
  try {
    config = loadConfig(path, overrides, roam::fuzz::pluginDir());
  } catch (const ConfigError& error) {
    checkOneLine(error.what());
    return 0;
  }
  ROAM_FUZZ_CHECK(!config.input.empty(), "a config without input was accepted");
  ROAM_FUZZ_CHECK(!config.estimators.empty(), "a config without estimators was accepted");
  (void)formatConfig(config);
  for (const auto& section : config.estimators) {
    try {
      auto library = PluginLibrary::open(roam::fuzz::pluginDir(), section.plugin);
      roam::KeyValues values;
      for (const auto& setting : section.plugin_settings) values.emplace_back(setting.key, setting.value);
      PluginInstance instance(library, section.name, values);
      (void)instance.effectiveConfig();
    } catch (const PluginConfigError& error) {
      checkOneLine(error.what());
    } catch (const PluginError& error) {
      checkOneLine(error.what());
    }
  }
  return 0;
}
