#include "roam/safe_decode.hpp"

#include <cstdint>
#include <exception>
#include <limits>

#include "roam/odometry_v1_t.hpp"

namespace roam {
namespace {

// Walks LCM-encoded bytes (big-endian) over the fields before and inside the variable parts.
class Walker {
 public:
  Walker(const void* data, int size) : bytes_(static_cast<const uint8_t*>(data)), size_(size) {}

  bool skip(int64_t n) {
    if (n < 0 || n > size_ - pos_) return false;
    pos_ += n;
    return true;
  }
  bool int32(int32_t* value) {
    if (size_ - pos_ < 4) return false;
    const uint8_t* p = bytes_ + pos_;
    *value = static_cast<int32_t>((uint32_t{p[0]} << 24) | (uint32_t{p[1]} << 16) | (uint32_t{p[2]} << 8) | p[3]);
    pos_ += 4;
    return true;
  }
  // An LCM string: int32 length (including the terminating NUL, so >= 1), then the bytes.
  bool string() {
    int32_t length = 0;
    return int32(&length) && length >= 1 && skip(length);
  }
  // An array count: not negative, and `count` elements of at least `min_element_bytes` fit.
  bool count(int32_t* count, int min_element_bytes) {
    return int32(count) && *count >= 0 &&
           static_cast<int64_t>(*count) * min_element_bytes <= size_ - pos_;
  }

 private:
  const uint8_t* bytes_;
  int64_t size_;
  int64_t pos_ = 0;
};

constexpr int kHash = 8, kInt64 = 8, kDouble = 8;

template <typename Message>
int decodeGuarded(const void* data, int size, Message* message) {
  if (data == nullptr || size < 0) return -1;
  try {
    return message->decode(data, 0, size);
  } catch (const std::exception&) {
    return -1;
  }
}

}  // namespace

int decodeMessage(const void* data, int size, roam::odometry_t* message) {
  const int used = decodeGuarded(data, size, message);
  if (used >= 0) return used;
  // A log from before lateral motion and covariances: the same step with lateral = 0 and the
  // covariance unknown.
  roam::odometry_v1_t legacy;
  const int legacy_used = decodeGuarded(data, size, &legacy);
  if (legacy_used < 0) return -1;
  message->utime = legacy.utime;
  message->delta_distance = legacy.delta_distance;
  message->delta_heading = legacy.delta_heading;
  message->delta_lateral = 0.0;
  for (double& value : message->covariance) value = std::numeric_limits<double>::quiet_NaN();
  return legacy_used;
}

int decodeMessage(const void* data, int size, roam::range_t* message) {
  return decodeGuarded(data, size, message);
}

int decodeMessage(const void* data, int size, roam::robot_range_t* message) {
  Walker walk(data, size);
  if (!walk.skip(kHash + kInt64) || !walk.string()) return -1;  // utime, other_robot
  return decodeGuarded(data, size, message);
}

int decodeMessage(const void* data, int size, roam::pose_t* message) {
  Walker walk(data, size);
  if (!walk.skip(kHash + kInt64) || !walk.string()) return -1;
  return decodeGuarded(data, size, message);
}

int decodeMessage(const void* data, int size, roam::map_t* message) {
  Walker walk(data, size);
  int32_t beacons = 0;
  constexpr int kBeaconBytes = 4 + 2 * kDouble + 4 * kDouble;  // id, x, y, covariance[4]
  if (!walk.skip(kHash + kInt64) || !walk.string() || !walk.count(&beacons, kBeaconBytes)) return -1;
  return decodeGuarded(data, size, message);
}

int decodeMessage(const void* data, int size, roam::trajectory_t* message) {
  Walker walk(data, size);
  int32_t poses = 0;
  constexpr int kPoseBytes = kInt64 + 3 * kDouble;  // utimes, x, y, heading
  if (!walk.skip(kHash + kInt64) || !walk.string() || !walk.count(&poses, kPoseBytes)) return -1;
  return decodeGuarded(data, size, message);
}

int decodeMessage(const void* data, int size, roam::estimator_status_t* message) {
  Walker walk(data, size);
  int32_t values = 0;
  // utime; estimator, plugin; state, 4 counters; last_rejection; cpu x2; last_error; keys; values
  if (!walk.skip(kHash + kInt64) || !walk.string() || !walk.string() || !walk.skip(1 + 4 * kInt64) ||
      !walk.string() || !walk.skip(2 * kDouble) || !walk.string() || !walk.count(&values, 4 + 1 + kDouble)) {
    return -1;
  }
  for (int32_t i = 0; i < values; ++i) {
    if (!walk.string()) return -1;
  }
  return decodeGuarded(data, size, message);
}

bool decodeInputUtime(bool odometry, const void* data, int size, int64_t* utime) {
  if (odometry) {
    roam::odometry_t message;
    if (decodeMessage(data, size, &message) < 0) return false;
    *utime = message.utime;
  } else {
    roam::range_t message;
    if (decodeMessage(data, size, &message) < 0) return false;
    *utime = message.utime;
  }
  return true;
}

}  // namespace roam
