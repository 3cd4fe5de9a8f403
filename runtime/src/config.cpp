#include "config.hpp"

#include "plugin_library.hpp"
#include "roam/sensor_noise.hpp"

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
namespace fs = std::filesystem;

namespace {

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

// The INI file, tokenised once: sections in file order, each with its settings and lines.
// '#' starts a comment anywhere on a line; keys and values are trimmed.
struct IniFile {
  std::vector<std::string> section_order;
  std::map<std::string, int> section_lines;             // "estimator.a" -> line
  std::map<std::string, std::vector<Setting>> sections;  // in file order
};

IniFile readIni(const std::string& file, std::istream& in) {
  IniFile ini;
  std::string line, section;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    const std::string text = trim(line.substr(0, line.find('#')));
    if (text.empty()) continue;
    Origin origin{file, number, ""};
    if (text.front() == '[') {
      if (text.back() != ']') fail(origin, "", "", "expected a section header like [runtime]");
      section = trim(text.substr(1, text.size() - 2));
      if (section.empty()) fail(origin, "", "", "empty section name");
      if (ini.section_lines.count(section)) {
        fail(origin, section, "",
             "section repeated (first at line " + std::to_string(ini.section_lines[section]) + ")");
      }
      ini.section_lines[section] = number;
      ini.section_order.push_back(section);
      ini.sections[section];
      continue;
    }
    const auto equals = text.find('=');
    if (equals == std::string::npos) fail(origin, section, "", "expected 'key = value', got '" + text + "'");
    const std::string key = trim(text.substr(0, equals));
    if (key.empty()) fail(origin, section, "", "missing key before '='");
    if (section.empty()) fail(origin, "", key, "key outside any section (put it under [runtime])");
    auto& settings = ini.sections[section];
    for (const auto& setting : settings) {
      if (setting.key == key) {
        fail(origin, section, key, "key repeated (first at line " + std::to_string(setting.origin.line) + ")");
      }
    }
    settings.push_back(Setting{key, trim(text.substr(equals + 1)), origin});
  }
  return ini;
}

// The [runtime] keys, each with its default (RunConfig's), check and help: the one list of them.
void addRuntimeOptions(Options& o, RunConfig* c) {
  o.add("input", &c->input, "a log file, or an LCM URL (live mode)");
  o.add("output", &c->output, "the result log (\"\": none)");
  o.add("plugin_path", &c->plugin_path, "':'-separated folders searched before the shipped one");
  o.add("odometry_channel", &c->odometry_channel, "input channel of odometry").nonEmpty();
  o.add("range_channel", &c->range_channel, "input channel of ranges").nonEmpty();
  o.add("initial_pose_channel", &c->initial_pose_channel, "input channel of the start pose").nonEmpty();
  o.add("beacons_channel", &c->beacons_channel, "input channel of surveyed beacons").nonEmpty();
  o.add("ground_truth_channel", &c->ground_truth_channel, "input channel of ground truth").nonEmpty();
  o.add("trajectory_interval_s", &c->trajectory_interval_s, "live mode: ask smoothers for their path this often (data time)").min(0.0);
  o.add("status_interval_s", &c->status_interval_s, "STATUS_* at least this often (data time)").min(0.0);
  o.add("max_odometry_gap_s", &c->max_odometry_gap_s, "a larger odometry gap counts as dropped steps").min(0.0);
  o.add("reorder_window_s", &c->reorder_window_s,
        "odometry and ranges are held this long (data time) and fed in utime order: a range that arrives up to "
        "this late still meets its odometry step (0: arrival order)").min(0.0).max(3600.0);
  o.add("isolation", &c->isolated, {{"none", false}, {"process", true}}, "estimators' default: in roam-run's process or their own");
  o.add("max_update_s", &c->max_update_s, "estimators' default wall-clock limit per update (0: none)").min(0.0);
  o.add("max_finish_s", &c->max_finish_s, "estimators' default wall-clock limit of finish (0: none)").min(0.0);
  o.add("idle_warning_s", &c->idle_warning_s, "live mode: warn when an input channel is quiet this long (0: never)").min(0.0);
  o.add("threads", &c->threads, "worker threads for in-process estimators (default: the machine's cores)").min(1).max(1024);
}

