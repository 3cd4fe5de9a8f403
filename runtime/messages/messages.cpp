#include "roam/messages.hpp"

#include <cctype>
#include <stdexcept>

namespace roam {

std::string upperCase(const std::string& text) {
  std::string upper = text;
  for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return upper;
}

std::string outputChannel(const std::string& prefix, const std::string& estimator_name) {
  std::string channel = prefix;
  if (!channel.empty() && channel.back() != '_') channel += '_';
  return channel + upperCase(estimator_name);
}

roam::odometry_t toMessage(const Odometry& odometry) {
  roam::odometry_t message;
  message.utime = odometry.utime;
  message.delta_distance = odometry.forward_m;
  message.delta_heading = odometry.delta_heading_rad;
  message.delta_lateral = odometry.lateral_m;
  for (int i = 0; i < 9; ++i) message.covariance[i] = odometry.covariance[i];
  return message;
}

Odometry fromMessage(const roam::odometry_t& message) {
  Odometry odometry;
  odometry.utime = message.utime;
  odometry.forward_m = message.delta_distance;
  odometry.delta_heading_rad = message.delta_heading;
  odometry.lateral_m = message.delta_lateral;
  for (int i = 0; i < 9; ++i) odometry.covariance[i] = message.covariance[i];
  return odometry;
}

roam::range_t toMessage(const Range& range) {
  roam::range_t message;
  message.utime = range.utime;
  message.beacon_id = range.beacon_id;
  message.range = range.range_m;
  message.sigma = range.sigma_m;
  message.has_bearing = range.has_bearing;
  message.bearing = range.bearing_rad;
  return message;
}

Range fromMessage(const roam::range_t& message) {
  Range range;
  range.utime = message.utime;
  range.beacon_id = message.beacon_id;
  range.range_m = message.range;
  range.sigma_m = message.sigma;
  range.has_bearing = message.has_bearing;
  range.bearing_rad = message.bearing;
  return range;
}

roam::pose_t toMessage(const Pose& pose, const std::string& estimator) {
  roam::pose_t message;
  message.utime = pose.utime;
  message.estimator = estimator;
  message.x = pose.x_m;
  message.y = pose.y_m;
  message.heading = pose.heading_rad;
  for (int i = 0; i < 9; ++i) message.covariance[i] = pose.covariance[i];
  return message;
}

Pose fromMessage(const roam::pose_t& message) {
  Pose pose;
  pose.utime = message.utime;
  pose.x_m = message.x;
  pose.y_m = message.y;
  pose.heading_rad = message.heading;
  for (int i = 0; i < 9; ++i) pose.covariance[i] = message.covariance[i];
  return pose;
}

roam::map_t toMessage(const Map& map, int64_t utime, const std::string& estimator) {
  roam::map_t message;
  message.utime = utime;
  message.estimator = estimator;
  message.num_beacons = static_cast<int32_t>(map.size());
  message.beacons.reserve(map.size());
  for (const Beacon& beacon : map) {
    roam::beacon_t out;
    out.id = beacon.id;
    out.x = beacon.x_m;
    out.y = beacon.y_m;
    for (int i = 0; i < 4; ++i) out.covariance[i] = beacon.covariance[i];
    message.beacons.push_back(out);
  }
  return message;
}

Map fromMessage(const roam::map_t& message) {
  Map map;
  map.reserve(message.beacons.size());
  for (const roam::beacon_t& in : message.beacons) {
    Beacon beacon;
    beacon.id = in.id;
    beacon.x_m = in.x;
    beacon.y_m = in.y;
    for (int i = 0; i < 4; ++i) beacon.covariance[i] = in.covariance[i];
    map.push_back(beacon);
  }
  return map;
}

roam::trajectory_t toMessage(const Path& path, int64_t utime, const std::string& estimator) {
  roam::trajectory_t message;
  message.utime = utime;
  message.estimator = estimator;
  message.num_poses = static_cast<int32_t>(path.size());
  message.utimes.reserve(path.size());
  message.x.reserve(path.size());
  message.y.reserve(path.size());
  message.heading.reserve(path.size());
  for (const Pose& pose : path) {
    message.utimes.push_back(pose.utime);
    message.x.push_back(pose.x_m);
    message.y.push_back(pose.y_m);
    message.heading.push_back(pose.heading_rad);
  }
  return message;
}

Path fromMessage(const roam::trajectory_t& message) {
  const size_t n = message.utimes.size();
  if (message.x.size() != n || message.y.size() != n || message.heading.size() != n) {
    throw std::runtime_error("trajectory_t from '" + message.estimator +
                             "': parallel arrays of different lengths");
  }
  Path path(n);
  for (size_t i = 0; i < n; ++i) {
    path[i].utime = message.utimes[i];
    path[i].x_m = message.x[i];
    path[i].y_m = message.y[i];
    path[i].heading_rad = message.heading[i];
  }
  return path;
}

}  // namespace roam
