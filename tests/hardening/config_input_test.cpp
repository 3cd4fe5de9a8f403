// Config values of the wrong type or out of range (README "Bad input"): one line naming the
// file, line, section and key, exit status 2, and nothing read or written — for the runtime's
// keys, for the SDK's max_range_m in every plugin, and for a plugin's own bound.
#include <gtest/gtest.h>

#include <algorithm>

#include "../runtime/test_util.hpp"
#include "hardening_util.hpp"

namespace roam {
namespace hardening {
namespace {

struct Case {
  std::string runtime_keys;  // under [runtime]
  std::string section;       // the estimator section (after plugin = ...)
  std::string plugin;
  std::string expected;      // part of the one line
};

void expectStartupError(const Case& c) {
  SCOPED_TRACE(c.expected);
  const fs::path dir = testing_util::scratchDir(
      std::string("hardening_config_") + ::testing::UnitTest::GetInstance()->current_test_info()->name());
  writeLog(dir / "input.lcmlog", cleanEvents());
  testing_util::writeFile(dir / "run.ini", "[runtime]\ninput = input.lcmlog\noutput = result.lcmlog\n" +
                                               c.runtime_keys + "[estimator." + c.plugin + "]\nplugin = " +
                                               c.plugin + "\n" + c.section);
  const auto result = testing_util::run(testing_util::roamRun() + " " + (dir / "run.ini").string());
  EXPECT_EQ(result.status, 2) << result.output;
  EXPECT_NE(result.output.find("roam-run: error: " + (dir / "run.ini").string() + c.expected), std::string::npos)
      << result.output;
  EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1) << result.output;
  EXPECT_FALSE(fs::exists(dir / "result.lcmlog")) << "nothing may be written";
}

TEST(BadConfig, RuntimeValuesOfTheWrongTypeOrOutOfRange) {
  expectStartupError({"status_interval_s = often\n", "", "deadreckoning",
                      ":4 [runtime] status_interval_s: expected a number, got 'often'"});
  expectStartupError({"max_odometry_gap_s = -1\n", "", "deadreckoning",
                      ":4 [runtime] max_odometry_gap_s: expected a value >= 0, got '-1'"});
  expectStartupError({"trajectory_interval_s = nan\n", "", "deadreckoning",
                      ":4 [runtime] trajectory_interval_s: expected a number, got 'nan'"});
  expectStartupError({"range_channel =\n", "", "deadreckoning",
                      ":4 [runtime] range_channel: expected a non-empty value, got ''"});
}

TEST(BadConfig, MaxRangeOfTheWrongTypeOrOutOfRangeInEveryPlugin) {
  for (const auto& plugin : pluginsInBuild()) {
    SCOPED_TRACE("plugin " + plugin);
    expectStartupError({"", "max_range_m = far\n", plugin,
                        ":6 [estimator." + plugin + "] max_range_m: expected a number, got 'far'"});
    expectStartupError({"", "max_range_m = 0\n", plugin,
                        ":6 [estimator." + plugin + "] max_range_m: expected a value > 0, got '0'"});
    expectStartupError({"", "max_range_m = inf\n", plugin,
                        ":6 [estimator." + plugin + "] max_range_m: expected a number, got 'inf'"});
  }
}

TEST(BadConfig, MaxStepOfTheWrongTypeOrOutOfRange) {
  expectStartupError({"", "max_speed_mps = -3\n", "deadreckoning",
                      ":6 [estimator.deadreckoning] max_speed_mps: expected a value > 0, got '-3'"});
  expectStartupError({"", "max_speed_mps = 3 m\n", "deadreckoning",
                      ":6 [estimator.deadreckoning] max_speed_mps: expected a number, got '3 m'"});
}

}  // namespace
}  // namespace hardening
}  // namespace roam
