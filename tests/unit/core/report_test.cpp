// StageReport: the fields every stage's report carries beside its own figures.
#include <gtest/gtest.h>

#include <cstring>
#include <memory>

#include "surfcap/core/json_document.hpp"
#include "surfcap/core/report.hpp"
#include "test_support.hpp"

namespace surfcap {
namespace {

TEST(StageReport, CarriesTimingsCpuAndPeakMemory) {
  core::StageReport report("test.stage");
  {
    auto timer = report.time("step");
  }
  // Touch 256 MiB: the peak resident memory the report gives must cover it.
  constexpr std::size_t bytes = std::size_t{256} << 20;
  const std::unique_ptr<char[]> block(new char[bytes]);
  std::memset(block.get(), 1, bytes);
  volatile char sink = block[bytes - 1];
  (void)sink;
  report.figures()["answer"] = 42;
  const core::Json document = report.to_json();
  EXPECT_EQ(document.at("format"), "surfcap.report/1");
  EXPECT_EQ(document.at("stage"), "test.stage");
  EXPECT_EQ(document.at("answer"), 42);
  EXPECT_TRUE(document.at("timings_s").contains("step"));
  EXPECT_GE(document.at("peak_rss_mb").get<double>(), 256.0);
  EXPECT_LE(document.at("peak_rss_mb").get<double>(), core::peak_rss_mb());
  EXPECT_GT(document.at("cpu_s").get<double>(), 0.0);  // touching the block took CPU time
  EXPECT_LE(document.at("cpu_s").get<double>(), core::process_cpu_seconds());

  testing::TemporaryDirectory directory("stage-report");
  report.write(directory / "report.json");
  const core::Json written = core::read_json_file(directory / "report.json");
  EXPECT_GE(written.at("peak_rss_mb").get<double>(), 256.0);
}

}  // namespace
}  // namespace surfcap
