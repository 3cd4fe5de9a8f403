// Fuzz target: messages into every estimator plugin of the build, through the host.
//
// Every libroam_<name>.so in the build's plugin folder (so each new plugin is fuzzed as soon
// as it is built) gets an instance with its default config. The bytes are read as a sequence
// of events, each LCM-encoded and handed to Host::onEvent as a log replay would:
//   tag byte, kind = tag % 6:
//     0 ODOMETRY      odometry_t (utime, delta_distance, delta_heading)
//     1 RANGE         range_t (utime, beacon id 0..7, range, sigma, has_bearing, bearing)
//     2 INITIAL_POSE  pose_t
//     3 BEACONS       map_t with 0..8 beacons (ids 0..7, repeats possible)
//     4 raw bytes (length byte) on one of the four input channels: decoding of garbage
//     5 a well-formed message of kind (next byte % 4) with one byte flipped or its end cut off
//   times: the next int16 times 10 ms added to the clock (so time can go backwards or stand);
//   numbers: a selector byte picks a small value (int16 / 64), raw IEEE bytes, or a special
//   (NaN, +-inf, 0, -0, 1e300, -1e300, the smallest subnormal, 1e4).
// Expected: no crash, hang or sanitizer report; every pose an estimator publishes is finite;
// every output decodes. A plugin that reports an error is marked failed by the host (allowed,
// and printed once per plugin and message when ROAM_FUZZ_VERBOSE is set).
// ROAM_FUZZ_SKIP_PLUGINS=name,... leaves plugins out.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "fuzz_util.hpp"
#include "host.hpp"
#include "plugin_library.hpp"
#include "roam/map_t.hpp"
#include "roam/messages.hpp"
#include "roam/plugin_shim.hpp"
#include "roam/odometry_t.hpp"
#include "roam/pose_t.hpp"
#include "roam/range_t.hpp"
#include "roam/trajectory_t.hpp"

using namespace roam::runtime;

namespace {

class Bytes {
 public:
  Bytes(const uint8_t* data, size_t size) : data_(data), size_(size) {}
  bool empty() const { return pos_ >= size_; }
  uint8_t byte() { return pos_ < size_ ? data_[pos_++] : 0; }
  int16_t int16() { return static_cast<int16_t>((byte() << 8) | byte()); }
  double number() {
    const uint8_t selector = byte();
    if (selector < 160) return static_cast<double>(int16()) / 64.0;
    if (selector < 200) {
      uint64_t bits = 0;
      for (int i = 0; i < 8; ++i) bits = (bits << 8) | byte();
      double value;
      std::memcpy(&value, &bits, sizeof(value));
      return value;
    }
    static const double kSpecial[] = {std::numeric_limits<double>::quiet_NaN(),
                                      std::numeric_limits<double>::infinity(),
                                      -std::numeric_limits<double>::infinity(),
                                      0.0, -0.0, 1e300, -1e300,
                                      std::numeric_limits<double>::denorm_min(), 1e4};
    return kSpecial[selector % (sizeof(kSpecial) / sizeof(kSpecial[0]))];
  }
  std::string raw(size_t length) {
    const size_t n = std::min(length, size_ - std::min(pos_, size_));
    std::string out(reinterpret_cast<const char*>(data_ + pos_), n);
    pos_ += n;
    return out;
  }

