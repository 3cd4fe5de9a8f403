// Estimators on worker threads: the output log is the same whatever the number of threads, with
// or without isolated estimators among them, and a failing estimator still stops only itself.
#include <gtest/gtest.h>

#include "log_compare.hpp"
#include "result_log.hpp"
#include "small_world.hpp"
#include "test_util.hpp"

namespace roam {
namespace {

using testing_util::firstDifference;
using testing_util::readEvents;
using testing_util::run;
using testing_util::roamRun;
using testing_util::scratchDir;
using testing_util::writeFile;
namespace fs = std::filesystem;

// Every shipped plugin, two of them twice (so four threads have work), and a plugin that throws.
const char* const kEstimators =
    "[estimator.dr]\nplugin = deadreckoning\n"
    "[estimator.ekf_start]\nplugin = ekf\nanchor = start_pose\n"
    "[estimator.ekf_beacons]\nplugin = ekf\nanchor = beacons\n"
    "[estimator.spectral]\nplugin = spectral\n"
    "[estimator.batch]\nplugin = spectral_batch\n"
    "[estimator.em_start]\nplugin = online_em\nanchor = start_pose\n"
    "[estimator.em_beacons]\nplugin = online_em\nanchor = beacons\n"
    "[estimator.throws]\nplugin = throws\nfail_after = 100\n";

TEST(Threads, TheOutputLogIsTheSameWhateverTheThreadCount) {
  const fs::path dir = scratchDir("threads_same");
  const fs::path log = testing_util::writeSmallWorldLog(dir);
  const fs::path config = writeFile(dir / "run.ini", "[runtime]\ninput = " + log.string() +
                                                         "\nplugin_path = " ROAM_TEST_PLUGIN_DIR "\n" + kEstimators);
  const std::pair<std::string, std::string> runs[] = {
      {"threads1.lcmlog", "--set runtime.threads=1"},
      {"threads4.lcmlog", "--set runtime.threads=4"},
      {"threads2-isolated.lcmlog", "--set runtime.threads=2 --set estimator.ekf_start.isolation=process "
                                   "--set estimator.em_start.isolation=process"}};
  for (const auto& [output, options] : runs) {
    const auto result = run(roamRun() + " " + config.string() + " --no-progress --output " +
                            (dir / output).string() + " " + options);
    EXPECT_EQ(result.status, 1) << result.output;  // the throwing plugin, and only it
    EXPECT_NE(result.output.find("roam-run: estimator 'throws' failed: add_odometry: deliberate failure at step 101"),
              std::string::npos) << result.output;
  }
  const auto reference = readEvents((dir / "threads1.lcmlog").string());
  ASSERT_GT(reference.size(), 2000u);
  EXPECT_EQ(firstDifference(readEvents((dir / "threads4.lcmlog").string()), reference), "");
  EXPECT_EQ(firstDifference(readEvents((dir / "threads2-isolated.lcmlog").string()), reference), "");
  const ResultLog out = readResultLog((dir / "threads4.lcmlog").string());
  EXPECT_EQ(out.find("throws")->poses.size(), 100u);
  EXPECT_EQ(out.find("em_beacons")->state, "finished");
}

TEST(Threads, AThreadCountThatIsNotAWholeNumberIsRefused) {
  const fs::path dir = scratchDir("threads_config");
  const fs::path config = writeFile(dir / "run.ini", "[runtime]\ninput = x.lcmlog\nthreads = 2.5\n"
                                                     "[estimator.dr]\nplugin = deadreckoning\n");
  const auto result = run(roamRun() + " " + config.string());
  EXPECT_EQ(result.status, 2) << result.output;
  EXPECT_NE(result.output.find("run.ini:3 [runtime] threads: expected an integer, got '2.5'"),
            std::string::npos) << result.output;
}

}  // namespace
}  // namespace roam
