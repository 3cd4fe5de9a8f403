// Every message type survives struct -> C struct -> LCM message -> memq:// -> LCM message -> C
// struct -> struct, the way roam's tools write and read logs (roam/messages.hpp converts LCM <-> C,
// the shim C <-> roam/types.hpp); every field comes back bit for bit from LCM through both
// conversions and back; and the channel-name helpers give the names of DESIGN.md.
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include "roam/messages.hpp"
#include "roam/odometry_v1_t.hpp"
#include "roam/plugin_shim.hpp"
#include "roam/safe_decode.hpp"

namespace {

// Publishes `message` on a fresh memq:// bus and returns what a subscriber decodes.
template <typename Message>
Message roundTrip(const Message& message, const std::string& channel = "TEST") {
  lcm::LCM bus("memq://");
  EXPECT_TRUE(bus.good());
  Message received;
  bool got = false;
  // Raw bytes through LCM's C API, decoded here as the runtime decodes them (roam::decodeMessage):
  // LCM 1.3.1's C++ subscription templates trip UndefinedBehaviorSanitizer's null and vptr checks
  // inside LCM's own header.
  struct Handler {
    Message* out;
    bool* got;
    static void onMessage(const lcm_recv_buf_t* rbuf, const char*, void* user) {
      auto* self = static_cast<Handler*>(user);
      *self->got = roam::decodeMessage(rbuf->data, static_cast<int>(rbuf->data_size), self->out) ==
                   static_cast<int>(rbuf->data_size);
    }
  } handler{&received, &got};
  lcm_subscription_t* subscription =
      lcm_subscribe(bus.getUnderlyingLCM(), channel.c_str(), &Handler::onMessage, &handler);
  EXPECT_NE(subscription, nullptr);
  EXPECT_EQ(bus.publish(channel, &message), 0);
  EXPECT_GT(bus.handleTimeout(1000), 0);
  EXPECT_TRUE(got);
  return received;
}

// roam/types.hpp -> LCM and back, composed as the tools compose it.
template <typename T, typename... Extra>
auto toLcm(const T& value, Extra... extra) {
  return roam::toMessage(roam::shim::toC(value), extra...);
}
template <typename Message>
auto fromLcm(const Message& message) {
  return roam::shim::fromC(roam::fromMessage(message));
}

// The encoded bytes of a message (what a log or the bus holds).
template <typename Message>
std::vector<uint8_t> bytes(const Message& message) {
  std::vector<uint8_t> out(static_cast<size_t>(message.getEncodedSize()));
  EXPECT_EQ(message.encode(out.data(), 0, static_cast<int>(out.size())), static_cast<int>(out.size()));
  return out;
}

TEST(Messages, ChannelNames) {
  EXPECT_STREQ(roam::channels::ODOMETRY, "ODOMETRY");
  EXPECT_STREQ(roam::channels::RANGE, "RANGE");
  EXPECT_STREQ(roam::channels::INITIAL_POSE, "INITIAL_POSE");
  EXPECT_STREQ(roam::channels::BEACONS, "BEACONS");
  EXPECT_STREQ(roam::channels::GROUND_TRUTH, "GROUND_TRUTH");
  EXPECT_EQ(roam::outputChannel("POSE_", "spectral"), "POSE_SPECTRAL");
  EXPECT_EQ(roam::outputChannel(roam::channels::TRAJECTORY_PREFIX, "ekf-2"), "TRAJECTORY_EKF-2");
  EXPECT_EQ(roam::outputChannel("MAP", "dr"), "MAP_DR");
}

TEST(Messages, OdometryRoundTrip) {
  roam::Odometry in;
  in.utime = 3856880000;
  in.forward_m = 0.1875;
  in.lateral_m = -0.5;
  in.delta_heading_rad = -0.015625;
  in.covariance = {0.04, 0.01, 0, 0.01, 0.09, 0, 0, 0, 1e-4};
  const roam::Odometry out = fromLcm(roundTrip(toLcm(in)));
  EXPECT_EQ(out.utime, in.utime);
  EXPECT_EQ(out.forward_m, in.forward_m);
  EXPECT_EQ(out.lateral_m, in.lateral_m);
  EXPECT_EQ(out.delta_heading_rad, in.delta_heading_rad);
  EXPECT_EQ(out.covariance, in.covariance);
  EXPECT_TRUE(out.hasCovariance());
}

TEST(Messages, OdometryFromAnOldLogIsAStepWithoutLateralMotionOrCovariance) {
  // roam's first logs hold odometry_v1_t's bytes (utime, distance, heading): 8 + 24 bytes.
  roam::odometry_v1_t old;
  old.utime = 42;
  old.delta_distance = 0.25;
  old.delta_heading = 0.125;
  std::vector<uint8_t> bytes(static_cast<size_t>(old.getEncodedSize()));
  ASSERT_EQ(old.encode(bytes.data(), 0, static_cast<int>(bytes.size())), 32);
  roam::odometry_t message;
  ASSERT_EQ(roam::decodeMessage(bytes.data(), static_cast<int>(bytes.size()), &message), 32);
  const roam::Odometry out = fromLcm(message);
  EXPECT_EQ(out.utime, 42);
  EXPECT_EQ(out.forward_m, 0.25);
  EXPECT_EQ(out.delta_heading_rad, 0.125);
  EXPECT_EQ(out.lateral_m, 0.0);
  EXPECT_FALSE(out.hasCovariance());
  EXPECT_TRUE(std::isnan(out.covariance[0]));
  // Bytes of neither layout are refused.
  EXPECT_EQ(roam::decodeMessage(bytes.data(), 20, &message), -1);
}

TEST(Messages, RangeRoundTrip) {
  roam::Range in;
  in.utime = 3858062000;
  in.beacon_id = 6;
  in.range_m = 41.658;
  in.sigma_m = 0.5;
  in.has_bearing = true;
  in.bearing_rad = 1.25;
  const roam::Range out = fromLcm(roundTrip(toLcm(in)));
  EXPECT_EQ(out.utime, in.utime);
  EXPECT_EQ(out.beacon_id, 6);
  EXPECT_EQ(out.range_m, 41.658);
  EXPECT_EQ(out.sigma_m, 0.5);
  EXPECT_TRUE(out.has_bearing);
  EXPECT_EQ(out.bearing_rad, 1.25);
}

TEST(Messages, PoseRoundTrip) {
  roam::Pose in;
  in.utime = 42;
  in.x_m = 1.5;
  in.y_m = -2.25;
  in.heading_rad = 3.0;
  in.covariance[0] = 0.01;  // the rest stays NaN
  const roam::pose_t message = roundTrip(toLcm(in, "spectral"));
  EXPECT_EQ(message.estimator, "spectral");
  const roam::Pose out = fromLcm(message);
  EXPECT_EQ(out.utime, 42);
  EXPECT_EQ(out.x_m, 1.5);
  EXPECT_EQ(out.y_m, -2.25);
  EXPECT_EQ(out.heading_rad, 3.0);
  EXPECT_EQ(out.covariance[0], 0.01);
  for (int i = 1; i < 9; ++i) EXPECT_TRUE(std::isnan(out.covariance[i])) << i;
}

TEST(Messages, MapRoundTrip) {
  roam::Map in(2);
  in[0].id = 0;
  in[0].x_m = -68.9265;
  in[0].y_m = 18.3778;
  in[1].id = 5;
  in[1].x_m = 1.0;
  in[1].y_m = 2.0;
  in[1].covariance = {0.1, 0.0, 0.0, 0.2};
  const roam::map_t message = roundTrip(toLcm(in, 77, "ekf"));
  EXPECT_EQ(message.utime, 77);
  EXPECT_EQ(message.estimator, "ekf");
  EXPECT_EQ(message.num_beacons, 2);
  const roam::Map out = fromLcm(message);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].id, 0);
  EXPECT_EQ(out[0].x_m, -68.9265);
  EXPECT_EQ(out[0].y_m, 18.3778);
  EXPECT_TRUE(std::isnan(out[0].covariance[3]));
  EXPECT_EQ(out[1].id, 5);
  EXPECT_EQ(out[1].covariance[3], 0.2);
}

