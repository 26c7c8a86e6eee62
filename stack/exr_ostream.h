// An OpenEXR output stream whose bytes reach the file on a thread of their own: the kernel's copy
// of a stack into the page cache (a third of an uncompressed stack's CPU time) then runs on the
// other core while the caller renders and encodes the next part. OpenEXR writes each uncompressed
// scanline as one small write and seeks back once to fill in the offset tables; this stream
// gathers the writes into large blocks and writes each at its offset (pwrite), in order.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <OpenEXR/ImfIO.h>

namespace skypol::stack {

class BackgroundFileStream final : public Imf::OStream {
 public:
  // Creates (or truncates) `path`; throws std::runtime_error naming it and the system's reason.
  // block_bytes: how much is gathered before a block is handed to the writing thread; at most
  // `blocks` blocks are in memory at once (the caller waits for a free one).
  explicit BackgroundFileStream(const std::string& path, std::size_t block_bytes = std::size_t{256} << 10,
                                int blocks = 4);
  // Closes the file without reporting errors (call finish() for them); waits for the thread.
  ~BackgroundFileStream() override;

  void write(const char c[], int n) override;
  uint64_t tellp() override;
  void seekp(uint64_t pos) override;

  // Writes what is gathered, waits until every block is in the file and closes it. Throws
  // std::runtime_error naming the file for any failed write or close, including earlier ones.
  void finish();

 private:
  struct Block {
    uint64_t offset = 0;
    std::vector<char> bytes;
  };
  void hand_over();  // the current block to the thread; a free one (or a new one) becomes current
  void run();        // the thread: writes queued blocks in order, returns emptied ones
  void throw_if_failed();

  std::string path_;
  int fd_ = -1;
  std::size_t block_bytes_;
  int blocks_;
  int blocks_made_ = 0;
  Block current_;

  std::mutex m_;
  std::condition_variable cv_;
  std::deque<Block> queued_;   // to write, in order
  std::vector<Block> free_;    // written, their memory kept
  bool busy_ = false;          // the thread is writing a block it took from queued_
  bool stop_ = false;
  std::string error_;          // the first failure, reported by write()/seekp()/finish()
  std::thread thread_;
};

}  // namespace skypol::stack
