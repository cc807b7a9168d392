#pragma once
// The machine-readable report every stage writes: timings and quality figures.

#include <chrono>
#include <filesystem>
#include <string>

#include "surfcap/core/json_document.hpp"

namespace surfcap::core {

/// This process's peak resident memory so far (getrusage's ru_maxrss), MiB; 0 where unknown.
double peak_rss_mb();
/// CPU time of this process so far (user + system, every thread), seconds.
double process_cpu_seconds();
/// Keeps freed large buffers in this process's heap instead of unmapping them (glibc's mmap and
/// trim thresholds raised): a stage that allocates and frees image- or mesh-sized buffers many
/// times per frame pays no page faults for them (zeroing fresh pages is otherwise most of its
/// system time). Peak memory is unchanged; freed memory is reused, not returned early.
void retain_freed_memory();

/// {"format":"surfcap.report/1","stage","version","timings_s":{...},"total_s","cpu_s","peak_rss_mb",
///  ...figures}; cpu_s and peak_rss_mb are the process's up to the moment the report is written.
class StageReport {
 public:
  explicit StageReport(std::string stage);

  /// Quality figures and anything else the stage wants to say; written at the top level.
  Json& figures() { return figures_; }
  void add_timing(const std::string& step, double seconds);

  /// Measures one step from construction to destruction (or stop()).
  class Timer {
   public:
    Timer(StageReport& report, std::string step);
    ~Timer();
    double stop();

   private:
    StageReport* report_;
    std::string step_;
    std::chrono::steady_clock::time_point start_;
    bool stopped_ = false;
  };
  Timer time(std::string step) { return Timer(*this, std::move(step)); }

  Json to_json() const;
  /// Writes atomically (JSON, sorted keys).
  void write(const std::filesystem::path& path) const;

 private:
  std::string stage_;
  Json figures_ = Json::object();
  Json timings_ = Json::object();
  std::chrono::steady_clock::time_point start_;
};

}  // namespace surfcap::core
