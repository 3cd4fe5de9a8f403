// rangesInJumpStretches: NLOS stretches found by jumps beyond the distance travelled.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "range_jumps.hpp"

namespace roam::spectral {
namespace {

// A robot driving east at 1 m/s from the origin (0.2 m every 0.2 s for 100 s), and one range to
// a beacon at (50, 20) every 3 s, true distance plus `excess_m(i)` for the i-th range.
struct Drive {
  OdometryPath path;
  std::vector<RangeSample> ranges;
};

template <typename Excess>
Drive drive(Excess excess_m, int beacon = 0, int num_ranges = 30) {
  Drive run;
  Pose start;
  run.path.reset(start);
  for (int k = 1; k <= 500; ++k) {
    Odometry step;
    step.utime = 200000LL * k;
    step.forward_m = 0.2;
    run.path.append(step);
  }
  for (int i = 0; i < num_ranges; ++i) {
    const double t_s = 1.0 + 3.0 * i;
    RangeSample r;
    r.utime = static_cast<int64_t>(t_s * 1e6);
    r.beacon = beacon;
    r.range_m = std::hypot(50.0 - t_s, 20.0) + excess_m(i);
    run.ranges.push_back(r);
  }
  return run;
}

std::vector<int> flagged(const std::vector<bool>& in_stretch) {
  std::vector<int> out;
  for (size_t i = 0; i < in_stretch.size(); ++i)
    if (in_stretch[i]) out.push_back(static_cast<int>(i));
  return out;
}

// The bound between two ranges 3 s (3 m of travel) apart: 1.3 x 3 + 4 sqrt(2) 0.5 = 6.73 m.
TEST(RangeJumps, StretchesAboveBothNeighboursAreFoundAndNothingElse) {
  const Drive run = drive([](int i) {
    if (i >= 6 && i <= 10) return 10.0;  // a stretch: up, then down
    if (i == 15) return 20.0;            // one long range
    if (i >= 20 && i <= 23) return 2.0;  // long by less than the bound: not seen
    return 0.0;
  });
  const std::vector<bool> in_stretch = rangesInJumpStretches(run.path, run.ranges, 1, RangeJumpBound{});
  EXPECT_EQ(flagged(in_stretch), (std::vector<int>{6, 7, 8, 9, 10, 15}));
}

TEST(RangeJumps, AStretchThatOpensOrClosesTheRunIsKept) {
  // Long at both ends (left by a jump down, entered by a jump up): one neighbour each, which a
  // short range could fool as well, so neither is taken for NLOS.
  const Drive run = drive([](int i) { return i <= 2 || i >= 26 ? 30.0 : 0.0; });
  EXPECT_TRUE(flagged(rangesInJumpStretches(run.path, run.ranges, 1, RangeJumpBound{})).empty());
}

TEST(RangeJumps, ShortRangesAndCleanRangesFlagNothing) {
  // A stretch 10 m short is entered down and left up: NLOS never shortens, so nothing is taken
  // for NLOS there (its neighbours open and close the run).
  const Drive shorter = drive([](int i) { return i >= 10 && i <= 14 ? -10.0 : 0.0; });
  EXPECT_TRUE(flagged(rangesInJumpStretches(shorter.path, shorter.ranges, 1, RangeJumpBound{})).empty());
  const Drive clean = drive([](int) { return 0.0; });
  EXPECT_TRUE(flagged(rangesInJumpStretches(clean.path, clean.ranges, 1, RangeJumpBound{})).empty());
}

TEST(RangeJumps, ABeaconWhoseStretchesWouldBeMostOfItsRangesKeepsThemAll) {
  // Long from the 3rd range to the 28th (26 of 30): the bound does not describe this beacon.
  const Drive run = drive([](int i) { return i >= 2 && i <= 27 ? 12.0 : 0.0; });
  EXPECT_TRUE(flagged(rangesInJumpStretches(run.path, run.ranges, 1, RangeJumpBound{})).empty());
}

TEST(RangeJumps, TheBoundGrowsWithTheDistanceTravelled) {
  // The same 10 m stretch with ranges 9 s apart (9 m of travel: bound 1.3 x 9 + 2.83 = 14.5 m)
  // is not a jump.
  Drive run = drive([](int i) { return i >= 3 && i <= 5 ? 10.0 : 0.0; }, 0, 10);
  for (size_t i = 0; i < run.ranges.size(); ++i) {
    const double t_s = 1.0 + 9.0 * static_cast<double>(i);
    run.ranges[i].utime = static_cast<int64_t>(t_s * 1e6);
    run.ranges[i].range_m = std::hypot(50.0 - t_s, 20.0) + (i >= 3 && i <= 5 ? 10.0 : 0.0);
  }
  EXPECT_TRUE(flagged(rangesInJumpStretches(run.path, run.ranges, 1, RangeJumpBound{})).empty());
}

}  // namespace
}  // namespace roam::spectral
