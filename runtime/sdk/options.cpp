#include "roam/options.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <sstream>

namespace roam {
namespace {

// The shortest text that parses back to the same double.
std::string formatDouble(double value) {
  char text[64];
  const auto result = std::to_chars(text, text + sizeof(text), value);
  return std::string(text, result.ptr);
}

size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

std::string trim(const std::string& text) {
  const auto begin = text.find_first_not_of(" \t\r\n");
  if (begin == std::string::npos) return "";
  const auto end = text.find_last_not_of(" \t\r\n");
  return text.substr(begin, end - begin + 1);
}

}  // namespace

std::string closestMatch(const std::string& word, const std::vector<std::string>& candidates) {
  std::string best;
  size_t best_distance = std::max<size_t>(2, word.size() / 3) + 1;
  for (const auto& candidate : candidates) {
    const size_t distance = editDistance(word, candidate);
    if (distance < best_distance) {
      best_distance = distance;
      best = candidate;
    }
  }
  return best;
}

Options::Option& Options::Option::min(double lower, bool inclusive) {
  auto numeric = numeric_;
  checks_.push_back([numeric, lower, inclusive]() -> std::string {
    const double value = numeric();
    if (inclusive ? value >= lower : value > lower) return "";
    return std::string("a value ") + (inclusive ? ">= " : "> ") + formatDouble(lower);
  });
  return *this;
}

Options::Option& Options::Option::max(double upper, bool inclusive) {
  auto numeric = numeric_;
  checks_.push_back([numeric, upper, inclusive]() -> std::string {
    const double value = numeric();
    if (inclusive ? value <= upper : value < upper) return "";
    return std::string("a value ") + (inclusive ? "<= " : "< ") + formatDouble(upper);
  });
  return *this;
}

Options::Option& Options::Option::oneOf(std::vector<std::string> choices) {
  auto print = print_;
  const bool hint_spelling = type_name_ == "a string";
  checks_.push_back([print, choices, hint_spelling]() -> std::string {
    const std::string value = print();
    if (std::find(choices.begin(), choices.end(), value) != choices.end()) return "";
    std::string expected = "one of";
    for (size_t i = 0; i < choices.size(); ++i) expected += (i ? " | " : " ") + choices[i];
    const std::string hint = hint_spelling ? closestMatch(value, choices) : "";
    if (!hint.empty()) expected += " (did you mean '" + hint + "'?)";
    return expected;
  });
  return *this;
}

Options::Option& Options::Option::oneOf(std::initializer_list<int> choices) {
  std::vector<std::string> names;
  for (int choice : choices) names.push_back(std::to_string(choice));
  return oneOf(names);
}

Options::Option& Options::Option::nonEmpty() {
  auto print = print_;
  checks_.push_back([print]() -> std::string { return print().empty() ? "a non-empty value" : ""; });
  return *this;
}

Options::Option& Options::addNamed(const std::string& key, const std::string& help,
                                   std::vector<std::string> names, std::function<void(size_t)> set,
                                   std::function<int()> get) {
  auto option = std::make_unique<Option>();
  option->key_ = key;
  option->help_ = help;
  option->type_name_ = "one of";
  for (size_t i = 0; i < names.size(); ++i) option->type_name_ += (i ? " | " : " ") + names[i];
  option->parse_ = [names, set](const std::string& text) {
    const auto it = std::find(names.begin(), names.end(), text);
    if (it == names.end()) return false;
    set(static_cast<size_t>(it - names.begin()));
    return true;
  };
  option->numeric_ = [get] { return static_cast<double>(get()); };
  option->print_ = [names, get] {
    const int index = get();
    return index < 0 ? std::string("(not a named value)") : names[static_cast<size_t>(index)];
  };
  option->hint_ = [names](const std::string& text) {
    const std::string hint = closestMatch(text, names);
    return hint.empty() ? std::string() : " (did you mean '" + hint + "'?)";
  };
  const std::string expected = option->type_name_;
  option->checks_.push_back([get, expected]() -> std::string { return get() < 0 ? expected : ""; });
  return insert(std::move(option));
}

Options& Options::require(std::function<bool()> holds, std::vector<std::string> keys,
                          std::string constraint) {
  requirements_.push_back(Requirement{std::move(holds), std::move(keys), std::move(constraint)});
  return *this;
}

std::string Options::printed(const std::string& key) const {
  for (const auto& option : options_) {
    if (option->key_ == key) return option->print_();
  }
  return "?";
}

Options::Option& Options::insert(std::unique_ptr<Option> option) {
  options_.push_back(std::move(option));
  return *options_.back();
}

Options::Option& Options::add(const std::string& key, double* target, const std::string& help) {
  auto option = std::make_unique<Option>();
  option->key_ = key;
  option->help_ = help;
  option->type_name_ = "a number";
  option->parse_ = [target](const std::string& text) {
    try {
      size_t used = 0;
      const double value = std::stod(text, &used);
      if (used != text.size() || !std::isfinite(value)) return false;
      *target = value;
      return true;
    } catch (const std::exception&) {
      return false;
    }
  };
  option->numeric_ = [target] { return *target; };
  option->print_ = [target] { return formatDouble(*target); };
  // A value from a config file is finite by parsing; one set in a struct is checked here.
  option->checks_.push_back([target]() -> std::string {
    return std::isfinite(*target) ? "" : "a finite number";
  });
  return insert(std::move(option));
}

Options::Option& Options::add(const std::string& key, int* target, const std::string& help) {
  auto option = std::make_unique<Option>();
  option->key_ = key;
  option->help_ = help;
  option->type_name_ = "an integer";
  option->parse_ = [target](const std::string& text) {
    try {
      size_t used = 0;
      const long value = std::stol(text, &used);
      if (used != text.size() || value < std::numeric_limits<int>::min() ||
          value > std::numeric_limits<int>::max())
        return false;
      *target = static_cast<int>(value);
      return true;
    } catch (const std::exception&) {
      return false;
    }
  };
  option->numeric_ = [target] { return static_cast<double>(*target); };
  option->print_ = [target] { return std::to_string(*target); };
  return insert(std::move(option));
}

Options::Option& Options::add(const std::string& key, bool* target, const std::string& help) {
  auto option = std::make_unique<Option>();
  option->key_ = key;
  option->help_ = help;
  option->type_name_ = "true or false";
  option->parse_ = [target](const std::string& text) {
    if (text == "true" || text == "1" || text == "yes" || text == "on") {
      *target = true;
      return true;
    }
    if (text == "false" || text == "0" || text == "no" || text == "off") {
      *target = false;
      return true;
    }
    return false;
  };
  option->numeric_ = [target] { return *target ? 1.0 : 0.0; };
  option->print_ = [target] { return std::string(*target ? "true" : "false"); };
  return insert(std::move(option));
}

Options::Option& Options::add(const std::string& key, std::string* target,
                              const std::string& help) {
  auto option = std::make_unique<Option>();
  option->key_ = key;
  option->help_ = help;
  option->type_name_ = "a string";
  option->parse_ = [target](const std::string& text) {
    *target = text;
    return true;
  };
  option->numeric_ = [] { return 0.0; };
  option->print_ = [target] { return *target; };
  return insert(std::move(option));
}

void Options::parse() {
  std::vector<std::string> known;
  for (const auto& option : options_) known.push_back(option->key_);
  // A shared value ("sensors.<key>", roam/sensor_noise.hpp) is a default that a declared <key>
  // takes unless the section sets <key> itself; an undeclared one is not this plugin's to read.
  const std::string shared_prefix = kSharedPrefix;
  std::vector<std::string> plain;
  for (const auto& entry : values_) plain.push_back(trim(entry.first));
  for (const auto& [raw_key, raw_value] : values_) {
    std::string key = trim(raw_key);
    const std::string value = trim(raw_value);
    const bool shared = key.compare(0, shared_prefix.size(), shared_prefix) == 0;
    if (shared) {
      key = key.substr(shared_prefix.size());
      if (std::find(known.begin(), known.end(), key) == known.end() ||
          std::find(plain.begin(), plain.end(), key) != plain.end())
        continue;
    }
    auto it = std::find_if(options_.begin(), options_.end(),
                           [&](const auto& option) { return option->key_ == key; });
    if (it == options_.end()) {
      std::string message = "unknown key '" + key + "'";
      const std::string hint = closestMatch(key, known);
      if (!hint.empty()) message += " (did you mean '" + hint + "'?)";
      throw ConfigError(key, message);
    }
    if (!(*it)->parse_(value)) {
      const std::string hint = (*it)->hint_ ? (*it)->hint_(value) : "";
      throw ConfigError(key, "expected " + (*it)->type_name_ + hint + ", got '" + value + "'");
    }
    given_.push_back(key);
  }
  for (const auto& option : options_) {
    for (const auto& check : option->checks_) {
      const std::string expected = check();
      if (!expected.empty()) {
        throw ConfigError(option->key_,
                          "expected " + expected + ", got '" + option->print_() + "'");
      }
    }
  }
  for (const auto& requirement : requirements_) {
    if (requirement.holds()) continue;
    std::string key = requirement.keys.empty() ? "" : requirement.keys.front();
    for (const auto& candidate : requirement.keys) {
      if (given(candidate)) {
        key = candidate;
        break;
      }
    }
    std::string got;
    for (const auto& candidate : requirement.keys)
      got += (got.empty() ? "" : ", ") + candidate + " = " + printed(candidate);
    throw ConfigError(key, "expected " + requirement.constraint + ", got " + got);
  }
  effective_.clear();
  for (const auto& option : options_) effective_.emplace_back(option->key_, option->print_());
  parsed_ = true;
}

bool Options::given(const std::string& key) const {
  return std::find(given_.begin(), given_.end(), key) != given_.end();
}

std::vector<std::string> Options::keys() const {
  std::vector<std::string> out;
  for (const auto& option : options_) out.push_back(option->key_);
  return out;
}

KeyValues Options::effective() const {
  if (parsed_) return effective_;
  KeyValues out;
  for (const auto& option : options_) out.emplace_back(option->key_, option->print_());
  return out;
}

}  // namespace roam
