// Framing and encoding for the pipe between roam-run and an isolated estimator's child process.
//
// Both ends are the same binary (the child is a fork of roam-run), so plain structs travel as
// sizeof(T) byte copies: the protocol never spells out a struct's layout, and a field added to
// roam_odometry or roam_pose needs no change here. A frame is a 4-byte length and its bytes.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

namespace roam {
namespace runtime {
namespace wire {

class Writer {
 public:
  template <typename T>
  Writer& pod(const T& value) {
    static_assert(std::is_trivially_copyable<T>::value, "byte copies only");
    append(&value, sizeof(T));
    return *this;
  }
  Writer& str(const std::string& text) {
    pod(static_cast<uint32_t>(text.size()));
    append(text.data(), text.size());
    return *this;
  }
  template <typename T>
  Writer& pods(const std::vector<T>& values) {
    static_assert(std::is_trivially_copyable<T>::value, "byte copies only");
    pod(static_cast<uint32_t>(values.size()));
    append(values.data(), values.size() * sizeof(T));
    return *this;
  }
  Writer& strs(const std::vector<std::string>& values) {
    pod(static_cast<uint32_t>(values.size()));
    for (const auto& value : values) str(value);
    return *this;
  }
  void clear() { bytes_.clear(); }
  const std::vector<uint8_t>& bytes() const { return bytes_; }

 private:
  // resize + memcpy rather than vector::insert, which GCC 12 warns about wrongly when inlined.
  void append(const void* data, size_t size) {
    if (size == 0) return;
    const size_t at = bytes_.size();
    bytes_.resize(at + size);
    std::memcpy(bytes_.data() + at, data, size);
  }
  std::vector<uint8_t> bytes_;
};

// Reads what a Writer wrote; ok() turns false (and stays false) at the first short read.
class Reader {
 public:
  Reader(const uint8_t* data, size_t size) : at_(data), end_(data + size) {}
  template <typename T>
  T pod() {
    T value{};
    if (take(sizeof(T))) std::memcpy(&value, at_ - sizeof(T), sizeof(T));
    return value;
  }
  std::string str() {
    const uint32_t n = pod<uint32_t>();
    if (!take(n)) return {};
    return std::string(reinterpret_cast<const char*>(at_ - n), n);
  }
  template <typename T>
  std::vector<T> pods() {
    const uint32_t n = pod<uint32_t>();
    std::vector<T> values;
    if (n > static_cast<size_t>(end_ - at_) / sizeof(T) || !take(n * sizeof(T))) {
      ok_ = false;
      return values;
    }
    values.resize(n);
    if (n > 0) std::memcpy(values.data(), at_ - n * sizeof(T), n * sizeof(T));
    return values;
  }
  std::vector<std::string> strs() {
    const uint32_t n = pod<uint32_t>();
    std::vector<std::string> values;
    for (uint32_t i = 0; i < n && ok_; ++i) values.push_back(str());
    return values;
  }
  bool ok() const { return ok_; }

 private:
  bool take(size_t n) {
    if (!ok_ || n > static_cast<size_t>(end_ - at_)) {
      ok_ = false;
      return false;
    }
    at_ += n;
    return true;
  }
  const uint8_t* at_;
  const uint8_t* end_;
  bool ok_ = true;
};

enum class IoResult { kOk, kClosed, kTimedOut };

// Writes one frame (length and bytes). kClosed if the other end is gone (no SIGPIPE).
IoResult sendFrame(int fd, const std::vector<uint8_t>& bytes);
// Reads one frame into *bytes. deadline_s: seconds on the steady clock (see nowSeconds()) by
// which the whole frame must have arrived; <= 0 waits for ever.
IoResult receiveFrame(int fd, std::vector<uint8_t>* bytes, double deadline_s);
double nowSeconds();

}  // namespace wire
}  // namespace runtime
}  // namespace roam