// The runtime's keys of an [estimator.NAME] section; every other key goes to the plugin.
void addEstimatorOptions(Options& o, EstimatorSection* e) {
  o.add("plugin", &e->plugin, "the plugin's name");
  o.add("pose_channel", &e->pose_channel, "output channel of poses").nonEmpty();
  o.add("map_channel", &e->map_channel, "output channel of the map").nonEmpty();
  o.add("trajectory_channel", &e->trajectory_channel, "output channel of the path").nonEmpty();
  o.add("status_channel", &e->status_channel, "output channel of the status").nonEmpty();
  o.add("isolation", &e->isolated, {{"none", false}, {"process", true}}, "in roam-run's process or its own");
  o.add("max_update_s", &e->max_update_s, "wall-clock limit per update (0: none)").min(0.0);
  o.add("max_finish_s", &e->max_finish_s, "wall-clock limit of finish (0: none)").min(0.0);
  o.add("max_memory_mb", &e->max_memory_mb, "isolation = process: memory the estimator's process may add (0: none)").min(0.0);
  o.require([e] { return e->max_memory_mb == 0.0 || e->isolated; }, {"max_memory_mb", "isolation"},
            "isolation = process when max_memory_mb > 0 (the limit applies to the estimator's own process)");
}

// Parses `settings` with `options`; a ConfigError names the setting's file, line, section and key.
void parseSection(Options& options, const std::vector<Setting>& settings, const std::string& section,
                  const Origin& section_origin) {
  try {
    options.parse();
  } catch (const roam::ConfigError& error) {
    Origin origin = section_origin;
    for (const auto& setting : settings) {
      if (setting.key == error.key()) origin = setting.origin;
    }
    fail(origin, section, error.key(), error.what());
  }
}

std::string resolvePath(const std::string& value, const fs::path& base) {
  if (value.empty() || value.find("://") != std::string::npos) return value;
  fs::path path(value);
  if (path.is_absolute()) return path.lexically_normal().string();
  return (base / path).lexically_normal().string();
}

bool validName(const std::string& name) {
  if (name.empty()) return false;
  for (char c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-') return false;
  }
  return true;
}

// A list of robot names (space- or comma-separated, each a channel suffix), as [team] key `key`.
std::vector<std::string> parseNames(const std::string& text, const Origin& origin, const std::string& key) {
  std::vector<std::string> names;
  std::istringstream words(text);
  for (std::string word; std::getline(words, word, ' ');) {
    for (std::string name; !word.empty();) {
      const auto comma = word.find(',');
      name = trim(word.substr(0, comma));
      word = comma == std::string::npos ? "" : word.substr(comma + 1);
      if (name.empty()) continue;
      if (!validName(name)) fail(origin, "team", key, "'" + name + "': a robot's name must be letters, digits, '_' or '-'");
      if (std::find(names.begin(), names.end(), name) != names.end())
        fail(origin, "team", key, "'" + name + "' is named twice");
      names.push_back(name);
    }
  }
  return names;
}

