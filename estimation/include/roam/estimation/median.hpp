// The upper median of a sample: the element at index n / 2 once sorted (the mean of the two
// middle ones is not taken); 0 for an empty sample. Robust scales are 1.4826 x the median of
// absolute residuals.
#pragma once

#include <algorithm>
#include <vector>

namespace roam {
namespace estimation {

inline double upperMedian(std::vector<double> values) {
  if (values.empty()) return 0.0;
  const auto mid = values.begin() + static_cast<long>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

}  // namespace estimation
}  // namespace roam
