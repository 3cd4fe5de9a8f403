// A minimal XML scanner for the plot tests: checks that tags balance and collects every element
// with its attributes, and the text inside <text> elements. Enough for the SVG roam-plot writes
// (no CDATA, no entities beyond the five XML ones, which are kept as written).
#pragma once

#include <map>
#include <string>
#include <vector>

namespace roam_test {

struct Element {
  std::string name;
  std::map<std::string, std::string> attributes;
  std::string text;  // character data directly inside (for <text> and <title>)
};

struct ScanResult {
  bool balanced = false;
  std::string problem;
  std::vector<Element> elements;  // in document order
  std::string root;
};

inline ScanResult scanXml(const std::string& xml) {
  ScanResult result;
  std::vector<size_t> open;  // indexes into elements
  size_t i = 0;
  while (i < xml.size()) {
    if (xml[i] != '<') {
      const size_t next = xml.find('<', i);
      const std::string chars = xml.substr(i, next == std::string::npos ? std::string::npos : next - i);
      if (!open.empty()) result.elements[open.back()].text += chars;
      if (chars.find('>') != std::string::npos) { result.problem = "stray '>'"; return result; }
      i = next == std::string::npos ? xml.size() : next;
      continue;
    }
    if (xml.compare(i, 2, "<?") == 0) { i = xml.find("?>", i) + 2; continue; }
    if (xml.compare(i, 4, "<!--") == 0) { i = xml.find("-->", i) + 3; continue; }
    // Find the tag's end outside quoted attribute values.
    size_t end = i + 1;
    char quote = 0;
    for (; end < xml.size(); ++end) {
      if (quote) { if (xml[end] == quote) quote = 0; }
      else if (xml[end] == '"' || xml[end] == '\'') quote = xml[end];
      else if (xml[end] == '<') { result.problem = "'<' inside a tag"; return result; }
      else if (xml[end] == '>') break;
    }
    if (end >= xml.size()) { result.problem = "unterminated tag"; return result; }
    std::string tag = xml.substr(i + 1, end - i - 1);
    i = end + 1;
    if (tag[0] == '/') {
      const std::string name = tag.substr(1);
      if (open.empty() || result.elements[open.back()].name != name) {
        result.problem = "</" + name + "> does not close the open element";
        return result;
      }
      open.pop_back();
      continue;
    }
    const bool self_closing = tag.back() == '/';
    if (self_closing) tag.pop_back();
    Element e;
    size_t p = tag.find_first_of(" \t\n");
    e.name = tag.substr(0, p);
    while (p != std::string::npos && p < tag.size()) {
      p = tag.find_first_not_of(" \t\n", p);
      if (p == std::string::npos) break;
      const size_t eq = tag.find('=', p);
      if (eq == std::string::npos || eq + 1 >= tag.size() || tag[eq + 1] != '"') {
        result.problem = "bad attribute in <" + e.name + ">";
        return result;
      }
      const size_t close = tag.find('"', eq + 2);
      if (close == std::string::npos) { result.problem = "unterminated attribute"; return result; }
      e.attributes[tag.substr(p, eq - p)] = tag.substr(eq + 2, close - eq - 2);
      p = close + 1;
    }
    if (result.elements.empty() && open.empty()) result.root = e.name;
    else if (open.empty()) { result.problem = "a second root element <" + e.name + ">"; return result; }
    result.elements.push_back(e);
    if (!self_closing) open.push_back(result.elements.size() - 1);
  }
  if (!open.empty()) { result.problem = "<" + result.elements[open.back()].name + "> is never closed"; return result; }
  result.balanced = !result.root.empty();
  if (!result.balanced) result.problem = "no root element";
  return result;
}

}  // namespace roam_test
