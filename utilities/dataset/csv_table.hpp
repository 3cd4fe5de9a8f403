// A small CSV reader for the roam data layout: one header line naming the columns (any order,
// extra columns ignored), comma-separated fields, LF or CRLF line endings, no quoting.
// Every error is a std::runtime_error that names the file, the line and the column.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace roam {

class CsvTable {
 public:
  // Reads the whole file; throws "<path>: cannot open ..." or "<path>:1: empty file (...)".
  explicit CsvTable(const std::string& path);

  const std::string& path() const { return path_; }
  size_t rows() const { return rows_.size(); }
  // 1-based line number of data row `row` in the file (the header is line 1).
  int line(size_t row) const { return rows_[row].line; }

  bool hasColumn(const std::string& name) const;
  // The field index of a column; throws "<path>:1: missing column 'name' (header: a, b, c)".
  size_t column(const std::string& name) const;

  // A finite double; throws "<path>:<line>: column 'name': expected a number, got 'text'".
  double number(size_t row, size_t column) const;
  // An integer (int32 range); throws like number() with "expected an integer".
  int integer(size_t row, size_t column) const;
  const std::string& text(size_t row, size_t column) const;

  // "<path>:<line>: column '<name>': " — the prefix of an error about one field.
  std::string where(size_t row, size_t column) const;

 private:
  struct Row {
    int line = 0;
    std::vector<std::string> fields;
  };
  std::string path_;
  std::vector<std::string> header_;
  std::vector<Row> rows_;
};

}  // namespace roam
