// estimation::upperMedian: odd and even samples (the upper of the two middle values), order of
// the input irrelevant, 0 for an empty sample.
#include <gtest/gtest.h>

#include <vector>

#include "roam/estimation/median.hpp"

namespace roam {
namespace estimation {
namespace {

TEST(UpperMedian, OddEvenAndEmpty) {
  EXPECT_EQ(upperMedian({3.0, -1.0, 2.0}), 2.0);
  EXPECT_EQ(upperMedian({4.0, 1.0, 3.0, 2.0}), 3.0);
  EXPECT_EQ(upperMedian({5.0}), 5.0);
  EXPECT_EQ(upperMedian({}), 0.0);
}

}  // namespace
}  // namespace estimation
}  // namespace roam
