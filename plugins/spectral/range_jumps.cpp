#include "range_jumps.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace roam::spectral {

namespace {

// Dead-reckoned distance travelled from the path's start to `utime` (linear between poses,
// clamped to the path's ends).
class DistanceAlongPath {
 public:
  explicit DistanceAlongPath(const OdometryPath& path) : path_(path), travelled_m_(path.size(), 0.0) {
    for (int k = 1; k < path.size(); ++k) travelled_m_[k] = travelled_m_[k - 1] + path.step_m[k - 1];
  }
  double at(int64_t utime) const {
    const int T = path_.size();
    if (T == 0) return 0.0;
    if (utime <= path_.utime.front()) return 0.0;
    if (utime >= path_.utime.back()) return travelled_m_.back();
    const int k = static_cast<int>(std::upper_bound(path_.utime.begin(), path_.utime.end(), utime) - path_.utime.begin()) - 1;
    const double span = static_cast<double>(path_.utime[k + 1] - path_.utime[k]);
    const double f = span > 0.0 ? static_cast<double>(utime - path_.utime[k]) / span : 0.0;
    return travelled_m_[k] + f * (travelled_m_[k + 1] - travelled_m_[k]);
  }

 private:
  const OdometryPath& path_;
  std::vector<double> travelled_m_;
};

}  // namespace

std::vector<bool> rangesInJumpStretches(const OdometryPath& path, const std::vector<RangeSample>& ranges,
                                        int num_beacons, const RangeJumpBound& bound) {
  std::vector<bool> in_stretch(ranges.size(), false);
  const DistanceAlongPath distance(path);
  const double noise_m = bound.sigmas * std::sqrt(2.0) * bound.range_sigma_m;
  for (int n = 0; n < num_beacons; ++n) {
    std::vector<size_t> mine;
    for (size_t i = 0; i < ranges.size(); ++i)
      if (ranges[i].beacon == n) mine.push_back(i);
    if (mine.size() < 2) continue;
    // jump[j]: between mine[j] and mine[j + 1]: +1 up, -1 down, 0 within the bound.
    std::vector<int> jump(mine.size() - 1, 0);
    for (size_t j = 0; j + 1 < mine.size(); ++j) {
      const RangeSample& a = ranges[mine[j]];
      const RangeSample& b = ranges[mine[j + 1]];
      const double limit_m = bound.max_scale * std::abs(distance.at(b.utime) - distance.at(a.utime)) + noise_m;
      const double change_m = b.range_m - a.range_m;
      jump[j] = change_m > limit_m ? 1 : (change_m < -limit_m ? -1 : 0);
    }
    // Stretches between jumps: [begin, end) in `mine`.
    std::vector<size_t> cuts = {0};
    for (size_t j = 0; j < jump.size(); ++j)
      if (jump[j] != 0) cuts.push_back(j + 1);
    cuts.push_back(mine.size());
    const size_t stretches = cuts.size() - 1;
    if (stretches < 2) continue;
    std::vector<bool> drop(mine.size(), false);
    size_t dropped = 0;
    for (size_t s = 0; s < stretches; ++s) {
      const size_t begin = cuts[s], end = cuts[s + 1];
      // Both ends seen: a stretch that opens or closes the run has one neighbour to vouch for it.
      if (s == 0 || s + 1 == stretches || jump[begin - 1] < 0 || jump[end - 1] > 0) continue;
      for (size_t j = begin; j < end; ++j) drop[j] = true;
      dropped += end - begin;
    }
    if (2 * dropped > mine.size()) continue;
    for (size_t j = 0; j < mine.size(); ++j)
      if (drop[j]) in_stretch[mine[j]] = true;
  }
  return in_stretch;
}

}  // namespace roam::spectral
