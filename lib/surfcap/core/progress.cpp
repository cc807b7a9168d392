#include "surfcap/core/progress.hpp"

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <cstdio>

namespace surfcap::core {

ProgressReporter::ProgressReporter(std::string label, std::size_t total, int terminal,
                                   std::chrono::milliseconds log_interval)
    : label_(std::move(label)),
      total_(total),
      terminal_(terminal < 0 ? ::isatty(::fileno(stderr)) != 0 : terminal != 0),
      log_interval_(log_interval),
      start_(std::chrono::steady_clock::now()),
      last_print_(start_) {}

ProgressReporter::~ProgressReporter() { finish(); }

std::string ProgressReporter::status_line() const {
  const std::size_t done = done_.load();
  const double fraction = total_ == 0 ? 1.0 : static_cast<double>(done) / static_cast<double>(total_);
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  constexpr int width = 30;
  const int filled = static_cast<int>(fraction * width);
  std::string bar = "[" + std::string(static_cast<std::size_t>(filled), '#') +
                    std::string(static_cast<std::size_t>(width - filled), '-') + "]";
  char tail[96];
  if (done > 0 && done < total_) {
    const double eta = elapsed / static_cast<double>(done) * static_cast<double>(total_ - done);
    std::snprintf(tail, sizeof tail, " %3d%% %zu/%zu eta %.0fs", static_cast<int>(fraction * 100), done, total_, eta);
  } else {
    std::snprintf(tail, sizeof tail, " %3d%% %zu/%zu %.1fs", static_cast<int>(fraction * 100), done, total_, elapsed);
  }
  return label_ + " " + bar + tail;
}

void ProgressReporter::update(std::size_t done) {
  const auto now = std::chrono::steady_clock::now();
  std::lock_guard lock(mutex_);
  if (finished_) return;
  if (terminal_) {
    if (now - last_print_ < std::chrono::milliseconds(100) && done < total_) return;
    std::fprintf(stderr, "\r%s\033[K", status_line().c_str());
    std::fflush(stderr);
  } else {
    if (now - last_print_ < log_interval_) return;
    spdlog::info("{}", status_line());
  }
  last_print_ = now;
}

void ProgressReporter::advance(std::size_t items) { update(done_.fetch_add(items) + items); }

ProgressCallback ProgressReporter::callback() {
  return [this](std::size_t done, std::size_t total) {
    if (total != total_) total_ = total;
    std::size_t previous = done_.load();
    while (done > previous && !done_.compare_exchange_weak(previous, done)) {
    }
    update(done);
  };
}

void ProgressReporter::finish() {
  std::lock_guard lock(mutex_);
  if (finished_) return;
  finished_ = true;
  if (terminal_) {
    std::fprintf(stderr, "\r%s\033[K\n", status_line().c_str());
    std::fflush(stderr);
  } else if (std::chrono::steady_clock::now() - start_ >= log_interval_) {
    spdlog::info("{}", status_line());
  }
}

}  // namespace surfcap::core
