// The end-of-run notes: each status value "note: <text>", with the config key the text names.
#include <gtest/gtest.h>

#include "run_notes.hpp"

namespace roam {
namespace runtime {
namespace {

TEST(RunNotes, EachNoteWithTheLongestKeyItNames) {
  EstimatorInstance::Status status;
  status.keys = {"rejected range: gated", "note: held the bias at 0: more than gyro_bias_max_drift_rad (0.05)",
                 "beacons_initialised", "note: fell back to dead reckoning"};
  status.values = {3.0, 1.0, 4.0, 1.0};
  const KeyValues config = {{"gyro_bias_max_drift_rad", "0.05"}, {"drift", "x"}, {"gate_probability", "0.999"}};
  const auto lines = runNotes("ekf_start", status, config);
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0], "note: ekf_start held the bias at 0: more than gyro_bias_max_drift_rad (0.05): look at key "
                      "gyro_bias_max_drift_rad");
  EXPECT_EQ(lines[1], "note: ekf_start fell back to dead reckoning");
}

TEST(RunNotes, NoneWithoutANote) {
  EstimatorInstance::Status status;
  status.keys = {"rejected range: note: not a note", "heading_rate_bias_estimated"};
  status.values = {1.0, 1.0};
  EXPECT_TRUE(runNotes("ekf", status, {}).empty());
}

TEST(RunNotes, EstimatorsWithNoRangeToWorkWithAreNamed) {
  EstimatorInstance::Status odometry_only, all_rejected, some_used, dead_reckoning;
  odometry_only.odometry_accepted = 100;
  all_rejected.odometry_accepted = 100;
  all_rejected.ranges_rejected = 56;
  some_used.odometry_accepted = 100;
  some_used.ranges_accepted = 50;
  some_used.ranges_rejected = 6;
  dead_reckoning.odometry_accepted = 100;
  // No ranges in the input: one line naming every estimator that ran.
  EXPECT_EQ(rangeUseNotes(0, "RANGE", {{"ekf", odometry_only}, {"dr", odometry_only}}),
            std::vector<std::string>{"note: the input has no ranges (channel RANGE): every estimator ran on "
                                     "odometry alone (ekf, dr)"});
  // Ranges in the input: the estimator that rejected every one is named; dead reckoning (takes
  // none) and one that used some are not.
  EXPECT_EQ(rangeUseNotes(56, "RANGE", {{"online_em", all_rejected}, {"ekf", some_used}, {"dr", dead_reckoning}}),
            std::vector<std::string>{"note: online_em rejected every one of its 56 ranges: it had odometry alone"});
}

}  // namespace
}  // namespace runtime
}  // namespace roam
