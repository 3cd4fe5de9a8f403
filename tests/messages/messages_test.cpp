// Every message type survives struct -> LCM message -> memq:// -> LCM message -> struct, and the
// channel-name helpers give the names of DESIGN.md.
#include <cmath>
#include <memory>
#include <string>

#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include "roam/messages.hpp"
#include "roam/odometry_v1_t.hpp"
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
  const roam::Odometry out = roam::fromMessage(roundTrip(roam::toMessage(in)));
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
  const roam::Odometry out = roam::fromMessage(message);
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
  const roam::Range out = roam::fromMessage(roundTrip(roam::toMessage(in)));
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
  const roam::pose_t message = roundTrip(roam::toMessage(in, "spectral"));
  EXPECT_EQ(message.estimator, "spectral");
  const roam::Pose out = roam::fromMessage(message);
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
  const roam::map_t message = roundTrip(roam::toMessage(in, 77, "ekf"));
  EXPECT_EQ(message.utime, 77);
  EXPECT_EQ(message.estimator, "ekf");
  EXPECT_EQ(message.num_beacons, 2);
  const roam::Map out = roam::fromMessage(message);
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
  const roam::trajectory_t message = roundTrip(roam::toMessage(in, 1400000, "dr"));
  EXPECT_EQ(message.utime, 1400000);
  EXPECT_EQ(message.estimator, "dr");
  EXPECT_EQ(message.num_poses, 3);
  const roam::Path out = roam::fromMessage(message);
  ASSERT_EQ(out.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(out[i].utime, in[i].utime);
    EXPECT_EQ(out[i].x_m, in[i].x_m);
    EXPECT_EQ(out[i].y_m, in[i].y_m);
    EXPECT_EQ(out[i].heading_rad, in[i].heading_rad);
  }
}

}  // namespace
