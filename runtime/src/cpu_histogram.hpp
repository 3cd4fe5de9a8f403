// CPU time per call, summarised in bounded memory: count, total, max, and a histogram with
// 32 logarithmic buckets per doubling from 1 ns to ~18 min, so a quantile is good to ~1 %
// (half a bucket) however long a live run goes. roam-run keeps one per estimator and input kind
// (CPU per update: median and 99th percentile in the end summary).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

namespace roam {
namespace runtime {

class CpuHistogram {
 public:
  static constexpr int kPerDoubling = 32;
  static constexpr int kBuckets = 40 * kPerDoubling;  // 1 ns x 2^40 ~ 1100 s
  static constexpr double kFloor_s = 1e-9;

  void add(double seconds) {
    if (!(seconds >= 0.0)) seconds = 0.0;  // NaN and clock glitches count as zero
    ++count_;
    total_s_ += seconds;
    max_s_ = std::max(max_s_, seconds);
    ++buckets_[static_cast<size_t>(bucketOf(seconds))];
  }

  int64_t count() const { return count_; }
  double total_s() const { return total_s_; }
  double max_s() const { return max_s_; }

  // The q-quantile (nearest rank): the geometric middle of its bucket, clamped to the largest
  // sample (which is the 1-quantile exactly); 0 when empty.
  double quantile(double q) const {
    if (count_ == 0) return 0.0;
    const double rank = std::ceil(std::clamp(q, 0.0, 1.0) * static_cast<double>(count_));
    const int64_t target = std::max<int64_t>(1, static_cast<int64_t>(rank));
    if (target >= count_) return max_s_;
    int64_t seen = 0;
    for (int b = 0; b < kBuckets; ++b) {
      seen += buckets_[static_cast<size_t>(b)];
      if (seen >= target) {
        if (b == 0) return std::min(kFloor_s, max_s_);
        if (b == kBuckets - 1) return max_s_;  // the overflow bucket
        return std::min(kFloor_s * std::exp2((b + 0.5) / kPerDoubling), max_s_);
      }
    }
    return max_s_;
  }

 private:
  static int bucketOf(double seconds) {
    if (seconds <= kFloor_s) return 0;
    const double index = std::floor(std::log2(seconds / kFloor_s) * kPerDoubling);
    return static_cast<int>(std::clamp(index, 0.0, static_cast<double>(kBuckets - 1)));
  }

  int64_t count_ = 0;
  double total_s_ = 0.0;
  double max_s_ = 0.0;
  std::array<int64_t, kBuckets> buckets_{};
};

}  // namespace runtime
}  // namespace roam
