// Helpers for the tools' tests: a scratch folder, writing small files, running a tool.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace roam_test {

// A fresh folder under the test's temporary directory, removed at the end.
class ScratchDir {
 public:
  ScratchDir() {
    std::string pattern = (std::filesystem::temp_directory_path() / "roam-tools-XXXXXX").string();
    path_ = ::mkdtemp(pattern.data()) ? pattern : "";
  }
  ~ScratchDir() {
    std::error_code ignored;
    if (!path_.empty()) std::filesystem::remove_all(path_, ignored);
  }
  const std::string& path() const { return path_; }
  std::string file(const std::string& name) const { return path_ + "/" + name; }
  void write(const std::string& name, const std::string& text) const {
    std::ofstream(file(name), std::ios::binary) << text;
  }

 private:
  std::string path_;
};

struct ToolResult {
  int status = -1;
  std::string out;  // stdout and stderr
};

inline ToolResult runTool(const std::string& command_line) {
  ToolResult result;
  FILE* pipe = ::popen((command_line + " 2>&1").c_str(), "r");
  if (!pipe) return result;
  std::array<char, 4096> buffer;
  size_t n;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0) result.out.append(buffer.data(), n);
  const int status = ::pclose(pipe);
  result.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

inline std::string tool(const std::string& name) { return std::string(ROAM_BINARY_DIR) + "/bin/" + name; }

}  // namespace roam_test

// The project's real data (Plaza 1, GOATS 16) ships in the repository's data/ folder: a test
// that reads it fails, naming the file, if it is missing.
#define ROAM_REQUIRE_DATA(path) \
  ASSERT_TRUE(std::filesystem::exists(path)) << "no " << (path) << " (the repository's data/ folder)"
