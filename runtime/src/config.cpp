#include "config.hpp"

#include "plugin_library.hpp"

#include <boost/program_options.hpp>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>

namespace roam {
namespace runtime {
namespace po = boost::program_options;
namespace fs = std::filesystem;

namespace {

const std::vector<std::string> kRuntimeKeys = {
    "input", "output", "plugin_path", "odometry_channel", "range_channel",
    "initial_pose_channel", "beacons_channel", "ground_truth_channel",
    "trajectory_interval_s", "status_interval_s", "max_odometry_gap_s", "isolation",
    "max_update_s", "max_finish_s", "idle_warning_s", "threads"};
const std::vector<std::string> kEstimatorRuntimeKeys = {
    "plugin", "pose_channel", "map_channel", "trajectory_channel", "status_channel",
    "isolation", "max_update_s", "max_finish_s", "max_memory_mb"};

std::string trim(const std::string& text) {
  const auto begin = text.find_first_not_of(" \t\r\n");
  if (begin == std::string::npos) return "";
  const auto end = text.find_last_not_of(" \t\r\n");
  return text.substr(begin, end - begin + 1);
}

std::string upper(std::string text) {
  for (char& c : text) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return text;
}

[[noreturn]] void fail(const Origin& origin, const std::string& section, const std::string& key,
                       const std::string& message) {
  std::string text = origin.describe();
  if (!section.empty()) text += " [" + section + "]";
  if (!key.empty()) text += " " + key;
  throw ConfigError(text + ": " + message);
}

// Line numbers of sections and keys, from a scan alongside Boost's parse (which has none).
struct LineIndex {
  std::map<std::string, int> section_lines;  // "estimator.a" -> line
  std::map<std::string, int> key_lines;      // "estimator.a.rank" -> first line
};

LineIndex indexLines(const std::string& file, std::istream& in) {
  LineIndex index;
  std::string line, section;
  int number = 0;
  std::map<std::string, int> seen;
  while (std::getline(in, line)) {
    ++number;
    const std::string text = trim(line.substr(0, line.find('#')));
    if (text.empty()) continue;
    Origin origin{file, number, ""};
    if (text.front() == '[') {
      if (text.back() != ']') fail(origin, "", "", "expected a section header like [runtime]");
      section = trim(text.substr(1, text.size() - 2));
      if (section.empty()) fail(origin, "", "", "empty section name");
      if (index.section_lines.count(section)) {
        fail(origin, section, "",
             "section repeated (first at line " + std::to_string(index.section_lines[section]) + ")");
      }
      index.section_lines[section] = number;
      continue;
    }
    const auto equals = text.find('=');
    if (equals == std::string::npos) fail(origin, section, "", "expected 'key = value', got '" + text + "'");
    const std::string key = trim(text.substr(0, equals));
    if (key.empty()) fail(origin, section, "", "missing key before '='");
    if (section.empty()) fail(origin, "", key, "key outside any section (put it under [runtime])");
    const std::string full = section + "." + key;
    if (index.key_lines.count(full)) {
      fail(origin, section, key,
           "key repeated (first at line " + std::to_string(index.key_lines[full]) + ")");
    }
    index.key_lines[full] = number;
  }
  return index;
}

std::string resolvePath(const std::string& value, const fs::path& base) {
  if (value.empty() || value.find("://") != std::string::npos) return value;
  fs::path path(value);
  if (path.is_absolute()) return path.lexically_normal().string();
  return (base / path).lexically_normal().string();
}

double parseNumber(const Setting& setting, const std::string& section, double min_value) {
  try {
    size_t used = 0;
    const double value = std::stod(setting.value, &used);
    if (used == setting.value.size() && std::isfinite(value) && value >= min_value) return value;
  } catch (const std::exception&) {
  }
  std::ostringstream expected;
  expected << "expected a number >= " << min_value << ", got '" << setting.value << "'";
  fail(setting.origin, section, setting.key, expected.str());
}

bool parseIsolation(const Setting& setting, const std::string& section) {
  if (setting.value == "process") return true;
  if (setting.value == "none") return false;
  fail(setting.origin, section, setting.key, "expected one of none | process, got '" + setting.value + "'");
}

bool validName(const std::string& name) {
  if (name.empty()) return false;
  for (char c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-') return false;
  }
  return true;
}

}  // namespace

std::string Origin::describe() const {
  if (!override_text.empty()) return override_text;
  if (line > 0) return file + ":" + std::to_string(line);
  return file.empty() ? "(default)" : file;
}

Origin EstimatorSection::originOf(const std::string& key) const {
  for (const auto& setting : plugin_settings) {
    if (setting.key == key) return setting.origin;
  }
  return section_origin;
}

RunConfig loadConfig(const std::string& path, const std::vector<std::string>& overrides,
                     const std::string& default_plugin_path) {
  RunConfig config;
  config.config_file = path;
  std::ifstream file(path);
  if (!file) throw ConfigError(path + ": cannot open the config file");
  const LineIndex index = indexLines(path, file);
  file.clear();
  file.seekg(0);

  // Boost.Program_options does the INI parsing; every key is taken as a string here and
  // validated below, where its line is known.
  po::options_description none;
  po::parsed_options parsed(&none);
  try {
    parsed = po::parse_config_file(file, none, /*allow_unregistered=*/true);
  } catch (const po::error& error) {
    throw ConfigError(path + ": " + error.what());
  }

  // section -> ordered settings
  std::vector<std::string> section_order;
  std::map<std::string, std::vector<Setting>> sections;
  auto addSetting = [&](const std::string& full_key, const std::string& value, const Origin& origin) {
    const auto dot = full_key.rfind('.');
    if (dot == std::string::npos || dot == 0) {
      fail(origin, "", full_key, "expected section.key");
    }
    const std::string section = full_key.substr(0, dot);
    const std::string key = full_key.substr(dot + 1);
    if (!sections.count(section)) section_order.push_back(section);
    auto& settings = sections[section];
    for (auto& setting : settings) {
      if (setting.key == key) {
        setting.value = value;
        setting.origin = origin;
        return;
      }
    }
    settings.push_back(Setting{key, value, origin});
  };
  for (const auto& option : parsed.options) {
    const std::string value = option.value.empty() ? "" : trim(option.value.front());
    const auto line = index.key_lines.find(option.string_key);
    addSetting(option.string_key, value,
               Origin{path, line == index.key_lines.end() ? 0 : line->second, ""});
  }
  // Sections with no keys still count (an empty [estimator.x] must be reported).
  for (const auto& [section, line] : index.section_lines) {
    if (!sections.count(section)) {
      section_order.push_back(section);
      sections[section];
    }
  }
  for (const auto& text : overrides) {
    const auto equals = text.find('=');
    const Origin origin{"", 0, "--set " + text};
    if (equals == std::string::npos) fail(origin, "", "", "expected section.key=value");
    addSetting(trim(text.substr(0, equals)), trim(text.substr(equals + 1)), origin);
  }

  const fs::path base = fs::absolute(fs::path(path)).parent_path();
  auto sectionOrigin = [&](const std::string& section) {
    const auto it = index.section_lines.find(section);
    return Origin{path, it == index.section_lines.end() ? 0 : it->second, ""};
  };

  bool have_input = false;
  bool threads_given = false;
  config.plugin_path = default_plugin_path;
  // Per-estimator fault settings given in their sections; [runtime] supplies the rest below.
  struct FaultSettings {
    std::optional<bool> isolated;
    std::optional<double> max_update_s, max_finish_s;
    const Setting* memory = nullptr;
  };
  std::vector<FaultSettings> fault_settings;
  for (const auto& section : section_order) {
    const auto& settings = sections[section];
    if (section == "runtime") {
      config.runtime_settings = settings;
      for (const auto& setting : settings) {
        const std::string& key = setting.key;
        if (key == "input") {
          config.input = resolvePath(setting.value, base);
          have_input = !setting.value.empty();
        } else if (key == "output") {
          config.output = resolvePath(setting.value, base);
        } else if (key == "plugin_path") {
          // ':'-separated folders searched in order; the shipped folder is always searched last.
          std::string list;
          for (const std::string& folder : PluginLibrary::searchFolders(setting.value)) {
            const std::string resolved = resolvePath(folder, base);
            if (resolved != default_plugin_path) list += resolved + ":";
          }
          config.plugin_path = list + default_plugin_path;
        } else if (key == "odometry_channel") {
          config.odometry_channel = setting.value;
        } else if (key == "range_channel") {
          config.range_channel = setting.value;
        } else if (key == "initial_pose_channel") {
          config.initial_pose_channel = setting.value;
        } else if (key == "beacons_channel") {
          config.beacons_channel = setting.value;
        } else if (key == "ground_truth_channel") {
          config.ground_truth_channel = setting.value;
        } else if (key == "trajectory_interval_s") {
          config.trajectory_interval_s = parseNumber(setting, section, 0.0);
        } else if (key == "status_interval_s") {
          config.status_interval_s = parseNumber(setting, section, 0.0);
        } else if (key == "max_odometry_gap_s") {
          config.max_odometry_gap_s = parseNumber(setting, section, 0.0);
        } else if (key == "isolation") {
          config.isolated = parseIsolation(setting, section);
        } else if (key == "max_update_s") {
          config.max_update_s = parseNumber(setting, section, 0.0);
        } else if (key == "max_finish_s") {
          config.max_finish_s = parseNumber(setting, section, 0.0);
        } else if (key == "idle_warning_s") {
          config.idle_warning_s = parseNumber(setting, section, 0.0);
        } else if (key == "threads") {
          const double threads = parseNumber(setting, section, 1.0);
          if (threads != std::floor(threads) || threads > 1024) {
            fail(setting.origin, section, key, "expected a whole number of threads, 1 to 1024, got '" + setting.value + "'");
          }
          config.threads = static_cast<int>(threads);
          threads_given = true;
        } else {
          std::string message = "unknown key";
          const std::string hint = closestMatch(key, kRuntimeKeys);
          if (!hint.empty()) message += " (did you mean '" + hint + "'?)";
          fail(setting.origin, section, key, message);
        }
        if (key.size() > 8 && key.compare(key.size() - 8, 8, "_channel") == 0 && setting.value.empty()) {
          fail(setting.origin, section, key, "expected a channel name, got ''");
        }
      }
      continue;
    }
    if (section.rfind("estimator.", 0) == 0) {
      EstimatorSection estimator;
      estimator.name = section.substr(10);
      estimator.section_origin = sectionOrigin(section);
      if (!validName(estimator.name)) {
        fail(estimator.section_origin, section, "",
             "estimator name must be letters, digits, '_' or '-'");
      }
      const std::string suffix = upper(estimator.name);
      estimator.pose_channel = "POSE_" + suffix;
      estimator.map_channel = "MAP_" + suffix;
      estimator.trajectory_channel = "TRAJECTORY_" + suffix;
      estimator.status_channel = "STATUS_" + suffix;
      FaultSettings faults;
      for (const auto& setting : settings) {
        if (setting.key == "isolation") {
          faults.isolated = parseIsolation(setting, section);
        } else if (setting.key == "max_update_s") {
          faults.max_update_s = parseNumber(setting, section, 0.0);
        } else if (setting.key == "max_finish_s") {
          faults.max_finish_s = parseNumber(setting, section, 0.0);
        } else if (setting.key == "max_memory_mb") {
          estimator.max_memory_mb = parseNumber(setting, section, 0.0);
          faults.memory = &setting;
        } else if (setting.key == "plugin") {
          estimator.plugin = setting.value;
          estimator.plugin_origin = setting.origin;
        } else if (setting.key == "pose_channel") {
          estimator.pose_channel = setting.value;
        } else if (setting.key == "map_channel") {
          estimator.map_channel = setting.value;
        } else if (setting.key == "trajectory_channel") {
          estimator.trajectory_channel = setting.value;
        } else if (setting.key == "status_channel") {
          estimator.status_channel = setting.value;
        } else {
          estimator.plugin_settings.push_back(setting);
        }
      }
      if (estimator.plugin.empty()) {
        fail(estimator.section_origin, section, "plugin", "missing: name the plugin, e.g. plugin = spectral");
      }
      config.estimators.push_back(estimator);
      fault_settings.push_back(faults);
      continue;
    }
    std::string message = "unknown section (expected [runtime] or [estimator.NAME])";
    const std::string hint = closestMatch(section, {"runtime"});
    if (!hint.empty()) message += " (did you mean '" + hint + "'?)";
    if (section.rfind("estimator", 0) == 0 || closestMatch(section.substr(0, 10), {"estimator."}) != "") {
      message = "unknown section (expected [estimator.NAME], with a dot)";
    }
    fail(sectionOrigin(section), section, "", message);
  }
  if (!have_input) {
    throw ConfigError(path + ": [runtime] input: missing: a log file or an LCM URL");
  }
  if (config.estimators.empty()) {
    throw ConfigError(path + ": no [estimator.NAME] section: nothing to run");
  }
  if (!threads_given) config.threads = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  for (size_t i = 0; i < config.estimators.size(); ++i) {
    EstimatorSection& estimator = config.estimators[i];
    const FaultSettings& faults = fault_settings[i];
    estimator.isolated = faults.isolated.value_or(config.isolated);
    estimator.max_update_s = faults.max_update_s.value_or(config.max_update_s);
    estimator.max_finish_s = faults.max_finish_s.value_or(config.max_finish_s);
    if (faults.memory != nullptr && estimator.max_memory_mb > 0.0 && !estimator.isolated) {
      fail(faults.memory->origin, "estimator." + estimator.name, "max_memory_mb",
           "needs isolation = process (the limit applies to the estimator's own process)");
    }
  }
  return config;
}

std::string formatConfig(const RunConfig& config, const std::vector<KeyValues>& plugin_effective) {
  std::ostringstream out;
  out << "# effective configuration of " << config.config_file << "\n";
  out << "[runtime]\n";
  out << "input = " << config.input << "\n";
  out << "output = " << config.output << "\n";
  out << "plugin_path = " << config.plugin_path << "\n";
  out << "odometry_channel = " << config.odometry_channel << "\n";
  out << "range_channel = " << config.range_channel << "\n";
  out << "initial_pose_channel = " << config.initial_pose_channel << "\n";
  out << "beacons_channel = " << config.beacons_channel << "\n";
  out << "ground_truth_channel = " << config.ground_truth_channel << "\n";
  out << "trajectory_interval_s = " << config.trajectory_interval_s << "\n";
  out << "status_interval_s = " << config.status_interval_s << "\n";
  out << "max_odometry_gap_s = " << config.max_odometry_gap_s << "\n";
  out << "isolation = " << (config.isolated ? "process" : "none") << "\n";
  out << "max_update_s = " << config.max_update_s << "\n";
  out << "max_finish_s = " << config.max_finish_s << "\n";
  out << "idle_warning_s = " << config.idle_warning_s << "\n";
  out << "threads = " << config.threads << "\n";
  for (size_t i = 0; i < config.estimators.size(); ++i) {
    const auto& estimator = config.estimators[i];
    out << "\n[estimator." << estimator.name << "]\n";
    out << "plugin = " << estimator.plugin << "\n";
    out << "pose_channel = " << estimator.pose_channel << "\n";
    out << "map_channel = " << estimator.map_channel << "\n";
    out << "trajectory_channel = " << estimator.trajectory_channel << "\n";
    out << "status_channel = " << estimator.status_channel << "\n";
    out << "isolation = " << (estimator.isolated ? "process" : "none") << "\n";
    out << "max_update_s = " << estimator.max_update_s << "\n";
    out << "max_finish_s = " << estimator.max_finish_s << "\n";
    if (estimator.isolated) out << "max_memory_mb = " << estimator.max_memory_mb << "\n";
    if (i < plugin_effective.size()) {
      for (const auto& [key, value] : plugin_effective[i]) out << key << " = " << value << "\n";
    } else {
      for (const auto& setting : estimator.plugin_settings) {
        out << setting.key << " = " << setting.value << "\n";
      }
    }
  }
  return out.str();
}

}  // namespace runtime
}  // namespace roam
