// roam-run's configuration: an INI file, tokenised once; the [runtime] keys and the runtime's
// keys of each [estimator.NAME] are declared with roam::Options (defaults, checks, help), as
// the plugins declare theirs, so errors, "did you mean" and --print-config are one code path.
//
//   [runtime]            input, output, plugin_path, channel names, live-mode settings
//   [sensors]            the sensors' stated noise, shared by every estimator (roam/sensor_noise.hpp)
//   [estimator.NAME]     plugin = <plugin name>; every other key goes to the plugin, except the
//                        runtime's per-estimator keys (pose_channel, map_channel, ...)
//
// Every problem is reported as a ConfigError carrying file, line, section and key, so the
// message reads "run.ini:12: [estimator.spectral] rank: expected one of 4 | 7, got '5'".
// Relative paths are resolved against the config file's folder.
#pragma once

#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "roam/options.hpp"
#include "roam/sensor_noise.hpp"

namespace roam {
namespace runtime {

// Where a value came from: a file line, or a command-line override.
struct Origin {
  std::string file;  // "" for defaults
  int line = 0;      // 0 if not from a file line
  std::string override_text;  // e.g. "--set estimator.a.rank=5"
  std::string describe() const;
};

class ConfigError : public std::runtime_error {
 public:
  explicit ConfigError(const std::string& message) : std::runtime_error(message) {}
};

struct Setting {
  std::string key;
  std::string value;
  Origin origin;
};

struct EstimatorSection {
  std::string name;     // NAME in [estimator.NAME]
  std::string plugin;   // the plugin key
  Origin plugin_origin;
  Origin section_origin;  // the [estimator.NAME] line
  std::vector<Setting> plugin_settings;  // passed to the plugin
  std::string pose_channel, map_channel, trajectory_channel, status_channel;
  // A team run: robot >= 0 for an instance of a one-robot plugin given robot `robot`'s inputs
  // alone (named NAME_<robot>); -1 for an instance that sees every input (a robot alone, or a
  // team plugin, whose poses and paths go to pose_channel / trajectory_channel + "_<robot>").
  int robot = -1;
  // Fault handling (defaults from [runtime]): where the estimator runs, its time limits in
  // wall-clock seconds (0 = none), and its memory limit in MB (isolation = process only).
  bool isolated = false;
  double max_update_s = 0.0;
  double max_finish_s = 0.0;
  double max_memory_mb = 0.0;
  // Origin of a plugin key, for error messages (section line if the key is unknown).
  Origin originOf(const std::string& key) const;
};

struct RunConfig {
  std::string config_file;
  std::string input;        // a log file path, or an LCM URL (contains "://")
  std::string output;       // result log path; "" for none
  std::string plugin_path;  // folder holding libroam_<plugin>.so
  std::string odometry_channel = "ODOMETRY";
  std::string range_channel = "RANGE";
  std::string initial_pose_channel = "INITIAL_POSE";
  std::string beacons_channel = "BEACONS";
  std::string ground_truth_channel = "GROUND_TRUTH";
  double trajectory_interval_s = 10.0;  // live mode: request paths this often (data time); 0 = end only
  double status_interval_s = 1.0;       // STATUS_* at least this often (data time)
  double max_odometry_gap_s = 1.0;      // a larger gap between odometry stamps counts as dropped steps
  double reorder_window_s = 1.0;        // odometry and ranges fed in utime order within this (data time)
  bool isolated = false;                // [runtime] isolation: the estimators' default
  double max_update_s = 0.0;            // the estimators' default time limits (0 = none)
  double max_finish_s = 0.0;
  double idle_warning_s = 5.0;          // live mode: warn when an input channel is quiet this long
  int threads = 1;                      // worker threads for in-process estimators (default: cores)
  std::vector<EstimatorSection> estimators;
  // [team] robots: empty for one robot (inputs on the channels above). A team's inputs are on
  // <CHANNEL>_<robot> (ODOMETRY_A, RANGE_A, ROBOT_RANGE_A, INITIAL_POSE_A; BEACONS is shared).
  std::vector<std::string> team;
  // [team] starts: the robots whose INITIAL_POSE_<robot> is given to the estimators (every robot
  // by default); the others' start poses are withheld, for a team estimator to find.
  std::vector<std::string> team_starts;
  bool isTeam() const { return !team.empty(); }
  // [sensors]: the sensors' stated noise (defaults included), and its settings as given; each
  // given one is in every estimator's plugin_settings as "sensors.<key>" (Options::kSharedPrefix).
  SensorNoise sensors;
  std::vector<Setting> sensor_settings;
  std::vector<Setting> runtime_settings;  // as given, for --print-config

  bool isLive() const { return input.find("://") != std::string::npos; }
};

// Reads and validates `path`; `overrides` are "section.key=value" strings from --set.
// `default_plugin_path` is used when [runtime] plugin_path is not given.
RunConfig loadConfig(const std::string& path, const std::vector<std::string>& overrides,
                     const std::string& default_plugin_path);

// The effective config as INI text (runtime keys with defaults; plugin keys as given, or the
// plugins' effective values when `plugin_effective` holds them, in estimator order).
std::string formatConfig(const RunConfig& config,
                         const std::vector<KeyValues>& plugin_effective = {});

// The runs of one [estimator.NAME] section: the section itself, except in a team run for a plugin
// that estimates one robot (team_plugin false): one copy per robot, named NAME_<robot>, its
// outputs on POSE_NAME_<robot> etc. (a pose_channel set in the section gets "_<robot>").
std::vector<EstimatorSection> teamRuns(const RunConfig& config, const EstimatorSection& section, bool team_plugin);

}  // namespace runtime
}  // namespace roam
