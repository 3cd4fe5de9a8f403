// Helpers for the runtime tests: temporary files and running roam-run as a user would.
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

namespace roam {
namespace testing_util {

// A fresh folder under the build tree's tests/ for one test.
// Named for the test as well: ctest runs tests in parallel, one process each, and two tests that
// share a helper (and so a name) must not remove each other's files.
inline std::filesystem::path scratchDir(const std::string& name) {
  const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::string folder = test == nullptr ? name : name + "." + test->test_suite_name() + "." + test->name();
  const auto dir = std::filesystem::path(ROAM_BINARY_DIR) / "tests" / "scratch" / folder;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

inline std::filesystem::path writeFile(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path) << text;
  return path;
}

struct CommandResult {
  int status = -1;     // exit status
  std::string output;  // stdout and stderr together
};

// Runs a shell command, capturing stdout and stderr.
inline CommandResult run(const std::string& command) {
  CommandResult result;
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (pipe == nullptr) return result;
  std::array<char, 4096> buffer{};
  size_t n = 0;
  while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0) result.output.append(buffer.data(), n);
  const int raw = pclose(pipe);
  result.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw);
  return result;
}

inline std::string roamRun() { return std::string(ROAM_BINARY_DIR) + "/bin/roam-run"; }

}  // namespace testing_util
}  // namespace roam
