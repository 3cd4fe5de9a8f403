// roam-run end to end, as a user runs it: replays, failures, bad configs, damaged logs.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "path_score.hpp"
#include "result_log.hpp"
#include "small_world.hpp"
#include "test_util.hpp"

namespace roam {
namespace {

using testing_util::run;
using testing_util::roamRun;
using testing_util::scratchDir;
using testing_util::writeFile;
namespace fs = std::filesystem;

constexpr double kPathTolerance_m = 1e-6;

fs::path writeConfig(const fs::path& dir, const fs::path& input, const std::string& estimators,
                     const std::string& plugin_path = "") {
  std::string text = "[runtime]\ninput = " + input.string() + "\noutput = result.lcmlog\n";
  if (!plugin_path.empty()) text += "plugin_path = " + plugin_path + "\n";
  return writeFile(dir / "run.ini", text + estimators);
}

std::string fileBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream out;
  out << in.rdbuf();
  return out.str();
}

TEST(Run, DeadReckoningOnPlaza1MatchesAnIndependentIntegrationOfTheCsv) {
  const fs::path dir = scratchDir("run_plaza");
  const fs::path config = writeConfig(dir, fs::path(ROAM_SOURCE_DIR) / "logs/plaza1.lcmlog",
                                      "[estimator.dr]\nplugin = deadreckoning\n");
  const auto result = run(roamRun() + " " + config.string() + " --no-progress");
  ASSERT_EQ(result.status, 0) << result.output;

  // Independent: integrate odometry.csv from groundtruth.csv's first row, move then turn.
  const fs::path data = fs::path(ROAM_SOURCE_DIR) / "data/plaza1";
  ASSERT_TRUE(fs::exists(data / "odometry.csv")) << "no " << data << " (the repository's data/ folder)";
  std::ifstream odometry_csv(data / "odometry.csv"), truth_csv(data / "groundtruth.csv");
  std::string line;
  std::getline(truth_csv, line);
  std::getline(odometry_csv, line);
  std::vector<std::array<double, 3>> truth;  // x, y, heading
  while (std::getline(truth_csv, line)) {
    double t, x, y, h;
    ASSERT_EQ(std::sscanf(line.c_str(), "%lf,%lf,%lf,%lf", &t, &x, &y, &h), 4);
    truth.push_back({x, y, h});
  }
  std::vector<std::array<double, 2>> integrated = {{truth[0][0], truth[0][1]}};
  double x = truth[0][0], y = truth[0][1], heading = truth[0][2];
  while (std::getline(odometry_csv, line)) {
    double t, d, dh;
    ASSERT_EQ(std::sscanf(line.c_str(), "%lf,%lf,%lf", &t, &d, &dh), 3);
    x += d * std::cos(heading);
    y += d * std::sin(heading);
    heading += dh;
    integrated.push_back({x, y});
  }
  ASSERT_EQ(integrated.size(), truth.size());  // 9,658 poses: odometry row k ends at GT row k+1

  const ResultLog log = readResultLog((dir / "result.lcmlog").string());
  const EstimatorOutputs* dr = log.find("dr");
  ASSERT_NE(dr, nullptr);
  ASSERT_TRUE(dr->trajectory.has_value());
  ASSERT_EQ(dr->trajectory->size(), integrated.size());
  double sum_error_m = 0.0, expected_sum_m = 0.0;
  for (size_t k = 0; k < integrated.size(); ++k) {
    const Pose& pose = (*dr->trajectory)[k];
    ASSERT_NEAR(pose.x_m, integrated[k][0], kPathTolerance_m) << "pose " << k;
    ASSERT_NEAR(pose.y_m, integrated[k][1], kPathTolerance_m) << "pose " << k;
    sum_error_m += std::hypot(pose.x_m - truth[k][0], pose.y_m - truth[k][1]);
    expected_sum_m += std::hypot(integrated[k][0] - truth[k][0], integrated[k][1] - truth[k][1]);
  }
  const double mean_error_m = sum_error_m / static_cast<double>(integrated.size());
  EXPECT_NEAR(mean_error_m, expected_sum_m / static_cast<double>(integrated.size()), kPathTolerance_m);
  EXPECT_NEAR(mean_error_m, 1.61, 0.005);  // the data README: 1.61 m
}

TEST(Run, TwoReplaysGiveIdenticalEstimates) {
  const fs::path dir = scratchDir("run_twice");
  const fs::path log = testing_util::writeSmallWorldLog(dir);
  const fs::path config = writeConfig(dir, log, "[estimator.dr]\nplugin = deadreckoning\n");
  ASSERT_EQ(run(roamRun() + " " + config.string() + " --no-progress --output first.lcmlog").status, 0);
  ASSERT_EQ(run(roamRun() + " " + config.string() + " --no-progress --output second.lcmlog").status, 0);
  const ResultLog first = readResultLog((fs::current_path() / "first.lcmlog").string());
  const ResultLog second = readResultLog((fs::current_path() / "second.lcmlog").string());
  ASSERT_EQ(first.estimators.size(), 1u);
  ASSERT_EQ(second.estimators.size(), 1u);
  const Path& a = first.estimators[0].poses;
  const Path& b = second.estimators[0].poses;
  ASSERT_EQ(a.size(), 301u);
  ASSERT_EQ(a.size(), b.size());
  for (size_t k = 0; k < a.size(); ++k) {
    ASSERT_EQ(a[k].utime, b[k].utime);
    ASSERT_EQ(a[k].x_m, b[k].x_m);  // bit-identical
    ASSERT_EQ(a[k].y_m, b[k].y_m);
    ASSERT_EQ(a[k].heading_rad, b[k].heading_rad);
  }
}

TEST(Run, AHeldCalibrationIsNotedWithItsKeyAtTheEnd) {
  // Ranges every 4 s: the EKF and online EM hold the heading-rate bias at 0 (0.01 rad/s x 3 x
  // 4 s = 0.12 rad > 0.08) and roam-run says so, naming each one's key; at the small world's
  // 2 Hz neither holds it. There online EM with 20 particles places no landmark (its ranging
  // positions lie too near a line) and rejects every range: said, and its path is dead reckoning
  // (the SDK's self-check).
  const fs::path dir = scratchDir("run_note");
  sim::SimConfig world = testing_util::smallWorld();
  world.range_rate_hz = 0.25;
  world.num_steps = 1000;  // 200 s: 50 ranges
  const fs::path sparse = dir / "sparse.lcmlog";
  writeDatasetLog(sparse.string(), sim::simulate(world));
  const std::string estimators = "[estimator.ekf]\nplugin = ekf\n[estimator.em]\nplugin = online_em\nnum_particles = 20\n";
  const fs::path config = writeConfig(dir, sparse, estimators);
  const auto result = run(roamRun() + " " + config.string() + " --no-progress");
  EXPECT_EQ(result.status, 0) << result.output;
  EXPECT_NE(result.output.find("roam-run: note: ekf held the heading-rate bias at 0: its first 20 ranges fixed the "
                               "position 4.00 s apart"),
            std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("(0.080); for a drifting gyro with clean ranges set it to 0: look at key "
                               "gyro_bias_max_drift_rad\n"),
            std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("roam-run: note: em held the heading-rate bias at 0"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("look at key heading_rate_bias_max_drift_rad\n"), std::string::npos) << result.output;
  const fs::path dense = writeConfig(dir, testing_util::writeSmallWorldLog(dir), estimators);
  const auto quiet = run(roamRun() + " " + dense.string() + " --no-progress");
  EXPECT_EQ(quiet.status, 0) << quiet.output;
  EXPECT_EQ(quiet.output.find("held the heading-rate bias"), std::string::npos) << quiet.output;
  EXPECT_NE(quiet.output.find("roam-run: note: em rejected every one of its 120 ranges: it had odometry alone\n"),
            std::string::npos) << quiet.output;
  EXPECT_NE(quiet.output.find("roam-run: note: em used no range (none accepted): the path published is dead "
                              "reckoning from the start pose\n"),
            std::string::npos) << quiet.output;
  EXPECT_EQ(quiet.output.find("note: ekf"), std::string::npos) << quiet.output;
}

TEST(Run, AnchorBeaconsWithoutASurveyIsNotedAndSpectralRefusesIt) {
  // A field run with no survey (roam-import without landmarks.csv: BEACONS empty) given to
  // anchor = beacons: the EKF, online EM and spectral + batch place every beacon from its ranges
  // and say so, naming the key; spectral fails with its reason. With the survey nothing is noted.
  const fs::path dir = scratchDir("run_no_survey");
  Dataset unsurveyed = sim::simulate(testing_util::smallWorld());
  unsurveyed.beacons.clear();
  const fs::path log = dir / "unsurveyed.lcmlog";
  writeDatasetLog(log.string(), unsurveyed);
  const std::string estimators =
      "[estimator.ekf]\nplugin = ekf\nanchor = beacons\n[estimator.em]\nplugin = online_em\nanchor = beacons\n"
      "num_particles = 20\n[estimator.batch]\nplugin = spectral_batch\nanchor = beacons\n"
      "[estimator.spectral]\nplugin = spectral\nanchor = beacons\n";
  const auto result = run(roamRun() + " " + writeConfig(dir, log, estimators).string() + " --no-progress");
  EXPECT_EQ(result.status, 1) << result.output;  // one estimator failed
  for (const std::string name : {"ekf", "em", "batch"}) {
    EXPECT_NE(result.output.find("roam-run: note: " + name + " anchor = beacons, but BEACONS held no beacon: every "
                                 "beacon was placed from its ranges, and the frame is the start pose's: look at key "
                                 "anchor\n"),
              std::string::npos)
        << name << "\n" << result.output;
  }
  EXPECT_NE(result.output.find("anchor = beacons needs >= 4 surveyed beacons that were ranged, got 0"), std::string::npos)
      << result.output;
  const fs::path surveyed = writeConfig(dir, testing_util::writeSmallWorldLog(dir), estimators);
  const auto quiet = run(roamRun() + " " + surveyed.string() + " --no-progress");
  EXPECT_EQ(quiet.output.find("BEACONS held no beacon"), std::string::npos) << quiet.output;
}

TEST(Run, EveryEstimatorHoldsAFastRobotFromTheStartPose) {
  // A fast UWB robot (sim::fastUwbWorld, seed-sweep's fast-uwb): 50 Hz odometry at 1 m/s, 10
  // ranges a second, a gyro drifting at 0.005 rad/s; five minutes, 15000 steps. Ten times Plaza
  // 1's rates: no estimator rejects an input, each recovers the bias and lands under dead
  // reckoning by an order of magnitude. After five minutes the EKF and online EM state the
  // bias to sigma 0.0007 rad/s (heading_rate_bias_sigma_rad_s): within 3 sigma of the truth.
  // Measured (seed 301): EKF 0.15 m (b 0.00518), spectral 0.31 (0.00493), spectral + batch
  // 0.33 (0.00514), online EM 0.18 (0.00602); dead reckoning 12.15 m.
  const fs::path dir = scratchDir("run_fast");
  const sim::SimRun world = sim::simulate(sim::fastUwbWorld(301, 15000));
  const fs::path input = dir / "fast.lcmlog";
  writeDatasetLog(input.string(), world);
  std::string estimators = "[estimator.dr]\nplugin = deadreckoning\n";
  for (const char* plugin : {"ekf", "spectral", "spectral_batch", "online_em"})
    estimators += std::string("[estimator.") + plugin + "]\nplugin = " + plugin + "\nanchor = start_pose\n";
  const fs::path config = writeConfig(dir, input, estimators);
  const auto result = run(roamRun() + " " + config.string() + " --no-progress");
  ASSERT_EQ(result.status, 0) << result.output;
  const ResultLog log = readResultLog((dir / "result.lcmlog").string());
  auto meanError_m = [&](const std::string& name) {
    const EstimatorOutputs* outputs = log.find(name);
    EXPECT_NE(outputs, nullptr) << name;
    if (outputs == nullptr) return kNaN;
    EXPECT_EQ(outputs->odometry_rejected, 0) << name;
    EXPECT_LE(outputs->ranges_rejected, 1) << name;  // online EM: the range after the last step
    return scorePath(outputs->scoredPath(), world.ground_truth, false).full.mean_m;
  };
  const double dead_reckoning_m = meanError_m("dr");
  EXPECT_GT(dead_reckoning_m, 5.0);
  for (const char* name : {"ekf", "spectral", "spectral_batch", "online_em"}) {
    const double error_m = meanError_m(name);
    const EstimatorOutputs* outputs = log.find(name);
    ASSERT_NE(outputs, nullptr);
    double bias_rad_s = kNaN;
    for (const auto& [key, value] : outputs->diagnostics)
      if (key == "heading_rate_bias_rad_s") bias_rad_s = value;
    std::printf("fast UWB robot, seed 301, start pose: %s %.2f m, b %.5f rad/s (dead reckoning %.2f m)\n", name,
                error_m, bias_rad_s, dead_reckoning_m);
    EXPECT_LT(error_m, 0.1 * dead_reckoning_m) << name;
    EXPECT_NEAR(bias_rad_s, 0.005, 0.002) << name;
  }
}

TEST(Run, AFailingPluginIsIsolatedAndNamedInTheExitStatus) {
  const fs::path dir = scratchDir("run_failing");
  const fs::path log = testing_util::writeSmallWorldLog(dir);
  const fs::path config = writeConfig(
      dir, log, "[estimator.good]\nplugin = deadreckoning\n[estimator.bad]\nplugin = throws\nfail_after = 50\n",
      ROAM_TEST_PLUGIN_DIR);
  const auto result = run(roamRun() + " " + config.string() + " --no-progress");
  EXPECT_EQ(result.status, 1) << result.output;
  EXPECT_NE(result.output.find("roam-run: estimator 'bad' failed: add_odometry: deliberate failure at step 51"),
            std::string::npos)
      << result.output;
  const ResultLog out = readResultLog((dir / "result.lcmlog").string());
  const EstimatorOutputs* good = out.find("good");
  const EstimatorOutputs* bad = out.find("bad");
  ASSERT_NE(good, nullptr);
  ASSERT_NE(bad, nullptr);
  EXPECT_EQ(good->poses.size(), 301u);  // the good estimator ran to the end
  ASSERT_TRUE(good->trajectory.has_value());
  EXPECT_EQ(bad->poses.size(), 50u);    // the bad one stopped at its failure
  EXPECT_EQ(bad->state, "failed");
  EXPECT_EQ(bad->last_error, "add_odometry: deliberate failure at step 51");
}

TEST(Run, StartupErrorsAreOneLineWithExitStatus2) {
  const fs::path dir = scratchDir("run_startup");
  const fs::path log = testing_util::writeSmallWorldLog(dir);
  struct Case {
    std::string estimators;
    std::string expected;
  };
  const std::vector<Case> cases = {
      {"[estimator.dr]\nplugin = deadreckonin\n",
       "run.ini:6 [estimator.dr] plugin: no plugin 'deadreckonin' in"},
      {"[estimator.dr]\nplugin = deadreckoning\nmax_speed_mp = 3\n",
       "run.ini:7 [estimator.dr] max_speed_mp: unknown key 'max_speed_mp' (did you mean 'max_speed_mps'?)"},
      {"[estimator.dr]\nplugin = deadreckoning\nmax_speed_mps = far\n",
       "run.ini:7 [estimator.dr] max_speed_mps: expected a number, got 'far'"},
      {"[estimator.v]\nplugin = wrong_version\n", "plugin ABI version"},
      {"[estimator.c]\nplugin = create_fails\n", "run.ini:5 [estimator.c]: deliberate create failure"},
  };
  for (const auto& c : cases) {
    const fs::path config = writeConfig(dir, log, c.estimators, ROAM_TEST_PLUGIN_DIR);
    const auto result = run(roamRun() + " " + config.string());
    EXPECT_EQ(result.status, 2) << result.output;
    EXPECT_NE(result.output.find(c.expected), std::string::npos) << result.output;
    EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1) << result.output;
    EXPECT_FALSE(fs::exists(dir / "result.lcmlog")) << "no data may be read or written";
  }
  const auto missing = run(roamRun() + " " + (dir / "nope.ini").string());
  EXPECT_EQ(missing.status, 2);
  EXPECT_NE(missing.output.find("nope.ini: cannot open the config file"), std::string::npos);
  const fs::path config = writeConfig(dir, dir / "absent.lcmlog", "[estimator.dr]\nplugin = deadreckoning\n");
  const auto absent = run(roamRun() + " " + config.string());
  EXPECT_EQ(absent.status, 2);
  EXPECT_NE(absent.output.find("absent.lcmlog: cannot open the input log"), std::string::npos) << absent.output;
}

TEST(Run, InputWithoutOutputSaysItReplacesTheConfigsOutput) {
  const fs::path dir = scratchDir("run_input_no_output");
  const fs::path log = testing_util::writeSmallWorldLog(dir);
  const fs::path config = writeConfig(dir, log, "[estimator.dr]\nplugin = deadreckoning\n");
  const auto first = run(roamRun() + " " + config.string() + " --no-progress");
  ASSERT_EQ(first.status, 0) << first.output;
  EXPECT_EQ(first.output.find("--input without --output"), std::string::npos) << first.output;
  // The same config on another input: the result log it would replace is named.
  const auto second = run(roamRun() + " " + config.string() + " --no-progress --input " + log.string());
  ASSERT_EQ(second.status, 0) << second.output;
  EXPECT_NE(second.output.find("roam-run: note: --input without --output: the results replace " +
                               (dir / "result.lcmlog").string() + ", the config's output"),
            std::string::npos) << second.output;
  const auto elsewhere = run(roamRun() + " " + config.string() + " --no-progress --input " + log.string() +
                             " --output " + (dir / "other.lcmlog").string());
  EXPECT_EQ(elsewhere.output.find("--input without --output"), std::string::npos) << elsewhere.output;
}

TEST(Run, PrintConfigShowsDefaults) {
  const fs::path dir = scratchDir("run_print");
  const fs::path config = writeConfig(dir, dir / "x.lcmlog", "[estimator.dr]\nplugin = deadreckoning\n");
  const auto result = run(roamRun() + " " + config.string() + " --print-config --set estimator.dr.max_speed_mps=2.5");
  EXPECT_EQ(result.status, 0) << result.output;
  EXPECT_NE(result.output.find("[estimator.dr]\nplugin = deadreckoning\npose_channel = POSE_DR\n"),
            std::string::npos) << result.output;
  EXPECT_NE(result.output.find("max_speed_mps = 2.5\n"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("status_interval_s = 1\n"), std::string::npos) << result.output;
}

TEST(Run, DamagedLogsAreReplayedAsFarAsPossibleAndReported) {
  const fs::path dir = scratchDir("run_damaged");
  const fs::path log = testing_util::writeSmallWorldLog(dir);
  const std::string bytes = fileBytes(log);
  const fs::path config_text = writeConfig(dir, dir / "damaged.lcmlog", "[estimator.dr]\nplugin = deadreckoning\n");

  // Cut in the middle of an event (the last 10 bytes gone).
  std::ofstream(dir / "damaged.lcmlog", std::ios::binary) << bytes.substr(0, bytes.size() - 10);
  auto result = run(roamRun() + " " + config_text.string() + " --no-progress");
  EXPECT_EQ(result.status, 0) << result.output;
  EXPECT_NE(result.output.find("the log ends inside an event (cut or corrupt): replayed up to there"),
            std::string::npos) << result.output;
  ResultLog out = readResultLog((dir / "result.lcmlog").string());
  ASSERT_EQ(out.estimators.size(), 1u);
  EXPECT_TRUE(out.estimators[0].trajectory.has_value());
  EXPECT_GE(out.estimators[0].poses.size(), 290u);

  // A corrupt sync word in the middle: that event is lost, the reader resynchronises.
  std::string corrupt = bytes;
  const size_t middle = corrupt.find("ODOMETRY", corrupt.size() / 2) - 28;  // its sync word
  ASSERT_EQ(static_cast<unsigned char>(corrupt[middle]), 0xED);
  corrupt[middle] = 'X';
  std::ofstream(dir / "damaged.lcmlog", std::ios::binary) << corrupt;
  result = run(roamRun() + " " + config_text.string() + " --no-progress");
  EXPECT_EQ(result.status, 0) << result.output;
  EXPECT_NE(result.output.find("corrupt bytes skipped"), std::string::npos) << result.output;
  out = readResultLog((dir / "result.lcmlog").string());
  EXPECT_EQ(out.estimators[0].poses.size(), 300u);  // one odometry step lost, the rest processed

  // Undecodable payload on a known channel: skipped and counted.
  std::string garbled = bytes;
  const size_t odometry = garbled.find("ODOMETRY", garbled.size() / 3) + 8;  // its payload
  for (size_t i = 0; i < 8; ++i) garbled[odometry + i] = '\x7f';  // wrong type fingerprint
  std::ofstream(dir / "damaged.lcmlog", std::ios::binary) << garbled;
  result = run(roamRun() + " " + config_text.string() + " --no-progress");
  EXPECT_EQ(result.status, 0) << result.output;
  EXPECT_NE(result.output.find("1 undecodable (skipped: ODOMETRY=1)"), std::string::npos) << result.output;
}

}  // namespace
}  // namespace roam
