// Typed, validated options for a plugin's config section.
//
//   roam::Options opts(key_values);
//   opts.add("rank", &config.rank, "rank of the factorisation").oneOf({4, 7});
//   opts.add("window_s", &config.window_s, "interpolation window").min(1.0);
//   opts.parse();   // throws roam::ConfigError naming the key and the broken constraint
//
// Unknown keys are rejected with a "did you mean" hint. effective() lists every option with
// its value after parsing (defaults included), for `roam-run --print-config`.
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

   private:
    friend class Options;
    std::string key_;
    std::string help_;
    std::string type_name_;
    std::function<bool(const std::string&)> parse_;  // false: not a valid value of the type
    std::function<double()> numeric_;                // current value as a number (numeric types)
    std::function<std::string()> print_;
    std::vector<std::function<std::string()>> checks_;  // "" if fine, else what is expected
  };

  explicit Options(KeyValues values) : values_(std::move(values)) {}

  Option& add(const std::string& key, double* target, const std::string& help);
  Option& add(const std::string& key, int* target, const std::string& help);
  Option& add(const std::string& key, bool* target, const std::string& help);
  Option& add(const std::string& key, std::string* target, const std::string& help);

  // Assigns every given value, runs every check; throws ConfigError on the first problem.
  void parse();
  // True if the key was given in the config (after parse()).
  bool given(const std::string& key) const;
  // Every option as key = value (defaults included), in the order added, as they were at the
  // end of parse() (the targets may be gone by the time this is asked).
  KeyValues effective() const;

 private:
  Option& insert(std::unique_ptr<Option> option);
  KeyValues values_;
  std::vector<std::unique_ptr<Option>> options_;
  std::vector<std::string> given_;
  KeyValues effective_;
  bool parsed_ = false;
};

}  // namespace roam