// [team] robots = A B C: the team's names; starts = A: the robots whose start pose the estimators
// are given (default: every robot).
void parseTeam(const std::vector<Setting>& settings, const Origin& section_origin, RunConfig* config) {
  std::string robots_text, starts_text = "all";
  KeyValues values;
  for (const auto& setting : settings) values.emplace_back(setting.key, setting.value);
  Options options(values);
  options.add("robots", &robots_text,
              "the team's robots, space-separated: each robot's inputs are on <CHANNEL>_<robot> (ODOMETRY_A, ...)");
  options.add("starts", &starts_text,
              "the robots whose INITIAL_POSE_<robot> the estimators are given (all: every robot); the others' "
              "starts are for the estimators to find from the ranges");
  parseSection(options, settings, "team", section_origin);
  Origin robots_origin = section_origin, starts_origin = section_origin;
  for (const auto& setting : settings) {
    if (setting.key == "robots") robots_origin = setting.origin;
    if (setting.key == "starts") starts_origin = setting.origin;
  }
  config->team = parseNames(robots_text, robots_origin, "robots");
  if (config->team.empty()) fail(robots_origin, "team", "robots", "missing: name the team's robots, e.g. robots = A B C");
  if (trim(starts_text) == "all") {
    config->team_starts = config->team;
    return;
  }
  config->team_starts = parseNames(starts_text, starts_origin, "starts");
  for (const auto& name : config->team_starts) {
    if (std::find(config->team.begin(), config->team.end(), name) == config->team.end())
      fail(starts_origin, "team", "starts", "'" + name + "' is not one of the team's robots (robots = ...)");
  }
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
  IniFile ini = readIni(path, file);
  for (const auto& text : overrides) {
    const auto equals = text.find('=');
    const Origin origin{"", 0, "--set " + text};
    if (equals == std::string::npos) fail(origin, "", "", "expected section.key=value");
    const std::string full_key = trim(text.substr(0, equals));
    const auto dot = full_key.rfind('.');
    if (dot == std::string::npos || dot == 0) fail(origin, "", full_key, "expected section.key");
    const std::string section = full_key.substr(0, dot), key = full_key.substr(dot + 1);
    if (!ini.sections.count(section)) {
      // A new [estimator.NAME] needs its plugin named; any other key for a section the file does
      // not have is a typo of a section's name, said as such (not as a missing plugin key).
      if (section != "runtime" && section != "team" && section != "sensors" && key != "plugin") {
        std::string sections;
        for (const auto& known : ini.section_order) sections += (sections.empty() ? "" : ", ") + ("[" + known + "]");
        std::string message = "no section [" + section + "] in " + path + " (it has " +
                              (sections.empty() ? std::string("none") : sections) + ")";
        std::vector<std::string> names(ini.section_order.begin(), ini.section_order.end());
        const std::string hint = closestMatch(section, names);
        if (!hint.empty()) message += "; did you mean '" + hint + "." + key + "'?";
        message += " (to add an estimator, name its plugin first: --set " + section + ".plugin=NAME)";
        fail(origin, "", "", message);
      }
      ini.section_order.push_back(section);
    }
    auto& settings = ini.sections[section];
    const Setting setting{key, trim(text.substr(equals + 1)), origin};
    auto it = std::find_if(settings.begin(), settings.end(), [&](const Setting& s) { return s.key == key; });
    if (it != settings.end()) {
      *it = setting;
    } else {
      settings.push_back(setting);
    }
  }

  const fs::path base = fs::absolute(fs::path(path)).parent_path();
  auto sectionOrigin = [&](const std::string& section) {
    const auto it = ini.section_lines.find(section);
    return Origin{path, it == ini.section_lines.end() ? 0 : it->second, ""};
  };
  for (const auto& section : ini.section_order) {
    if (section == "runtime" || section == "team" || section == "sensors" || section.rfind("estimator.", 0) == 0)
      continue;
    std::string message = "unknown section (expected [runtime], [sensors], [team] or [estimator.NAME])";
    const std::string hint = closestMatch(section, {"runtime", "sensors", "team"});
    if (!hint.empty()) message += " (did you mean '" + hint + "'?)";
    if (section.rfind("estimator", 0) == 0 || closestMatch(section.substr(0, 10), {"estimator."}) != "") {
      message = "unknown section (expected [estimator.NAME], with a dot)";
    }
    fail(sectionOrigin(section), section, "", message);
  }

  // [runtime], first wherever it stands: it holds the estimators' defaults.
  const auto& runtime_settings = ini.sections["runtime"];
  config.runtime_settings = runtime_settings;
  config.threads = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  KeyValues runtime_values;
  for (const auto& setting : runtime_settings) runtime_values.emplace_back(setting.key, setting.value);
  Options runtime_options(runtime_values);
  addRuntimeOptions(runtime_options, &config);
  parseSection(runtime_options, runtime_settings, "runtime", sectionOrigin("runtime"));
  if (config.input.empty()) {
    throw ConfigError(path + ": [runtime] input: missing: a log file or an LCM URL");
  }
  config.input = resolvePath(config.input, base);
  config.output = resolvePath(config.output, base);
  if (runtime_options.given("plugin_path")) {
    // ':'-separated folders searched in order; the shipped folder is always searched last.
    std::string list;
    for (const std::string& folder : PluginLibrary::searchFolders(config.plugin_path)) {
      const std::string resolved = resolvePath(folder, base);
      if (resolved != default_plugin_path) list += resolved + ":";
    }
    config.plugin_path = list + default_plugin_path;
  } else {
    config.plugin_path = default_plugin_path;
  }

  if (ini.sections.count("team")) parseTeam(ini.sections["team"], sectionOrigin("team"), &config);

  // [sensors]: the sensors' stated noise, every estimator's default (roam/sensor_noise.hpp).
  config.sensor_settings = ini.sections["sensors"];
  KeyValues sensor_values;
  for (const auto& setting : config.sensor_settings) sensor_values.emplace_back(setting.key, setting.value);
  Options sensor_options(sensor_values);
  addSensorNoiseOptions(sensor_options, &config.sensors);
  parseSection(sensor_options, config.sensor_settings, "sensors", sectionOrigin("sensors"));

  for (const auto& section : ini.section_order) {
    if (section.rfind("estimator.", 0) != 0) continue;
    EstimatorSection estimator;
    estimator.name = section.substr(10);
    estimator.section_origin = sectionOrigin(section);
    if (!validName(estimator.name)) {
      fail(estimator.section_origin, section, "", "estimator name must be letters, digits, '_' or '-'");
    }
    const std::string suffix = upper(estimator.name);
    estimator.pose_channel = "POSE_" + suffix;
    estimator.map_channel = "MAP_" + suffix;
    estimator.trajectory_channel = "TRAJECTORY_" + suffix;
    estimator.status_channel = "STATUS_" + suffix;
    estimator.isolated = config.isolated;
    estimator.max_update_s = config.max_update_s;
    estimator.max_finish_s = config.max_finish_s;
    // The runtime's own keys (those addEstimatorOptions declares) are parsed here; the rest
    // are the plugin's.
    Options runtime_keys(KeyValues{});
    addEstimatorOptions(runtime_keys, &estimator);
    const std::vector<std::string> own = runtime_keys.keys();
    KeyValues values;
    std::vector<Setting> own_settings;
    for (const auto& setting : ini.sections[section]) {
      if (std::find(own.begin(), own.end(), setting.key) != own.end()) {
        values.emplace_back(setting.key, setting.value);
        own_settings.push_back(setting);
        if (setting.key == "plugin") estimator.plugin_origin = setting.origin;
      } else {
        estimator.plugin_settings.push_back(setting);
      }
    }
    for (const auto& setting : config.sensor_settings)
      estimator.plugin_settings.push_back(Setting{Options::kSharedPrefix + setting.key, setting.value, setting.origin});
    Options options(values);
    addEstimatorOptions(options, &estimator);
    parseSection(options, own_settings, section, estimator.section_origin);
    if (estimator.plugin.empty()) {
      fail(estimator.section_origin, section, "plugin", "missing: name the plugin, e.g. plugin = spectral");
    }
    config.estimators.push_back(estimator);
  }
  if (config.estimators.empty()) {
    throw ConfigError(path + ": no [estimator.NAME] section: nothing to run");
  }
  return config;
}

