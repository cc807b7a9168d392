#pragma once
// Progress of long work: the library reports through a callback; tools show it as a bar on a
// terminal or as periodic log lines otherwise (farm logs).

#include <atomic>
#include <chrono>
#include <cstddef>
#include <functional>
#include <mutex>
#include <string>

namespace surfcap::core {

/// Called by library code as work completes: (items done so far, total items). May be called
/// from several threads; may be empty.
using ProgressCallback = std::function<void(std::size_t done, std::size_t total)>;

class ProgressReporter {
 public:
  /// `terminal` < 0: detect whether stderr is a terminal.
  ProgressReporter(std::string label, std::size_t total, int terminal = -1,
                   std::chrono::milliseconds log_interval = std::chrono::seconds(5));
  ~ProgressReporter();
  ProgressReporter(const ProgressReporter&) = delete;
  ProgressReporter& operator=(const ProgressReporter&) = delete;

  /// Thread-safe.
  void advance(std::size_t items = 1);
  void finish();
  /// A callback for library code that forwards the absolute count.
  ProgressCallback callback();

  std::size_t done() const { return done_.load(); }
  /// The line the reporter would print now, e.g. "align [#####-----] 50% 10/20 eta 3s".
  std::string status_line() const;

 private:
  void update(std::size_t done);

  std::string label_;
  std::size_t total_;
  bool terminal_;
  std::chrono::milliseconds log_interval_;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_print_;
  std::atomic<std::size_t> done_{0};
  std::mutex mutex_;
  bool finished_ = false;
};

}  // namespace surfcap::core
