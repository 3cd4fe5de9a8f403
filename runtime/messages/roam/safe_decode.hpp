// decodeMessage: LCM decoding of roam's input and output messages that is safe on damaged
// bytes (a corrupt log, a garbled packet on the bus).
//
// lcm-gen's C++ decoders trust the lengths inside the bytes: a string length <= 0 makes them
// throw std::length_error, and an array count makes them allocate that many elements before
// they find the bytes missing (a map_t claiming 2^31 beacons asks for 120 GB). decodeMessage
// first walks the variable-length fields and checks every string length and array count
// against the bytes that are there, then decodes, and never throws.
#pragma once

#include <cstdint>

#include "roam/estimator_status_t.hpp"
#include "roam/map_t.hpp"
#include "roam/odometry_t.hpp"
#include "roam/pose_t.hpp"
#include "roam/range_t.hpp"
#include "roam/robot_range_t.hpp"
#include "roam/trajectory_t.hpp"

namespace roam {

// As Message::decode(data, 0, size): the number of bytes used, or -1 if the bytes are not a
// message of that type (including every case where LCM's decoder would throw or over-allocate).
// odometry_t also reads the older odometry_v1_t layout (lateral 0, covariance NaN).
int decodeMessage(const void* data, int size, roam::odometry_t* message);
int decodeMessage(const void* data, int size, roam::range_t* message);
int decodeMessage(const void* data, int size, roam::robot_range_t* message);
int decodeMessage(const void* data, int size, roam::pose_t* message);
int decodeMessage(const void* data, int size, roam::map_t* message);
int decodeMessage(const void* data, int size, roam::trajectory_t* message);
int decodeMessage(const void* data, int size, roam::estimator_status_t* message);

// The utime of an odometry_t (odometry = true) or a range_t; false if the bytes are not one.
// What the host reorders inputs by, and what roam-logcheck measures their lateness with.
bool decodeInputUtime(bool odometry, const void* data, int size, int64_t* utime);

}  // namespace roam