TEST(Messages, TrajectoryRoundTrip) {
  roam::Path in(3);
  for (int i = 0; i < 3; ++i) {
    in[i].utime = 1000000 + 200000 * i;
    in[i].x_m = 0.5 * i;
    in[i].y_m = -0.25 * i;
    in[i].heading_rad = 0.125 * i;
  }
  const roam::trajectory_t message = roundTrip(toLcm(in, 1400000, "dr"));
  EXPECT_EQ(message.utime, 1400000);
  EXPECT_EQ(message.estimator, "dr");
  EXPECT_EQ(message.num_poses, 3);
  const roam::Path out = fromLcm(message);
  ASSERT_EQ(out.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(out[i].utime, in[i].utime);
    EXPECT_EQ(out[i].x_m, in[i].x_m);
    EXPECT_EQ(out[i].y_m, in[i].y_m);
    EXPECT_EQ(out[i].heading_rad, in[i].heading_rad);
  }
}

// LCM -> C -> roam/types.hpp -> C -> LCM gives the same bytes for every message type: every
// field of every .lcm file is carried by both conversions, in both directions. Each field holds a
// value of its own, so a field dropped or swapped with another on either side changes the bytes.
TEST(Messages, EveryFieldSurvivesBothConversionsBothWays) {
  auto there_and_back = [](const auto& message, auto... extra) {
    return roam::toMessage(roam::shim::toC(roam::shim::fromC(roam::fromMessage(message))), extra...);
  };
  roam::odometry_t odometry;
  odometry.utime = 1001;
  odometry.delta_distance = 0.5;
  odometry.delta_lateral = -0.25;
  odometry.delta_heading = 0.125;
  for (int i = 0; i < 9; ++i) odometry.covariance[i] = 1.0 + i;
  EXPECT_EQ(bytes(there_and_back(odometry)), bytes(odometry));

  roam::range_t range;
  range.utime = 1002;
  range.beacon_id = 7;
  range.range = 41.658;
  range.sigma = 0.75;
  range.has_bearing = 1;
  range.bearing = -1.5;
  EXPECT_EQ(bytes(there_and_back(range)), bytes(range));

  roam::pose_t pose;
  pose.utime = 1003;
  pose.estimator = "ekf_start";
  pose.x = -68.9265;
  pose.y = 18.3778;
  pose.heading = 2.5;
  for (int i = 0; i < 9; ++i) pose.covariance[i] = 0.5 * (i + 1);
  EXPECT_EQ(bytes(there_and_back(pose, pose.estimator)), bytes(pose));

  roam::map_t map;
  map.utime = 1004;
  map.estimator = "spectral";
  map.num_beacons = 2;
  map.beacons.resize(2);
  for (int b = 0; b < 2; ++b) {
    map.beacons[b].id = 10 + b;
    map.beacons[b].x = 1.5 + b;
    map.beacons[b].y = -2.5 - b;
    for (int i = 0; i < 4; ++i) map.beacons[b].covariance[i] = 0.25 * (i + 1) + b;
  }
  EXPECT_EQ(bytes(there_and_back(map, map.utime, map.estimator)), bytes(map));

  roam::trajectory_t trajectory;
  trajectory.utime = 1005;
  trajectory.estimator = "online_em";
  trajectory.num_poses = 3;
  for (int i = 0; i < 3; ++i) {
    trajectory.utimes.push_back(2000 + i);
    trajectory.x.push_back(0.5 * i + 0.1);
    trajectory.y.push_back(-0.25 * i - 0.2);
    trajectory.heading.push_back(0.125 * i + 0.3);
  }
  EXPECT_EQ(bytes(there_and_back(trajectory, trajectory.utime, trajectory.estimator)), bytes(trajectory));
}

// LCM's boolean is a byte; the ABI promises has_bearing is 0 or 1, whatever byte a log holds.
TEST(Messages, RangeBearingFlagIsZeroOrOneInTheAbi) {
  roam::range_t range;
  range.utime = 1;
  range.beacon_id = 2;
  range.range = 3.0;
  range.sigma = 0.5;
  range.bearing = 0.0;
  range.has_bearing = 5;
  EXPECT_EQ(roam::fromMessage(range).has_bearing, 1);
  range.has_bearing = 0;
  EXPECT_EQ(roam::fromMessage(range).has_bearing, 0);
}

// Parallel arrays of different lengths are refused rather than read past their end.
TEST(Messages, TrajectoryWithArraysOfDifferentLengthsIsRefused) {
  roam::trajectory_t trajectory;
  trajectory.utime = 1;
  trajectory.estimator = "dr";
  trajectory.num_poses = 2;
  trajectory.utimes = {1, 2};
  trajectory.x = {0.0, 1.0};
  trajectory.y = {0.0};
  trajectory.heading = {0.0, 0.0};
  EXPECT_THROW(roam::fromMessage(trajectory), std::runtime_error);
}

}  // namespace
