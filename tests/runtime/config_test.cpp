// roam-run's config loading: every error names file, line, section and key.
#include <gtest/gtest.h>

#include "config.hpp"
#include "test_util.hpp"

namespace roam {
namespace runtime {
namespace {

using testing_util::scratchDir;
using testing_util::writeFile;

std::string loadError(const std::string& text, const std::vector<std::string>& overrides = {}) {
  const auto dir = scratchDir("config_error");
  const auto path = writeFile(dir / "bad.ini", text);
  try {
    loadConfig(path.string(), overrides, "/plugins");
  } catch (const ConfigError& error) {
    // Strip the folder so the expected strings stay short.
    std::string message = error.what();
    const std::string prefix = dir.string() + "/";
    for (size_t at = message.find(prefix); at != std::string::npos; at = message.find(prefix, at)) {
      message.erase(at, prefix.size());
    }
    return message;
  }
  return "(no error)";
}

TEST(Config, ReadsSectionsAndResolvesPathsAgainstTheConfigFolder) {
  const auto dir = scratchDir("config_ok");
  const auto path = writeFile(dir / "run.ini",
                              "[runtime]\n"
                              "input = ../logs/a.lcmlog   # a comment\n"
                              "output = out/result.lcmlog\n"
                              "\n"
                              "[estimator.dr]\n"
                              "plugin = deadreckoning\n"
                              "max_speed_mps = 3\n");
  const RunConfig config = loadConfig(path.string(), {}, "/default/plugins");
  EXPECT_EQ(config.input, (dir.parent_path() / "logs/a.lcmlog").lexically_normal().string());
  EXPECT_EQ(config.output, (dir / "out/result.lcmlog").string());
  EXPECT_EQ(config.plugin_path, "/default/plugins");
  ASSERT_EQ(config.estimators.size(), 1u);
  EXPECT_EQ(config.estimators[0].name, "dr");
  EXPECT_EQ(config.estimators[0].plugin, "deadreckoning");
  EXPECT_EQ(config.estimators[0].pose_channel, "POSE_DR");
  EXPECT_EQ(config.estimators[0].trajectory_channel, "TRAJECTORY_DR");
  ASSERT_EQ(config.estimators[0].plugin_settings.size(), 1u);
  EXPECT_EQ(config.estimators[0].plugin_settings[0].key, "max_speed_mps");
  EXPECT_EQ(config.estimators[0].plugin_settings[0].value, "3");
  EXPECT_EQ(config.estimators[0].plugin_settings[0].origin.line, 7);
  EXPECT_FALSE(config.isLive());
}

TEST(Config, UrlInputsAreNotPathsAndOverridesWin) {
  const auto dir = scratchDir("config_url");
  const auto path = writeFile(dir / "run.ini",
                              "[runtime]\ninput = a.lcmlog\n[estimator.dr]\nplugin = deadreckoning\n");
  const RunConfig config = loadConfig(
      path.string(), {"runtime.input=udpm://239.255.76.67:7667?ttl=0", "estimator.dr.max_speed_mps=2"}, "/p");
  EXPECT_EQ(config.input, "udpm://239.255.76.67:7667?ttl=0");
  EXPECT_TRUE(config.isLive());
  ASSERT_EQ(config.estimators[0].plugin_settings.size(), 1u);
  EXPECT_EQ(config.estimators[0].plugin_settings[0].origin.describe(), "--set estimator.dr.max_speed_mps=2");
}

TEST(Config, OverrideOfASectionTheFileLacksNamesTheSection) {
  const std::string text = "[runtime]\ninput = a.lcmlog\n[estimator.ekf]\nplugin = x\n";
  EXPECT_EQ(loadError(text, {"estimator.ekg.anchor=beacons"}),
            "--set estimator.ekg.anchor=beacons: no section [estimator.ekg] in bad.ini (it has [runtime], "
            "[estimator.ekf]); did you mean 'estimator.ekf.anchor'? (to add an estimator, name its plugin "
            "first: --set estimator.ekg.plugin=NAME)");
  // Naming a plugin adds an estimator, as before.
  const auto dir = scratchDir("config_override_new");
  const auto path = writeFile(dir / "ok.ini", text);
  const RunConfig config = loadConfig(path.string(), {"estimator.b.plugin=y", "estimator.b.rank=4"}, "/p");
  ASSERT_EQ(config.estimators.size(), 2u);
  EXPECT_EQ(config.estimators[1].plugin, "y");
}

TEST(Config, ErrorsNameFileLineSectionAndKey) {
  const std::string head = "[runtime]\ninput = a.lcmlog\n";
  EXPECT_EQ(loadError(head + "inptu = b\n[estimator.a]\nplugin = x\n"),
            "bad.ini:3 [runtime] inptu: unknown key 'inptu' (did you mean 'input'?)");
  EXPECT_EQ(loadError(head + "status_interval_s = fast\n[estimator.a]\nplugin = x\n"),
            "bad.ini:3 [runtime] status_interval_s: expected a number, got 'fast'");
  EXPECT_EQ(loadError(head + "[estimator.a]\nrank = 4\n"),
            "bad.ini:3 [estimator.a] plugin: missing: name the plugin, e.g. plugin = spectral");
  EXPECT_EQ(loadError(head + "[estimater.a]\nplugin = x\n"),
            "bad.ini:3 [estimater.a]: unknown section (expected [estimator.NAME], with a dot)");
  EXPECT_EQ(loadError(head + "[estimator.a]\nplugin = x\nplugin = y\n"),
            "bad.ini:5 [estimator.a] plugin: key repeated (first at line 4)");
  EXPECT_EQ(loadError(head + "just some words\n"),
            "bad.ini:3 [runtime]: expected 'key = value', got 'just some words'");
  EXPECT_EQ(loadError("input = a\n"), "bad.ini:1 input: key outside any section (put it under [runtime])");
  EXPECT_EQ(loadError("[runtime]\noutput = x\n[estimator.a]\nplugin = x\n"),
            "bad.ini: [runtime] input: missing: a log file or an LCM URL");
  EXPECT_EQ(loadError(head), "bad.ini: no [estimator.NAME] section: nothing to run");
  EXPECT_EQ(loadError(head + "[estimator.a b]\nplugin = x\n"),
            "bad.ini:3 [estimator.a b]: estimator name must be letters, digits, '_' or '-'");
  EXPECT_EQ(loadError(head + "[estimator.a]\nplugin = x\n", {"runtime.odometry_channel="}),
            "--set runtime.odometry_channel= [runtime] odometry_channel: expected a non-empty value, got ''");
}

TEST(Config, RuntimeKeysGoThroughOptionsLikeThePlugins) {
  // [runtime] and the runtime's estimator keys are declared with roam::Options: the same
  // messages, hints and constraints as a plugin's keys.
  const std::string head = "[runtime]\ninput = a.lcmlog\n";
  const std::string tail = "[estimator.a]\nplugin = x\n";
  EXPECT_EQ(loadError(head + "max_update_s = -1\n" + tail),
            "bad.ini:3 [runtime] max_update_s: expected a value >= 0, got '-1'");
  EXPECT_EQ(loadError(head + "threads = 0\n" + tail), "bad.ini:3 [runtime] threads: expected a value >= 1, got '0'");
  EXPECT_EQ(loadError(head + "threads = 2000\n" + tail),
            "bad.ini:3 [runtime] threads: expected a value <= 1024, got '2000'");
  EXPECT_EQ(loadError(head + "isolation = proces\n" + tail),
            "bad.ini:3 [runtime] isolation: expected one of none | process (did you mean 'process'?), got 'proces'");
  EXPECT_EQ(loadError(head + tail + "pose_channel =\n"),
            "bad.ini:5 [estimator.a] pose_channel: expected a non-empty value, got ''");
  EXPECT_EQ(loadError(head + tail + "max_memory_mb = 64\n", {"estimator.a.isolation=none"}),
            "bad.ini:5 [estimator.a] max_memory_mb: expected isolation = process when max_memory_mb > 0 (the limit "
            "applies to the estimator's own process), got max_memory_mb = 64, isolation = none");
  // [runtime] supplies the estimators' defaults wherever it stands in the file.
  const auto dir = scratchDir("config_runtime_last");
  const auto path = writeFile(dir / "run.ini", tail + "max_finish_s = 3\n" + head + "isolation = process\n"
                                                   "max_finish_s = 9\nthreads = 2\n");
  const RunConfig config = loadConfig(path.string(), {}, "/p");
  EXPECT_EQ(config.threads, 2);
  EXPECT_TRUE(config.isolated);
  ASSERT_EQ(config.estimators.size(), 1u);
  EXPECT_TRUE(config.estimators[0].isolated);
  EXPECT_EQ(config.estimators[0].max_finish_s, 3.0);
  EXPECT_TRUE(config.estimators[0].plugin_settings.empty());
  // --print-config prints the declared keys with their names and values.
  const std::string printed = formatConfig(config);
  EXPECT_NE(printed.find("[runtime]\ninput = " + (dir / "a.lcmlog").string() + "\noutput = \nplugin_path = /p\n"
                         "odometry_channel = ODOMETRY\n"),
            std::string::npos) << printed;
  EXPECT_NE(printed.find("isolation = process\nmax_update_s = 0\nmax_finish_s = 9\nidle_warning_s = 5\nthreads = 2\n"),
            std::string::npos) << printed;
  EXPECT_NE(printed.find("[estimator.a]\nplugin = x\npose_channel = POSE_A\nmap_channel = MAP_A\n"
                         "trajectory_channel = TRAJECTORY_A\nstatus_channel = STATUS_A\nisolation = process\n"
                         "max_update_s = 0\nmax_finish_s = 3\nmax_memory_mb = 0\n"),
            std::string::npos) << printed;
}

TEST(Config, SensorsStateTheNoiseOnceForEveryEstimator) {
  // [sensors]: the sensors' stated noise, checked with the SDK's declaration and handed to every
  // estimator as a shared default ("sensors.<key>"), after the estimator's own keys.
  const std::string head = "[runtime]\ninput = a.lcmlog\n";
  const std::string tail = "[estimator.a]\nplugin = ekf\nrange_sigma_m = 0.3\n[estimator.b]\nplugin = deadreckoning\n";
  EXPECT_EQ(loadError(head + "[sensors]\nrange_sigma = 0.7\n" + tail),
            "bad.ini:4 [sensors] range_sigma: unknown key 'range_sigma' (did you mean 'range_sigma_m'?)");
  EXPECT_EQ(loadError(head + "[sensors]\nrange_sigma_m = 0\n" + tail),
            "bad.ini:4 [sensors] range_sigma_m: expected a value > 0, got '0'");
  EXPECT_EQ(loadError(head + "[sensor]\n" + tail),
            "bad.ini:3 [sensor]: unknown section (expected [runtime], [sensors], [team] or [estimator.NAME]) "
            "(did you mean 'sensors'?)");
  const auto dir = scratchDir("config_sensors");
  const auto path = writeFile(dir / "run.ini", head + "[sensors]\nrange_sigma_m = 0.7\n" + tail);
  const RunConfig config = loadConfig(path.string(), {"sensors.odo_distance_sigma_rel=0.05"}, "/p");
  EXPECT_EQ(config.sensors.range_sigma_m, 0.7);
  EXPECT_EQ(config.sensors.odo_distance_sigma_rel, 0.05);
  EXPECT_EQ(config.sensors.bearing_sigma_rad, SensorNoise{}.bearing_sigma_rad);
  ASSERT_EQ(config.estimators.size(), 2u);
  for (const auto& estimator : config.estimators) {
    const auto& settings = estimator.plugin_settings;
    ASSERT_GE(settings.size(), 2u);
    EXPECT_EQ(settings[settings.size() - 2].key, "sensors.range_sigma_m");
    EXPECT_EQ(settings[settings.size() - 2].value, "0.7");
    EXPECT_EQ(settings[settings.size() - 2].origin.line, 4);
    EXPECT_EQ(settings.back().key, "sensors.odo_distance_sigma_rel");
    EXPECT_EQ(settings.back().origin.describe(), "--set sensors.odo_distance_sigma_rel=0.05");
  }
  EXPECT_EQ(config.estimators[0].plugin_settings.front().key, "range_sigma_m");
  // --print-config: [sensors] with every figure; an estimator's own value where it differs.
  const std::string printed = formatConfig(config);
  EXPECT_NE(printed.find("[sensors]\nodo_distance_sigma_rel = 0.05\nodo_distance_sigma_m = 0.005\n"), std::string::npos)
      << printed;
  EXPECT_NE(printed.find("range_sigma_m = 0.7\n"), std::string::npos) << printed;
  EXPECT_NE(printed.find("max_finish_s = 0\nrange_sigma_m = 0.3\n"), std::string::npos) << printed;
  EXPECT_EQ(printed.find("\nsensors."), std::string::npos) << printed;
}

TEST(Config, MissingFileIsReported) {
  EXPECT_THROW(loadConfig("/nonexistent/roam.ini", {}, "/p"), ConfigError);
}

}  // namespace
}  // namespace runtime
}  // namespace roam