std::vector<EstimatorSection> teamRuns(const RunConfig& config, const EstimatorSection& section, bool team_plugin) {
  if (!config.isTeam() || team_plugin) return {section};
  std::vector<EstimatorSection> runs;
  for (size_t r = 0; r < config.team.size(); ++r) {
    EstimatorSection run = section;
    const std::string suffix = "_" + config.team[r];
    run.name += suffix;
    run.robot = static_cast<int>(r);
    for (std::string* channel : {&run.pose_channel, &run.map_channel, &run.trajectory_channel, &run.status_channel})
      *channel += suffix;
    runs.push_back(run);
  }
  return runs;
}

std::string formatConfig(const RunConfig& config, const std::vector<KeyValues>& plugin_effective) {
  std::ostringstream out;
  out << "# effective configuration of " << config.config_file << "\n";
  out << "[runtime]\n";
  // The declarations print the values (Options over no keys: the current values, as parsed).
  RunConfig copy = config;
  Options runtime(KeyValues{});
  addRuntimeOptions(runtime, &copy);
  for (const auto& [key, value] : runtime.effective()) out << key << " = " << value << "\n";
  if (config.isTeam()) {
    out << "\n[team]\nrobots =";
    for (const auto& robot : config.team) out << " " << robot;
    out << "\nstarts =";
    if (config.team_starts == config.team) out << " all";
    for (const auto& robot : config.team_starts) {
      if (config.team_starts != config.team) out << " " << robot;
    }
    out << "\n";
  }
  out << "\n[sensors]\n";
  SensorNoise sensors = config.sensors;
  Options sensor_options(KeyValues{});
  addSensorNoiseOptions(sensor_options, &sensors);
  const KeyValues sensor_values = sensor_options.effective();
  for (const auto& [key, value] : sensor_values) out << key << " = " << value << "\n";
  for (size_t i = 0; i < config.estimators.size(); ++i) {
    EstimatorSection estimator = config.estimators[i];
    out << "\n[estimator." << estimator.name << "]\n";
    Options own(KeyValues{});
    addEstimatorOptions(own, &estimator);
    for (const auto& [key, value] : own.effective()) {
      if (key == "max_memory_mb" && !estimator.isolated) continue;  // applies to isolated ones only
      out << key << " = " << value << "\n";
    }
    if (i < plugin_effective.size()) {
      // A sensor's figure is printed under [sensors]; here only where this estimator differs.
      for (const auto& [key, value] : plugin_effective[i]) {
        const bool shared = std::find(sensor_values.begin(), sensor_values.end(), std::make_pair(key, value)) !=
                            sensor_values.end();
        if (!shared) out << key << " = " << value << "\n";
      }
    } else {
      for (const auto& setting : estimator.plugin_settings) {
        if (setting.key.rfind(Options::kSharedPrefix, 0) == 0) continue;
        out << setting.key << " = " << setting.value << "\n";
      }
    }
  }
  return out.str();
}

}  // namespace runtime
}  // namespace roam
