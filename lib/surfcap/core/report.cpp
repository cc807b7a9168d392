#include "surfcap/core/report.hpp"

#include <malloc.h>
#include <sys/resource.h>

#include "surfcap/core/version.hpp"

namespace surfcap::core {

double peak_rss_mb() {
  rusage usage{};
  if (getrusage(RUSAGE_SELF, &usage) != 0) return 0.0;
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // Linux: kilobytes
}

void retain_freed_memory() {
  mallopt(M_MMAP_THRESHOLD, 256 << 20);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
}

double process_cpu_seconds() {
  rusage usage{};
  if (getrusage(RUSAGE_SELF, &usage) != 0) return 0.0;
  auto seconds = [](const timeval& t) { return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec); };
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

StageReport::StageReport(std::string stage) : stage_(std::move(stage)), start_(std::chrono::steady_clock::now()) {}

void StageReport::add_timing(const std::string& step, double seconds) {
  timings_[step] = timings_.value(step, 0.0) + seconds;
}

StageReport::Timer::Timer(StageReport& report, std::string step)
    : report_(&report), step_(std::move(step)), start_(std::chrono::steady_clock::now()) {}

StageReport::Timer::~Timer() { stop(); }

double StageReport::Timer::stop() {
  if (stopped_) return 0.0;
  stopped_ = true;
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  report_->add_timing(step_, seconds);
  return seconds;
}

Json StageReport::to_json() const {
  Json document = figures_;
  document["format"] = format_tag("report", 1);
  document["stage"] = stage_;
  document["version"] = std::string(version());
  document["timings_s"] = timings_;
  document["total_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  document["cpu_s"] = process_cpu_seconds();
  document["peak_rss_mb"] = peak_rss_mb();
  return document;
}

void StageReport::write(const std::filesystem::path& path) const { write_json_file(path, to_json()); }

}  // namespace surfcap::core
