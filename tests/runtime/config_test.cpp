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
    if (message.rfind(prefix, 0) == 0) message = message.substr(prefix.size());
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

TEST(Config, ErrorsNameFileLineSectionAndKey) {
  const std::string head = "[runtime]\ninput = a.lcmlog\n";
  EXPECT_EQ(loadError(head + "inptu = b\n[estimator.a]\nplugin = x\n"),
            "bad.ini:3 [runtime] inptu: unknown key (did you mean 'input'?)");
  EXPECT_EQ(loadError(head + "status_interval_s = fast\n[estimator.a]\nplugin = x\n"),
            "bad.ini:3 [runtime] status_interval_s: expected a number >= 0, got 'fast'");
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
            "--set runtime.odometry_channel= [runtime] odometry_channel: expected a channel name, got ''");
}

TEST(Config, MissingFileIsReported) {
  EXPECT_THROW(loadConfig("/nonexistent/roam.ini", {}, "/p"), ConfigError);
}

}  // namespace
}  // namespace runtime
}  // namespace roam
