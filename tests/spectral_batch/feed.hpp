// The spectral_batch tests' helpers: the shared feeder (tests/common/feed.hpp) and a path score.
#pragma once

#include <cmath>
#include <stdexcept>

#include "../common/feed.hpp"

namespace roam {
namespace test {

// Mean position error (m) of a path with one pose per ground-truth pose.
inline double meanError_m(const Path& path, const Path& truth) {
  if (path.size() != truth.size()) throw std::invalid_argument("meanError_m: sizes differ");
  double sum_m = 0.0;
  for (size_t k = 0; k < path.size(); ++k)
    sum_m += std::hypot(path[k].x_m - truth[k].x_m, path[k].y_m - truth[k].y_m);
  return sum_m / static_cast<double>(path.size());
}

}  // namespace test
}  // namespace roam
