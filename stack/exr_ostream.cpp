#include "stack/exr_ostream.h"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <stdexcept>
#include <unistd.h>

namespace skypol::stack {

BackgroundFileStream::BackgroundFileStream(const std::string& path, std::size_t block_bytes, int blocks)
    : Imf::OStream(path.c_str()), path_(path), block_bytes_(block_bytes), blocks_(blocks < 2 ? 2 : blocks) {
  // 0666 and the umask, as std::ofstream (OpenEXR's own stream) creates files.
  fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd_ < 0) throw std::runtime_error("cannot create " + path + ": " + std::strerror(errno));
  current_.bytes.reserve(block_bytes_);
  blocks_made_ = 1;
  thread_ = std::thread([this] { run(); });
}

BackgroundFileStream::~BackgroundFileStream() {
  {
    std::lock_guard<std::mutex> lock(m_);
    stop_ = true;
  }
  cv_.notify_all();
  if (thread_.joinable()) thread_.join();
  if (fd_ >= 0) ::close(fd_);
}

void BackgroundFileStream::run() {
  std::unique_lock<std::mutex> lock(m_);
  for (;;) {
    cv_.wait(lock, [&] { return stop_ || !queued_.empty(); });
    if (queued_.empty()) return;  // stopping, and everything handed over is written
    Block b = std::move(queued_.front());
    queued_.pop_front();
    busy_ = true;
    lock.unlock();
    // Write the block whole: pwrite may write less than asked, and EINTR is not a failure.
    std::string failure;
    const char* p = b.bytes.data();
    std::size_t left = b.bytes.size();
    uint64_t at = b.offset;
    while (left > 0 && failure.empty()) {
      const ssize_t n = ::pwrite(fd_, p, left, static_cast<off_t>(at));
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) {
        failure = "cannot write " + path_ + ": " + (n < 0 ? std::strerror(errno) : "nothing written");
        break;
      }
      p += n;
      at += static_cast<uint64_t>(n);
      left -= static_cast<std::size_t>(n);
    }
    b.bytes.clear();
    lock.lock();
    busy_ = false;
    if (!failure.empty() && error_.empty()) error_ = failure;
    free_.push_back(std::move(b));
    cv_.notify_all();
  }
}

void BackgroundFileStream::throw_if_failed() {
  std::lock_guard<std::mutex> lock(m_);
  if (!error_.empty()) throw std::runtime_error(error_);
}

void BackgroundFileStream::hand_over() {
  if (current_.bytes.empty()) return;
  const uint64_t next = current_.offset + current_.bytes.size();
  std::unique_lock<std::mutex> lock(m_);
  queued_.push_back(std::move(current_));
  cv_.notify_all();
  if (free_.empty() && blocks_made_ < blocks_) {
    ++blocks_made_;
    current_ = Block{};
    lock.unlock();
    current_.bytes.reserve(block_bytes_);
  } else {
    cv_.wait(lock, [&] { return !free_.empty(); });
    current_ = std::move(free_.back());
    free_.pop_back();
  }
  current_.offset = next;
  current_.bytes.clear();
}

void BackgroundFileStream::write(const char c[], int n) {
  throw_if_failed();
  std::size_t left = n > 0 ? static_cast<std::size_t>(n) : 0;
  while (left > 0) {
    const std::size_t room = block_bytes_ - current_.bytes.size();
    const std::size_t take = left < room ? left : room;
    current_.bytes.insert(current_.bytes.end(), c, c + take);
    c += take;
    left -= take;
    if (current_.bytes.size() == block_bytes_) hand_over();
  }
}

uint64_t BackgroundFileStream::tellp() { return current_.offset + current_.bytes.size(); }

void BackgroundFileStream::seekp(uint64_t pos) {
  if (pos == tellp()) return;
  throw_if_failed();
  hand_over();  // the gathered bytes keep their offset; the next ones start at pos
  current_.offset = pos;
}

void BackgroundFileStream::finish() {
  hand_over();
  {
    std::unique_lock<std::mutex> lock(m_);
    cv_.wait(lock, [&] { return queued_.empty() && !busy_; });
    if (!error_.empty()) throw std::runtime_error(error_);
  }
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0) throw std::runtime_error("cannot close " + path_ + ": " + std::strerror(errno));
}

}  // namespace skypol::stack
