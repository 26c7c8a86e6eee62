// Progress on a terminal: a bar, the count, the rate and the time left, redrawn at most 10 times a
// second (a pipe or a file gets nothing: logs stay clean, tests see no progress).
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <cstdio>
#include <unistd.h>

#include "cli/commands.h"

namespace skypol::cli {
namespace {

std::string duration_text(double s) {
  char buf[32];
  if (s < 60) std::snprintf(buf, sizeof buf, "%.0f s", s);
  else if (s < 3600) std::snprintf(buf, sizeof buf, "%d min %02d s", static_cast<int>(s / 60), static_cast<int>(s) % 60);
  else std::snprintf(buf, sizeof buf, "%d h %02d min", static_cast<int>(s / 3600), static_cast<int>(s / 60) % 60);
  return buf;
}

}  // namespace

Progress make_progress(bool quiet, const char* unit) {
  Progress p;
  p.enabled = !quiet && ::isatty(STDERR_FILENO) != 0;
  p.unit = unit;
  p.start = std::chrono::steady_clock::now();
  return p;
}

std::string progress_line(std::size_t done, std::size_t total, double elapsed_s, const char* unit) {
  constexpr int width = 30;
  const int filled = static_cast<int>(width * done / total);
  char line[160];
  int k = std::snprintf(line, sizeof line, "[%.*s%*s] %zu/%zu %s", filled, "##############################",
                        width - filled, "", done, total, unit);
  if (done > 0 && elapsed_s > 0) {
    const double rate = static_cast<double>(done) / elapsed_s;
    const std::string left = duration_text(static_cast<double>(total - done) / rate);
    // A slow rate reads better as seconds per item.
    if (rate >= 1) {
      k += std::snprintf(line + k, sizeof line - static_cast<std::size_t>(k), ", %.1f/s", rate);
    } else {
      k += std::snprintf(line + k, sizeof line - static_cast<std::size_t>(k), ", %.1f s each", 1 / rate);
    }
    std::snprintf(line + k, sizeof line - static_cast<std::size_t>(k), done < total ? ", %s left" : ", %s",
                  done < total ? left.c_str() : duration_text(elapsed_s).c_str());
  }
  return line;
}

void Progress::operator()(std::size_t done, std::size_t total) const {
  if (!enabled || total == 0) return;
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (done < total && elapsed - last_drawn_s < 0.1 && done != 0) return;
  last_drawn_s = elapsed;
  // \033[K clears what a longer previous line left.
  std::fprintf(stderr, "\r%s\033[K", progress_line(done, total, elapsed, unit).c_str());
  if (done == total) std::fprintf(stderr, "\n");
  std::fflush(stderr);
}

struct Ticker::State {
  Progress progress;
  std::mutex m;
  std::condition_variable cv;
  std::size_t done = 0, total = 0;
  bool stop = false;
  bool hidden = false;
  std::thread thread;
};

Ticker::Ticker(Progress p) : state_(std::make_unique<State>()) {
  state_->progress = p;
  if (!p.enabled) return;
  state_->thread = std::thread([s = state_.get()] {
    std::unique_lock<std::mutex> lock(s->m);
    while (!s->cv.wait_for(lock, std::chrono::milliseconds(500), [s] { return s->stop; })) {
      if (!s->hidden && s->total > 0 && s->done < s->total) {
        s->progress.last_drawn_s = -1;  // redraw now, whatever the rate limit says
        s->progress(s->done, s->total);
      }
    }
  });
}

void Ticker::operator()(std::size_t done, std::size_t total) {
  std::lock_guard<std::mutex> lock(state_->m);
  state_->done = done;
  state_->total = total;
  state_->hidden = false;
  state_->progress.last_drawn_s = -1;  // every call is drawn: they are few
  state_->progress(done, total);
}

void Ticker::hide() {
  std::lock_guard<std::mutex> lock(state_->m);
  if (!state_->progress.enabled || state_->hidden || state_->done >= state_->total) return;
  std::fprintf(stderr, "\r\033[K");
  std::fflush(stderr);
  state_->hidden = true;
}

Ticker::~Ticker() {
  if (!state_->thread.joinable()) return;
  {
    std::lock_guard<std::mutex> lock(state_->m);
    state_->stop = true;
  }
  state_->cv.notify_all();
  state_->thread.join();
}

}  // namespace skypol::cli
