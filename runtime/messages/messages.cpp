#include "roam/messages.hpp"

#include <algorithm>
#include <cctype>
#include <cstddef>
#include <iterator>
#include <limits>
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

namespace {

// One field from one side to the other: scalars are assigned, fixed-size arrays copied element
// by element (their lengths checked at compile time), and LCM's booleans (int8_t) and the ABI's
// flags (int32_t) kept to 0 or 1, as plugin_abi.h promises.
template <typename To, typename From>
void assign(To& to, const From& from) {
  to = from;
}
template <typename T, std::size_t N>
void assign(T (&to)[N], const T (&from)[N]) {
  std::copy(from, from + N, to);
}
void assign(int32_t& to, const int8_t& from) { to = from != 0 ? 1 : 0; }
void assign(int8_t& to, const int32_t& from) { to = from != 0 ? 1 : 0; }

// The two directions the field lists below are run in.
struct IntoC {
  template <typename M, typename C>
  void operator()(const M& message_field, C& c_field) const { assign(c_field, message_field); }
};
struct IntoMessage {
  template <typename M, typename C>
  void operator()(M& message_field, const C& c_field) const { assign(message_field, c_field); }
};

// The field lists: each LCM field beside its plugin_abi.h field, written once for both
// directions. `Message` and `C` are const on the side read from.
struct OdometryFields {
  template <typename Message, typename C, typename Copy>
  static void visit(Message& m, C& c, Copy copy) {
    copy(m.utime, c.utime);
    copy(m.delta_distance, c.forward_m);
    copy(m.delta_lateral, c.lateral_m);
    copy(m.delta_heading, c.delta_heading_rad);
    copy(m.covariance, c.covariance);
  }
};

struct RangeFields {
  template <typename Message, typename C, typename Copy>
  static void visit(Message& m, C& c, Copy copy) {
    copy(m.utime, c.utime);
    copy(m.beacon_id, c.beacon_id);
    copy(m.range, c.range_m);
    copy(m.sigma, c.sigma_m);
    copy(m.has_bearing, c.has_bearing);
    copy(m.bearing, c.bearing_rad);
  }
};

struct PoseFields {
  template <typename Message, typename C, typename Copy>
  static void visit(Message& m, C& c, Copy copy) {
    copy(m.utime, c.utime);
    copy(m.x, c.x_m);
    copy(m.y, c.y_m);
    copy(m.heading, c.heading_rad);
    copy(m.covariance, c.covariance);
  }
};

struct BeaconFields {
  template <typename Message, typename C, typename Copy>
  static void visit(Message& m, C& c, Copy copy) {
    copy(m.id, c.id);
    copy(m.x, c.x_m);
    copy(m.y, c.y_m);
    copy(m.covariance, c.covariance);
  }
};

// trajectory_t holds a path as parallel arrays: each array beside the roam_pose field it holds.
struct TrajectoryColumns {
  template <typename Message, typename Column>
  static void visit(Message& m, Column column) {
    column(m.utimes, &roam_pose::utime);
    column(m.x, &roam_pose::x_m);
    column(m.y, &roam_pose::y_m);
    column(m.heading, &roam_pose::heading_rad);
  }
};

template <typename C, typename Fields, typename Message>
C intoC(const Message& message) {
  C out{};
  Fields::visit(message, out, IntoC{});
  return out;
}

template <typename Message, typename Fields, typename C>
Message intoMessage(const C& c) {
  Message out;
  Fields::visit(out, c, IntoMessage{});
  return out;
}

}  // namespace

roam_odometry fromMessage(const roam::odometry_t& message) {
  return intoC<roam_odometry, OdometryFields>(message);
}

roam::odometry_t toMessage(const roam_odometry& odometry) {
  return intoMessage<roam::odometry_t, OdometryFields>(odometry);
}

roam_range fromMessage(const roam::range_t& message) { return intoC<roam_range, RangeFields>(message); }

roam::range_t toMessage(const roam_range& range) { return intoMessage<roam::range_t, RangeFields>(range); }

roam_pose fromMessage(const roam::pose_t& message) { return intoC<roam_pose, PoseFields>(message); }

roam::pose_t toMessage(const roam_pose& pose, const std::string& estimator) {
  roam::pose_t message = intoMessage<roam::pose_t, PoseFields>(pose);
  message.estimator = estimator;
  return message;
}

std::vector<roam_beacon> fromMessage(const roam::map_t& message) {
  std::vector<roam_beacon> beacons;
  beacons.reserve(message.beacons.size());
  for (const roam::beacon_t& beacon : message.beacons) beacons.push_back(intoC<roam_beacon, BeaconFields>(beacon));
  return beacons;
}

roam::map_t toMessage(const std::vector<roam_beacon>& beacons, int64_t utime, const std::string& estimator) {
  roam::map_t message;
  message.utime = utime;
  message.estimator = estimator;
  message.num_beacons = static_cast<int32_t>(beacons.size());
  message.beacons.reserve(beacons.size());
  for (const roam_beacon& beacon : beacons) message.beacons.push_back(intoMessage<roam::beacon_t, BeaconFields>(beacon));
  return message;
}

std::vector<roam_pose> fromMessage(const roam::trajectory_t& message) {
  const std::size_t n = message.utimes.size();
  TrajectoryColumns::visit(message, [&](const auto& column, auto) {
    if (column.size() != n) {
      throw std::runtime_error("trajectory_t from '" + message.estimator +
                               "': parallel arrays of different lengths");
    }
  });
  roam_pose blank{};
  std::fill(std::begin(blank.covariance), std::end(blank.covariance), std::numeric_limits<double>::quiet_NaN());
  std::vector<roam_pose> poses(n, blank);
  TrajectoryColumns::visit(message, [&](const auto& column, auto field) {
    for (std::size_t i = 0; i < n; ++i) poses[i].*field = column[i];
  });
  return poses;
}

roam::trajectory_t toMessage(const std::vector<roam_pose>& poses, int64_t utime, const std::string& estimator) {
  roam::trajectory_t message;
  message.utime = utime;
  message.estimator = estimator;
  message.num_poses = static_cast<int32_t>(poses.size());
  TrajectoryColumns::visit(message, [&](auto& column, auto field) {
    column.reserve(poses.size());
    for (const roam_pose& pose : poses) column.push_back(pose.*field);
  });
  return message;
}

}  // namespace roam
