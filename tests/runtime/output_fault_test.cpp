// The output log's faults: a file that cannot grow, a full disk (a small tmpfs in a private
// mount namespace, never the machine's disk), a folder removed during the run. Each ends the run
// with one line naming the file and exit status 3, and what was written before stays readable.
#include <gtest/gtest.h>

#include "small_world.hpp"
#include "test_util.hpp"

namespace roam {
namespace {

using testing_util::run;
using testing_util::roamRun;
using testing_util::scratchDir;
using testing_util::writeFile;
namespace fs = std::filesystem;

std::string logcheck() { return std::string(ROAM_BINARY_DIR) + "/bin/roam-logcheck"; }

fs::path writeSetup(const fs::path& dir, const std::string& estimators) {
  const fs::path log = testing_util::writeSmallWorldLog(dir);
  return writeFile(dir / "run.ini", "[runtime]\ninput = " + log.string() +
                                        "\nplugin_path = " ROAM_TEST_PLUGIN_DIR "\n" + estimators);
}

const char* const kEstimators = "[estimator.dr]\nplugin = deadreckoning\n[estimator.ekf]\nplugin = ekf\n";

// The last line of roam-run's output must be the one error line; the log must check clean.
void expectStoppedWithReadableLog(const testing_util::CommandResult& result, const fs::path& output,
                                  const std::string& why) {
  EXPECT_EQ(result.status, 3) << result.output;
  EXPECT_NE(result.output.find("roam-run: error: " + output.string() + ": cannot write the output log: " + why +
                               "; the "),
            std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find(" events before it are intact\n"), std::string::npos) << result.output;
}

TEST(OutputFault, AFileThatCannotGrowStopsTheRunAndLeavesWholeEvents) {
  const fs::path dir = scratchDir("output_cannot_grow");
  const fs::path config = writeSetup(dir, kEstimators);
  const fs::path output = dir / "out.lcmlog";
  // ulimit -f: at most 64 KiB per file (the whole result is ~200 KB).
  const auto result = run("bash -c 'ulimit -f 64; exec " + roamRun() + " " + config.string() +
                          " --no-progress --output " + output.string() + "'");
  expectStoppedWithReadableLog(result, output, "File too large");
  EXPECT_LE(fs::file_size(output), 64u * 1024u);
  EXPECT_GT(fs::file_size(output), 60u * 1024u);  // filled up to the last whole event
  const auto check = run(logcheck() + " " + output.string());
  EXPECT_EQ(check.status, 0) << check.output;
}

TEST(OutputFault, AFullDiskStopsTheRunAndLeavesAReadableLog) {
  if (run("unshare -m true").status != 0) GTEST_SKIP() << "unshare -m is not available (needs root)";
  const fs::path dir = scratchDir("output_full_disk");
  const fs::path config = writeSetup(dir, kEstimators);
  const fs::path disk = dir / "disk";
  fs::create_directories(disk);
  const fs::path output = disk / "out.lcmlog";
  // A 64 KiB tmpfs, in a mount namespace of its own: gone when the shell ends.
  const auto result = run("unshare -m sh -c 'mount -t tmpfs -o size=64k roam-test-disk " + disk.string() +
                          " && " + roamRun() + " " + config.string() + " --no-progress --output " + output.string() +
                          "; status=$?; " + logcheck() + " " + output.string() +
                          " >/dev/null 2>&1; echo \"logcheck $?\"; exit $status'");
  expectStoppedWithReadableLog(result, output, "No space left on device");
  EXPECT_NE(result.output.find("logcheck 0"), std::string::npos) << result.output;
}

TEST(OutputFault, AnOutputFolderRemovedDuringTheRunIsReported) {
  const fs::path dir = scratchDir("output_removed");
  // A slow estimator (5 ms a step, 300 steps) keeps the run going while the folder goes.
  const fs::path config = writeSetup(
      dir, "[estimator.slow]\nplugin = hangs\nfail_after = 0\nhang_s = 0.005\nhang_every_step = true\n");
  const fs::path output = dir / "results" / "out.lcmlog";
  const auto result = run("sh -c '" + roamRun() + " " + config.string() + " --no-progress --output " +
                          output.string() + " & sleep 0.5; rm -rf " + (dir / "results").string() +
                          "; wait $!'");
  EXPECT_EQ(result.status, 3) << result.output;
  EXPECT_NE(result.output.find("roam-run: error: " + output.string() +
                               ": the output log was removed during the run (the file or its folder)"),
            std::string::npos)
      << result.output;
}

}  // namespace
}  // namespace roam
