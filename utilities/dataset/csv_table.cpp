#include "csv_table.hpp"

#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <stdexcept>

namespace roam {
namespace {

std::string trim(const std::string& text) {
  const char* space = " \t\r\n";
  const size_t first = text.find_first_not_of(space);
  if (first == std::string::npos) return "";
  const size_t last = text.find_last_not_of(space);
  return text.substr(first, last - first + 1);
}

std::vector<std::string> splitFields(const std::string& line) {
  std::vector<std::string> fields;
  size_t begin = 0;
  while (true) {
    const size_t comma = line.find(',', begin);
    fields.push_back(trim(line.substr(begin, comma == std::string::npos ? std::string::npos : comma - begin)));
    if (comma == std::string::npos) break;
    begin = comma + 1;
  }
  return fields;
}

}  // namespace

CsvTable::CsvTable(const std::string& path) : path_(path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot open (" + std::strerror(errno) + ")");
  std::string line;
  int line_number = 0;
  bool have_header = false;
  while (std::getline(in, line)) {
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (trim(line).empty()) continue;  // blank lines (e.g. a trailing one) carry nothing
    std::vector<std::string> fields = splitFields(line);
    if (!have_header) {
      header_ = std::move(fields);
      have_header = true;
      continue;
    }
    if (fields.size() < header_.size()) {
      throw std::runtime_error(path + ":" + std::to_string(line_number) + ": expected " +
                               std::to_string(header_.size()) + " fields as in the header, got " +
                               std::to_string(fields.size()));
    }
    rows_.push_back(Row{line_number, std::move(fields)});
  }
  if (!have_header) throw std::runtime_error(path + ":1: empty file (expected a header line)");
}

bool CsvTable::hasColumn(const std::string& name) const {
  for (const auto& h : header_) {
    if (h == name) return true;
  }
  return false;
}

size_t CsvTable::column(const std::string& name) const {
  for (size_t i = 0; i < header_.size(); ++i) {
    if (header_[i] == name) return i;
  }
  std::string names;
  for (const auto& h : header_) names += (names.empty() ? "" : ", ") + h;
  throw std::runtime_error(path_ + ":1: missing column '" + name + "' (header: " + names + ")");
}

std::string CsvTable::where(size_t row, size_t column) const {
  return path_ + ":" + std::to_string(rows_[row].line) + ": column '" + header_[column] + "': ";
}

const std::string& CsvTable::text(size_t row, size_t column) const {
  return rows_[row].fields[column];
}

double CsvTable::number(size_t row, size_t column) const {
  const std::string& field = text(row, column);
  char* end = nullptr;
  errno = 0;
  const double value = field.empty() ? 0.0 : std::strtod(field.c_str(), &end);
  if (field.empty() || end != field.c_str() + field.size() || errno == ERANGE || !std::isfinite(value)) {
    throw std::runtime_error(where(row, column) + "expected a number, got '" + field + "'");
  }
  return value;
}

int CsvTable::integer(size_t row, size_t column) const {
  const std::string& field = text(row, column);
  char* end = nullptr;
  errno = 0;
  const long value = field.empty() ? 0 : std::strtol(field.c_str(), &end, 10);
  if (field.empty() || end != field.c_str() + field.size() || errno == ERANGE || value < INT_MIN ||
      value > INT_MAX) {
    throw std::runtime_error(where(row, column) + "expected an integer, got '" + field + "'");
  }
  return static_cast<int>(value);
}

}  // namespace roam
