// The end-of-run warning when an estimator rejects more than 5 % of an input.
#include <gtest/gtest.h>

#include "rejection_warning.hpp"

namespace roam {
namespace runtime {
namespace {

EstimatorInstance::Status statusWith(int64_t ranges_accepted, int64_t ranges_rejected) {
  EstimatorInstance::Status status;
  status.odometry_accepted = 100;
  status.ranges_accepted = ranges_accepted;
  status.ranges_rejected = ranges_rejected;
  status.keys = {"rejected range: longer than max_range_m", "rejected range: gated: beyond gate_probability",
                 "beacons_initialised"};
  status.values = {2.0, static_cast<double>(ranges_rejected - 2), 4.0};
  return status;
}

const KeyValues kConfig = {{"max_range_m", "1000"}, {"gate_probability", "0.999"}, {"gate", "x"}};

TEST(RejectionWarning, NamesTheCountTheTopReasonAndTheKeyItNames) {
  // 439 of 572 = 76.7 %: the top reason (437) names gate_probability (the longer of 'gate' and
  // 'gate_probability', both in the reason).
  const auto lines = rejectionWarnings("ekf", statusWith(133, 439), kConfig);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0], "warning: ekf rejected 439 of 572 ranges (77 %), most as 'gated: beyond gate_probability' "
                      "(437): look at key gate_probability");
}

TEST(RejectionWarning, SilentAtOrBelowFivePercent) {
  EXPECT_TRUE(rejectionWarnings("ekf", statusWith(95, 5), kConfig).empty());   // exactly 5 %
  EXPECT_EQ(rejectionWarnings("ekf", statusWith(94, 6), kConfig).size(), 1u);  // 6 %
}

TEST(RejectionWarning, AReasonThatNamesNoKeySaysSo) {
  EstimatorInstance::Status status;
  status.odometry_accepted = 10;
  status.odometry_rejected = 10;
  status.keys = {"rejected odometry: not finite"};
  status.values = {10.0};
  const auto lines = rejectionWarnings("dr", status, kConfig);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0], "warning: dr rejected 10 of 20 odometry steps (50 %), most as 'not finite' (10): the data "
                      "may not suit this estimator (see its README)");
}

}  // namespace
}  // namespace runtime
}  // namespace roam
