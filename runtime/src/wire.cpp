#include "wire.hpp"

#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>

namespace roam {
namespace runtime {
namespace wire {
namespace {

IoResult sendAll(int fd, const uint8_t* data, size_t size) {
  while (size > 0) {
    const ssize_t n = ::send(fd, data, size, MSG_NOSIGNAL);
    if (n < 0) {
      if (errno == EINTR) continue;
      return IoResult::kClosed;
    }
    data += n;
    size -= static_cast<size_t>(n);
  }
  return IoResult::kOk;
}

IoResult receiveAll(int fd, uint8_t* data, size_t size, double deadline_s) {
  while (size > 0) {
    if (deadline_s > 0.0) {
      const double left_s = deadline_s - nowSeconds();
      if (left_s <= 0.0) return IoResult::kTimedOut;
      pollfd wait{fd, POLLIN, 0};
      const int ready = ::poll(&wait, 1, static_cast<int>(std::ceil(left_s * 1e3)));
      if (ready < 0 && errno == EINTR) continue;
      if (ready == 0) continue;  // the loop re-checks the deadline
    }
    const ssize_t n = ::read(fd, data, size);
    if (n < 0) {
      if (errno == EINTR) continue;
      return IoResult::kClosed;
    }
    if (n == 0) return IoResult::kClosed;
    data += n;
    size -= static_cast<size_t>(n);
  }
  return IoResult::kOk;
}

}  // namespace

double nowSeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

IoResult sendFrame(int fd, const std::vector<uint8_t>& bytes) {
  const uint32_t size = static_cast<uint32_t>(bytes.size());
  // One write for small frames (the common case: an odometry step), two otherwise.
  if (bytes.size() <= 4096) {
    uint8_t frame[4 + 4096];
    std::memcpy(frame, &size, 4);
    std::memcpy(frame + 4, bytes.data(), bytes.size());
    return sendAll(fd, frame, 4 + bytes.size());
  }
  const IoResult head = sendAll(fd, reinterpret_cast<const uint8_t*>(&size), 4);
  if (head != IoResult::kOk) return head;
  return sendAll(fd, bytes.data(), bytes.size());
}

IoResult receiveFrame(int fd, std::vector<uint8_t>* bytes, double deadline_s) {
  uint32_t size = 0;
  const IoResult head = receiveAll(fd, reinterpret_cast<uint8_t*>(&size), 4, deadline_s);
  if (head != IoResult::kOk) return head;
  bytes->resize(size);
  return receiveAll(fd, bytes->data(), size, deadline_s);
}

}  // namespace wire
}  // namespace runtime
}  // namespace roam