 private:
  const uint8_t* data_;
  size_t size_;
  size_t pos_ = 0;
};

// Checks every output the host publishes.
class CheckingSink : public Sink {
 public:
  void write(const std::string& channel, int64_t, const void* data, int size) override {
    if (channel.rfind("POSE_", 0) == 0) {
      roam::pose_t pose;
      ROAM_FUZZ_CHECK(pose.decode(data, 0, size) == size, "an output pose that does not decode");
      ROAM_FUZZ_CHECK(std::isfinite(pose.x) && std::isfinite(pose.y) && std::isfinite(pose.heading),
                      channel + ": a non-finite pose was published");
    } else if (channel.rfind("TRAJECTORY_", 0) == 0) {
      roam::trajectory_t path;
      ROAM_FUZZ_CHECK(path.decode(data, 0, size) == size, "an output path that does not decode");
      for (int i = 0; i < path.num_poses; ++i) {
        ROAM_FUZZ_CHECK(std::isfinite(path.x[i]) && std::isfinite(path.y[i]),
                        channel + ": a non-finite path pose was published");
      }
    } else if (channel.rfind("MAP_", 0) == 0) {
      roam::map_t map;
      ROAM_FUZZ_CHECK(map.decode(data, 0, size) == size, "an output map that does not decode");
    }
  }
};

struct Plugins {
  std::vector<std::shared_ptr<PluginLibrary>> libraries;
  std::vector<std::string> names;
};

const Plugins& plugins() {
  static const Plugins loaded = [] {
    Plugins out;
    // ROAM_FUZZ_SKIP_PLUGINS=a,b leaves plugins out (one with a known, reported finding, so
    // the fuzzer's time goes to the others).
    const char* skip_env = std::getenv("ROAM_FUZZ_SKIP_PLUGINS");
    const std::string skip = "," + std::string(skip_env ? skip_env : "") + ",";
    for (const auto& name : PluginLibrary::available(roam::fuzz::pluginDir())) {
      if (skip.find("," + name + ",") != std::string::npos) {
        std::fprintf(stderr, "not fuzzing plugin %s (ROAM_FUZZ_SKIP_PLUGINS)\n", name.c_str());
        continue;
      }
      try {
        auto library = PluginLibrary::open(roam::fuzz::pluginDir(), name);
        PluginInstance probe(library, name, roam::KeyValues{});  // defaults must be a valid config
        out.libraries.push_back(library);
        out.names.push_back(name);
        std::fprintf(stderr, "fuzzing plugin %s\n", name.c_str());
      } catch (const std::exception& error) {
        std::fprintf(stderr, "not fuzzing plugin %s: %s\n", name.c_str(), error.what());
      }
    }
    ROAM_FUZZ_CHECK(!out.names.empty(), "no plugin in " + roam::fuzz::pluginDir());
    return out;
  }();
  return loaded;
}

template <typename Message>
std::string encode(const Message& message) {
  std::string bytes(static_cast<size_t>(message.getEncodedSize()), '\0');
  message.encode(&bytes[0], 0, static_cast<int>(bytes.size()));
  return bytes;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  roam::fuzz::pinPlugins();
  const Plugins& loaded = plugins();
  RunConfig config;
  config.input = "fuzz";
  std::vector<EstimatorSlot> slots;
  for (size_t i = 0; i < loaded.names.size(); ++i) {
    EstimatorSlot slot;
    slot.section.name = loaded.names[i];
    slot.section.plugin = loaded.names[i];
    const std::string suffix = roam::upperCase(loaded.names[i]);
    slot.section.pose_channel = "POSE_" + suffix;
    slot.section.map_channel = "MAP_" + suffix;
    slot.section.trajectory_channel = "TRAJECTORY_" + suffix;
    slot.section.status_channel = "STATUS_" + suffix;
    slot.instance = std::make_unique<PluginInstance>(loaded.libraries[i], loaded.names[i], roam::KeyValues{});
    config.estimators.push_back(slot.section);
    slots.push_back(std::move(slot));
  }
  CheckingSink sink;
  Host host(config, std::move(slots), &sink, nullptr);

  const char* channels[] = {"ODOMETRY", "RANGE", "INITIAL_POSE", "BEACONS"};
  Bytes in(data, size);
  int64_t utime = 1000000;
  auto message = [&](int kind) -> std::string {
    utime += static_cast<int64_t>(in.int16()) * 10000;
    switch (kind) {
      case 0: {
        roam::Odometry odometry{utime, in.number(), in.number()};
        return encode(roam::toMessage(roam::shim::toC(odometry)));
      }
      case 1: {
        roam::Range range;
        range.utime = utime;
        range.beacon_id = in.byte() % 8;
        range.range_m = in.number();
        range.sigma_m = in.number();
        range.has_bearing = (in.byte() & 1) != 0;
        range.bearing_rad = in.number();
        return encode(roam::toMessage(roam::shim::toC(range)));
      }
      case 2: {
        roam::Pose pose;
        pose.utime = utime;
        pose.x_m = in.number();
        pose.y_m = in.number();
        pose.heading_rad = in.number();
        return encode(roam::toMessage(roam::shim::toC(pose)));
      }
      default: {
        roam::Map map(in.byte() % 9);
        for (auto& beacon : map) {
          beacon.id = in.byte() % 8;
          beacon.x_m = in.number();
          beacon.y_m = in.number();
        }
        return encode(roam::toMessage(roam::shim::toC(map), utime));
      }
    }
  };
  int events = 0;
  while (!in.empty() && events < 256) {
    ++events;
    const uint8_t tag = in.byte();
    const int kind = tag % 6;
    if (kind < 4) {
      const std::string bytes = message(kind);
      host.onEvent(channels[kind], utime, bytes.data(), static_cast<int>(bytes.size()));
    } else if (kind == 4) {
      const std::string bytes = in.raw(in.byte());
      host.onEvent(channels[(tag / 6) % 4], utime, bytes.data(), static_cast<int>(bytes.size()));
    } else {
      const int inner = in.byte() % 4;
      std::string bytes = message(inner);
      const uint8_t where = in.byte();
      if (where & 1) {
        bytes[where % bytes.size()] ^= static_cast<char>(in.byte() | 1);
      } else {
        bytes.resize(where % bytes.size());
      }
      host.onEvent(channels[inner], utime, bytes.data(), static_cast<int>(bytes.size()));
    }
  }
  host.finish();
  static std::set<std::string> reported;
  if (std::getenv("ROAM_FUZZ_VERBOSE") != nullptr) {
    for (const auto& slot : host.estimators()) {
      const std::string line = slot.section.name + ": " + slot.instance->error();
      if (slot.instance->failed() && reported.insert(line).second) std::fprintf(stderr, "failed: %s\n", line.c_str());
    }
  }
  return 0;
}
