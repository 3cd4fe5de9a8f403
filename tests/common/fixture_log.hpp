// Writing small fixture logs by hand, message by message, for the tools' tests (roam-eval,
// roam-export, roam-plot): each test states its truth and estimates and works out the figures.
#pragma once

#include <cmath>
#include <cstdint>
#include <lcm/lcm-cpp.hpp>
#include <string>
#include <vector>

#include "roam/map_t.hpp"
#include "roam/pose_t.hpp"

namespace roam {
namespace test {

// An LCM log written event by event, numbered from 0.
class FixtureLog {
 public:
  explicit FixtureLog(const std::string& path) : log_(path, "w") {}
  template <typename Message>
  void write(const std::string& channel, int64_t utime, const Message& m) {
    std::vector<uint8_t> buffer(m.getEncodedSize());
    m.encode(buffer.data(), 0, static_cast<int>(buffer.size()));
    lcm::LogEvent e;
    e.eventnum = n_++;
    e.timestamp = utime;
    e.channel = channel;
    e.datalen = static_cast<int32_t>(buffer.size());
    e.data = buffer.data();
    log_.writeEvent(&e);
  }

 private:
  lcm::LogFile log_;
  int64_t n_ = 0;
};

// A pose_t at (x, y) heading 0 with an unknown (NaN) covariance.
inline roam::pose_t fixturePose(int64_t utime, double x, double y, const std::string& estimator = "") {
  roam::pose_t p{};
  p.utime = utime;
  p.estimator = estimator;
  p.x = x;
  p.y = y;
  for (double& c : p.covariance) c = NAN;
  return p;
}

// A map_t of beacons {id, x, y} with unknown (NaN) covariances, at utime 0 with no estimator.
struct FixtureBeacon {
  int32_t id;
  double x, y;
};
inline roam::map_t fixtureMap(const std::vector<FixtureBeacon>& beacons) {
  roam::map_t map{};
  map.num_beacons = static_cast<int32_t>(beacons.size());
  for (const FixtureBeacon& in : beacons) {
    roam::beacon_t out{};
    out.id = in.id;
    out.x = in.x;
    out.y = in.y;
    for (double& c : out.covariance) c = NAN;
    map.beacons.push_back(out);
  }
  return map;
}

}  // namespace test
}  // namespace roam
