// roam::Options: typed plugin options whose errors name the key and the broken constraint.
#include "roam/options.hpp"
#include "roam/sensor_noise.hpp"

#include <gtest/gtest.h>

#include <limits>

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

TEST(Options, ASharedValueIsADefaultForADeclaredKeyOnly) {
  // "sensors.<key>" (the runtime's [sensors]): taken by a declared key that the values do not set
  // themselves, wherever it stands; skipped, not refused, where the key is not declared.
  double range_sigma_m = 0.5, bearing_sigma_rad = 0.05;
  Options options({{"sensors.range_sigma_m", "0.7"}, {"bearing_sigma_rad", "0.1"}, {"sensors.bearing_sigma_rad", "0.2"},
                   {"sensors.odo_distance_sigma_m", "0.01"}});
  options.add("range_sigma_m", &range_sigma_m, "").min(0.0, false);
  options.add("bearing_sigma_rad", &bearing_sigma_rad, "");
  options.parse();
  EXPECT_EQ(range_sigma_m, 0.7);
  EXPECT_EQ(bearing_sigma_rad, 0.1);
  EXPECT_TRUE(options.given("range_sigma_m"));
  EXPECT_FALSE(options.given("odo_distance_sigma_m"));
  // Its checks are the key's own.
  Options bad(KeyValues{{"sensors.range_sigma_m", "-1"}});
  bad.add("range_sigma_m", &range_sigma_m, "").min(0.0, false);
  try {
    bad.parse();
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.key(), "range_sigma_m");
  }
}

TEST(Options, PositiveOdometryFloorsAreCheckedWhereTheModelWeighsBySigma) {
  // kPositive (spectral, spectral + batch: a smoother that divides by each step's sigma) refuses
  // a zero floor, naming both keys; kMayBeZero (the filters) takes it.
  for (const char* key : {"odo_distance_sigma_m", "odo_heading_sigma_rad"}) {
    SensorNoise weighed;
    Options strict(KeyValues{{key, "0"}});
    addSensorNoiseOptions(strict, &weighed, OdometryFloors::kPositive);
    try {
      strict.parse();
      FAIL() << key << ": no error";
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find("odo_distance_sigma_m > 0 and odo_heading_sigma_rad > 0"), std::string::npos) << e.what();
    }
    SensorNoise filtered;
    Options lenient(KeyValues{{key, "0"}});
    addSensorNoiseOptions(lenient, &filtered);
    lenient.parse();
    EXPECT_EQ(filtered.odo_distance_sigma_m * filtered.odo_heading_sigma_rad, 0.0);
  }
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

enum class Anchor { kBeacons, kStartPose };

struct RangeConfig {
  Anchor anchor = Anchor::kBeacons;
  int min_ranges = 6;
  int max_ranges = 200;
  double sigma_m = 0.5;
};

// The one declaration of RangeConfig's keys: each option's checks and one across keys.
void addRangeOptions(Options& o, RangeConfig* c) {
  o.add("anchor", &c->anchor, {{"beacons", Anchor::kBeacons}, {"start_pose", Anchor::kStartPose}}, "frame");
  o.add("min_ranges", &c->min_ranges, "ranges before initialising").min(3);
  o.add("max_ranges", &c->max_ranges, "ranges buffered").min(3);
  o.add("sigma_m", &c->sigma_m, "range sigma").min(0.0, false);
  o.require([c] { return c->max_ranges >= c->min_ranges; }, {"max_ranges", "min_ranges"},
            "max_ranges >= min_ranges");
}

std::string rangeError(const KeyValues& values, RangeConfig* config = nullptr) {
  RangeConfig local;
  Options options(values);
  addRangeOptions(options, config ? config : &local);
  try {
    options.parse();
  } catch (const ConfigError& error) {
    return error.key() + ": " + error.what();
  }
  return "";
}

TEST(Options, EnumsAreParsedOnceFromTheirNamesAndPrintedByName) {
  RangeConfig config;
  EXPECT_EQ(rangeError({{"anchor", "start_pose"}}, &config), "");
  EXPECT_EQ(config.anchor, Anchor::kStartPose);
  EXPECT_EQ(rangeError({{"anchor", "start-pose"}}),
            "anchor: expected one of beacons | start_pose (did you mean 'start_pose'?), got 'start-pose'");
  EXPECT_EQ(rangeError({{"anchor", "4"}}), "anchor: expected one of beacons | start_pose, got '4'");
  Options options(KeyValues{{"anchor", "start_pose"}});
  addRangeOptions(options, &config);
  options.parse();
  EXPECT_EQ(options.effective().front(), (std::pair<std::string, std::string>{"anchor", "start_pose"}));
}

TEST(Options, ACrossKeyConstraintNamesTheKeyTheConfigGave) {
  EXPECT_EQ(rangeError({{"max_ranges", "5"}}),
            "max_ranges: expected max_ranges >= min_ranges, got max_ranges = 5, min_ranges = 6");
  EXPECT_EQ(rangeError({{"min_ranges", "300"}}),
            "min_ranges: expected max_ranges >= min_ranges, got max_ranges = 200, min_ranges = 300");
  EXPECT_EQ(rangeError({{"min_ranges", "10"}, {"max_ranges", "10"}}), "");
  // Each key's own check comes first.
  EXPECT_EQ(rangeError({{"min_ranges", "2"}}), "min_ranges: expected a value >= 3, got '2'");
}

// checkConfig: a struct built in code (not from a file) meets the same declared checks.
std::string checkError(const RangeConfig& config) {
  try {
    checkConfig(config, addRangeOptions);
  } catch (const ConfigError& error) {
    return error.key() + " | " + error.what();
  }
  return "";
}

TEST(Options, CheckConfigRunsTheDeclaredChecksOverAStructsValues) {
  RangeConfig config;
  EXPECT_EQ(checkError(config), "");
  config.sigma_m = 0.0;
  EXPECT_EQ(checkError(config), "sigma_m | sigma_m: expected a value > 0, got '0'");
  config.sigma_m = std::numeric_limits<double>::infinity();
  EXPECT_EQ(checkError(config), "sigma_m | sigma_m: expected a finite number, got 'inf'");
  config = RangeConfig{};
  config.max_ranges = 4;
  EXPECT_EQ(checkError(config),
            "max_ranges | max_ranges: expected max_ranges >= min_ranges, got max_ranges = 4, min_ranges = 6");
  config = RangeConfig{};
  config.anchor = static_cast<Anchor>(7);
  EXPECT_EQ(checkError(config),
            "anchor | anchor: expected one of beacons | start_pose, got '(not a named value)'");
}

}  // namespace
}  // namespace roam
