#include "log_sink.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>

namespace roam {
namespace runtime {
namespace {

void putBigEndian(std::vector<uint8_t>* out, uint64_t value, int bytes) {
  for (int i = bytes - 1; i >= 0; --i) out->push_back(static_cast<uint8_t>(value >> (8 * i)));
}

}  // namespace

LogSink::LogSink(const std::string& path) : path_(path) {
  const auto parent = std::filesystem::path(path).parent_path();
  std::error_code ec;
  if (!parent.empty()) std::filesystem::create_directories(parent, ec);
  fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) {
    throw std::runtime_error(path + ": cannot create the output log: " + std::strerror(errno));
  }
}

LogSink::~LogSink() {
  if (fd_ >= 0) ::close(fd_);
}

void LogSink::fail(const std::string& why) {
  if (failed()) return;
  error_ = path_ + ": " + why + "; the " + std::to_string(events_) + " events before it are intact";
  if (stop_ != nullptr) stop_->store(true);
}

void LogSink::checkStillThere() {
  struct stat open_file {}, at_path {};
  if (::fstat(fd_, &open_file) != 0) return;
  if (::stat(path_.c_str(), &at_path) != 0 || at_path.st_ino != open_file.st_ino ||
      at_path.st_dev != open_file.st_dev) {
    error_ = path_ + ": the output log was removed during the run (the file or its folder): the events "
             "written to it are lost";
    if (stop_ != nullptr) stop_->store(true);
  }
}

void LogSink::write(const std::string& channel, int64_t utime, const void* data, int size) {
  if (failed()) return;
  buffer_.clear();
  putBigEndian(&buffer_, kLogSyncWord, 4);
  putBigEndian(&buffer_, static_cast<uint64_t>(events_), 8);
  putBigEndian(&buffer_, static_cast<uint64_t>(utime), 8);
  putBigEndian(&buffer_, static_cast<uint32_t>(channel.size()), 4);
  putBigEndian(&buffer_, static_cast<uint32_t>(size), 4);
  buffer_.insert(buffer_.end(), channel.begin(), channel.end());
  const auto* bytes = static_cast<const uint8_t*>(data);
  buffer_.insert(buffer_.end(), bytes, bytes + size);
  size_t written = 0;
  while (written < buffer_.size()) {
    const ssize_t n = ::write(fd_, buffer_.data() + written, buffer_.size() - written);
    if (n < 0) {
      if (errno == EINTR) continue;
      const int why = errno;
      // Cut off the part of this event that did get written: the log ends with a whole event.
      if (written > 0 && ::ftruncate(fd_, bytes_) == 0) ::lseek(fd_, bytes_, SEEK_SET);
      fail(std::string("cannot write the output log: ") + std::strerror(why));
      return;
    }
    written += static_cast<size_t>(n);
  }
  bytes_ += static_cast<int64_t>(written);
  ++events_;
  if (events_ % 1024 == 0) checkStillThere();
}

void LogSink::flush() {
  if (failed()) return;
  if (::fsync(fd_) != 0 && errno != EINVAL) {
    fail(std::string("cannot write the output log: ") + std::strerror(errno));
    return;
  }
  checkStillThere();
}

}  // namespace runtime
}  // namespace roam
