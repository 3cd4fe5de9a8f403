// roam::Options: typed plugin options whose errors name the key and the broken constraint.
#include "roam/options.hpp"

#include <gtest/gtest.h>

namespace roam {
namespace {

struct Config {
  int rank = 7;
  double window_s = 20.0;
  bool calibrate = true;
  std::string anchor = "beacons";
};

// Parses `values` into a Config; returns "" or "key: message".
std::string parseError(const KeyValues& values, Config* config = nullptr) {
  Config local;
  Config& c = config ? *config : local;
  Options options(values);
  options.add("rank", &c.rank, "rank").oneOf({4, 7});
  options.add("window_s", &c.window_s, "window").min(0.0, false);
  options.add("calibrate", &c.calibrate, "estimate range scale");
  options.add("anchor", &c.anchor, "anchor").oneOf({"beacons", "start_pose"});
  try {
    options.parse();
  } catch (const ConfigError& error) {
    return error.key() + ": " + error.what();
  }
  return "";
}

TEST(Options, DefaultsAndGivenValues) {
  Config config;
  EXPECT_EQ(parseError({{"rank", "4"}, {"window_s", "2.5"}, {"calibrate", "false"}}, &config), "");
  EXPECT_EQ(config.rank, 4);
  EXPECT_DOUBLE_EQ(config.window_s, 2.5);
  EXPECT_FALSE(config.calibrate);
  EXPECT_EQ(config.anchor, "beacons");
}

TEST(Options, ErrorsNameTheKeyAndWhatWasExpected) {
  EXPECT_EQ(parseError({{"rank", "5"}}), "rank: expected one of 4 | 7, got '5'");
  EXPECT_EQ(parseError({{"rank", "four"}}), "rank: expected an integer, got 'four'");
  EXPECT_EQ(parseError({{"rank", "4.5"}}), "rank: expected an integer, got '4.5'");
  EXPECT_EQ(parseError({{"window_s", "0"}}), "window_s: expected a value > 0, got '0'");
  EXPECT_EQ(parseError({{"window_s", "nan"}}), "window_s: expected a number, got 'nan'");
  EXPECT_EQ(parseError({{"calibrate", "maybe"}}), "calibrate: expected true or false, got 'maybe'");
  EXPECT_EQ(parseError({{"anchor", "start-pose"}}),
            "anchor: expected one of beacons | start_pose (did you mean 'start_pose'?), got 'start-pose'");
  EXPECT_EQ(parseError({{"rnak", "4"}}), "rnak: unknown key 'rnak' (did you mean 'rank'?)");
  EXPECT_EQ(parseError({{"zzzzzz", "4"}}), "zzzzzz: unknown key 'zzzzzz'");
}

TEST(Options, EffectiveListsEveryOptionWithDefaults) {
  Config config;
  Options options(KeyValues{{"rank", "4"}});
  options.add("rank", &config.rank, "rank").oneOf({4, 7});
  options.add("window_s", &config.window_s, "window");
  options.parse();
  const KeyValues expected = {{"rank", "4"}, {"window_s", "20"}};
  EXPECT_EQ(options.effective(), expected);
  EXPECT_TRUE(options.given("rank"));
  EXPECT_FALSE(options.given("window_s"));
}

}  // namespace
}  // namespace roam
