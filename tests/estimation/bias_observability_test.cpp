// The heading-rate bias observability rule: drift = prior x 3 x (interval between position fixes
// of the first 20 ranges), estimated at or under max_drift_rad, held above it.
#include <gtest/gtest.h>

#include "roam/estimation/bias_observability.hpp"

namespace roam {
namespace estimation {
namespace {

using Decision = BiasObservability::Decision;

// Ranges every interval_s, `per_fix` of them at each time (several beacons at once).
Decision decide(BiasObservability* rule, double interval_s, int per_fix, int ranges) {
  Decision decision = Decision::kUndecided;
  for (int i = 0; i < ranges; ++i) {
    decision = rule->addRange(1000000 + static_cast<int64_t>((i / per_fix) * interval_s * 1e6));
  }
  return decision;
}

TEST(BiasObservability, EstimatesAtUwbRatesAndHoldsAtAuvRates) {
  // 0.01 rad/s x 3 x 0.5 s = 0.015 rad <= 0.05; x 3 x 2 s = 0.06 > 0.05.
  BiasObservability uwb(0.01, 0.05), slow(0.01, 0.05);
  EXPECT_EQ(decide(&uwb, 0.5, 1, 20), Decision::kEstimate);
  EXPECT_DOUBLE_EQ(uwb.intervalS(), 0.5);
  EXPECT_NEAR(uwb.driftRad(), 0.015, 1e-15);
  EXPECT_EQ(decide(&slow, 2.0, 1, 20), Decision::kHold);
  EXPECT_NEAR(slow.driftRad(), 0.06, 1e-15);
}

TEST(BiasObservability, DecidesAtTheTwentiethRangeAndKeepsIt) {
  BiasObservability rule(0.01, 0.05);
  EXPECT_EQ(decide(&rule, 0.5, 1, 19), Decision::kUndecided);
  EXPECT_TRUE(rule.denseSoFar());  // the provisional decision
  EXPECT_TRUE(rule.estimateSoFar());
  EXPECT_EQ(rule.addRange(10000000), Decision::kEstimate);
  // Later ranges, however sparse, change nothing.
  EXPECT_EQ(rule.addRange(900000000), Decision::kEstimate);
  EXPECT_DOUBLE_EQ(rule.intervalS(), 0.5);
}

TEST(BiasObservability, RangesAtOneTimeAreOneFix) {
  // Four beacons at once every 2 s: 20 ranges are 5 fixes, 2 s apart (0.06 rad: held), not
  // 20 ranges 0.42 s apart (0.013 rad).
  BiasObservability rule(0.01, 0.05);
  EXPECT_EQ(decide(&rule, 2.0, 4, 20), Decision::kHold);
  EXPECT_DOUBLE_EQ(rule.intervalS(), 2.0);
  // All at one time: no interval yet, so no decision until a third fix time.
  BiasObservability burst(0.01, 0.05);
  EXPECT_EQ(decide(&burst, 0.0, 1, 25), Decision::kUndecided);
  EXPECT_FALSE(burst.denseSoFar());
  EXPECT_FALSE(burst.estimateSoFar());
  EXPECT_EQ(burst.addRange(1500000), Decision::kUndecided);
  EXPECT_EQ(burst.addRange(2000000), Decision::kEstimate);  // 3 fixes over 1 s: 0.5 s apart
}

TEST(BiasObservability, ZeroThresholdAlwaysEstimates) {
  BiasObservability rule(0.01, 0.0);
  EXPECT_EQ(rule.decision(), Decision::kEstimate);
  EXPECT_EQ(decide(&rule, 10.0, 1, 20), Decision::kEstimate);
}

TEST(BiasObservability, TheHeldNoteNamesTheIntervalTheDriftAndTheKey) {
  BiasObservability rule(0.01, 0.05);
  decide(&rule, 2.0, 1, 20);
  EXPECT_EQ(rule.heldNote("gyro_bias_max_drift_rad"),
            "held the heading-rate bias at 0: its first 20 ranges fixed the position 2.00 s apart, over three fixes "
            "the bias prior turns the heading 0.060 rad, more than gyro_bias_max_drift_rad (0.050); for a drifting "
            "gyro with clean ranges set it to 0");
}

}  // namespace
}  // namespace estimation
}  // namespace roam
