// Typed, validated options for a plugin's config section.
//
//   roam::Options opts(key_values);
//   opts.add("rank", &config.rank, "rank of the factorisation").oneOf({4, 7});
//   opts.add("window_s", &config.window_s, "interpolation window").min(1.0);
//   opts.add("anchor", &config.anchor, {{"beacons", Anchor::kBeacons}, {"start_pose", Anchor::kStartPose}},
//            "frame anchor");                      // an enum, parsed once from its names
//   opts.require([&] { return config.b >= config.a; }, {"b", "a"}, "b >= a");  // across keys
//   opts.parse();   // throws roam::ConfigError naming the key and the broken constraint
//
// The declaration is the only validator: a core built from a config struct (not from a config
// file) runs the same checks with checkConfig(config, addXOptions), which parses no keys and so
// checks the struct's own values. Unknown keys are rejected with a "did you mean" hint.
// effective() lists every option with its value after parsing (defaults included), for
// `roam-run --print-config`.
#pragma once

#include <functional>
#include <initializer_list>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace roam {

using KeyValues = std::vector<std::pair<std::string, std::string>>;

class ConfigError : public std::runtime_error {
 public:
  ConfigError(std::string key, const std::string& message)
      : std::runtime_error(message), key_(std::move(key)) {}
  const std::string& key() const { return key_; }

 private:
  std::string key_;
};

// The closest candidate within a small edit distance, or "".
std::string closestMatch(const std::string& word, const std::vector<std::string>& candidates);

class Options {
 public:
  // One option: its parser and checks. Returned by add() so checks can be chained.
  class Option {
   public:
    Option& min(double lower, bool inclusive = true);
    Option& max(double upper, bool inclusive = true);
    Option& oneOf(std::vector<std::string> choices);
    Option& oneOf(std::initializer_list<int> choices);
    Option& nonEmpty();  // a string that may not be ""

   private:
    friend class Options;
    std::string key_;
    std::string help_;
    std::string type_name_;
    std::function<bool(const std::string&)> parse_;  // false: not a valid value of the type
    std::function<double()> numeric_;                // current value as a number (numeric types)
    std::function<std::string()> print_;
    std::function<std::string(const std::string&)> hint_;  // after a bad value: " (did you mean ..)"
    std::vector<std::function<std::string()>> checks_;  // "" if fine, else what is expected
  };

  template <typename Enum>
  using Names = std::vector<std::pair<std::string, Enum>>;

  explicit Options(KeyValues values) : values_(std::move(values)) {}

  // A value keyed "sensors.<key>" is a shared default (the runtime's [sensors] section,
  // roam/sensor_noise.hpp): parse() gives it to a declared <key> that the values do not set
  // themselves, and skips it where <key> is not declared.
  static constexpr const char* kSharedPrefix = "sensors.";

  Option& add(const std::string& key, double* target, const std::string& help);
  Option& add(const std::string& key, int* target, const std::string& help);
  Option& add(const std::string& key, bool* target, const std::string& help);
  Option& add(const std::string& key, std::string* target, const std::string& help);
  // An enum option (or any value with a name table, e.g. a bool spelt none | process): the
  // config gives one of the names, the target holds its value, and effective() prints the name.
  template <typename Enum>
  Option& add(const std::string& key, Enum* target, Names<Enum> names, const std::string& help) {
    std::vector<std::string> labels;
    for (const auto& entry : names) labels.push_back(entry.first);
    return addNamed(
        key, help, labels,
        [target, names](size_t index) { *target = names[index].second; },
        [target, names]() -> int {
          for (size_t i = 0; i < names.size(); ++i)
            if (names[i].second == *target) return static_cast<int>(i);
          return -1;
        });
  }

  // A constraint across keys, checked after every option's own: throws ConfigError naming the
  // first of `keys` the config gave (else the first), "expected <constraint>, got k1 = v1, ...".
  Options& require(std::function<bool()> holds, std::vector<std::string> keys, std::string constraint);

  // Assigns every given value, runs every check; throws ConfigError on the first problem.
  void parse();
  // True if the key was given in the config (after parse()).
  bool given(const std::string& key) const;
  // The keys declared so far, in the order added.
  std::vector<std::string> keys() const;
  // Every option as key = value (defaults included), in the order added, as they were at the
  // end of parse() (the targets may be gone by the time this is asked).
  KeyValues effective() const;

 private:
  struct Requirement {
    std::function<bool()> holds;
    std::vector<std::string> keys;
    std::string constraint;
  };
  Option& insert(std::unique_ptr<Option> option);
  Option& addNamed(const std::string& key, const std::string& help, std::vector<std::string> names,
                   std::function<void(size_t)> set, std::function<int()> get);
  std::string printed(const std::string& key) const;
  KeyValues values_;
  std::vector<Requirement> requirements_;
  std::vector<std::unique_ptr<Option>> options_;
  std::vector<std::string> given_;
  KeyValues effective_;
  bool parsed_ = false;
};

// Runs the checks `declare` registers (declare(Options&, Config*), the function the plugin shim
// uses) over `config`'s own values; throws ConfigError whose message starts with the key.
// For cores built from a struct: the declaration stays the only validator.
template <typename Config, typename Declare>
void checkConfig(const Config& config, Declare&& declare) {
  Config copy = config;
  Options options{KeyValues{}};
  declare(options, &copy);
  try {
    options.parse();
  } catch (const ConfigError& error) {
    throw ConfigError(error.key(), error.key() + ": " + error.what());
  }
}

// Sets `values` on `config` through the same declaration (as a config section would), e.g. in a
// test: setOptions(&config, addXOptions, {{"loss", "cauchy"}}). Throws ConfigError.
template <typename Config, typename Declare>
void setOptions(Config* config, Declare&& declare, KeyValues values) {
  Options options(std::move(values));
  declare(options, config);
  options.parse();
}

}  // namespace roam
