// CPU per update in roam-run's end summary: the bounded histogram behind its median and p99.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "cpu_histogram.hpp"

namespace roam {
namespace runtime {
namespace {

TEST(CpuHistogram, EmptyGivesZeros) {
  CpuHistogram h;
  EXPECT_EQ(h.count(), 0);
  EXPECT_EQ(h.quantile(0.5), 0.0);
  EXPECT_EQ(h.total_s(), 0.0);
}

TEST(CpuHistogram, QuantilesWithinTheBucketWidthOfTheExactOnes) {
  std::mt19937_64 rng(3);
  std::lognormal_distribution<double> times(std::log(5e-6), 1.0);  // ~5 us, a long right tail
  std::vector<double> samples(20000);
  CpuHistogram h;
  double total = 0.0;
  for (double& s : samples) {
    s = times(rng);
    h.add(s);
    total += s;
  }
  std::sort(samples.begin(), samples.end());
  for (const double q : {0.5, 0.9, 0.99}) {
    const double exact = samples[static_cast<size_t>(std::ceil(q * samples.size())) - 1];
    EXPECT_NEAR(h.quantile(q) / exact, 1.0, 0.012) << "q = " << q;  // half a bucket: 2^(1/64) - 1
  }
  EXPECT_EQ(h.count(), 20000);
  EXPECT_NEAR(h.total_s(), total, 1e-12);
  EXPECT_EQ(h.max_s(), samples.back());
  EXPECT_EQ(h.quantile(1.0), samples.back());
}

TEST(CpuHistogram, ExtremesAreClampedNotLost) {
  CpuHistogram h;
  h.add(0.0);
  h.add(-1.0);          // a clock glitch counts as zero
  h.add(std::nan(""));  // so does NaN
  h.add(1e6);           // beyond the last bucket
  EXPECT_EQ(h.count(), 4);
  EXPECT_LE(h.quantile(0.5), 1e-9);
  EXPECT_EQ(h.quantile(1.0), 1e6);
  EXPECT_EQ(h.max_s(), 1e6);
}

}  // namespace
}  // namespace runtime
}  // namespace roam
