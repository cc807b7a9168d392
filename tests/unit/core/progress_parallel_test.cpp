#include <gtest/gtest.h>

#include <atomic>
#include <numeric>
#include <stdexcept>
#include <vector>

#include "surfcap/core/parallel.hpp"
#include "surfcap/core/progress.hpp"

namespace surfcap {
namespace {

TEST(Parallel, EveryIndexRunsOnceWithAnyThreadCount) {
  for (const int threads : {1, 2, 4, 0}) {
    std::vector<int> hits(1000, 0);
    core::parallel_for(1000, threads, [&](long i) { ++hits[static_cast<std::size_t>(i)]; });
    EXPECT_EQ(std::accumulate(hits.begin(), hits.end(), 0), 1000);
    EXPECT_EQ(*std::min_element(hits.begin(), hits.end()), 1);
  }
}

TEST(Parallel, HonoursTheThreadCount) {
  std::atomic<int> active{0}, peak{0};
  core::parallel_for(64, 2, [&](long) {
    const int now = ++active;
    int seen = peak.load();
    while (now > seen && !peak.compare_exchange_weak(seen, now)) {
    }
    volatile double sink = 0;
    for (int k = 0; k < 20000; ++k) sink = sink + k;
    --active;
  });
  EXPECT_LE(peak.load(), 2);
}

TEST(Parallel, RethrowsTheLowestFailedIndex) {
  try {
    core::parallel_for(100, 1, [](long i) {
      if (i == 17 || i == 60) throw std::runtime_error("index " + std::to_string(i));
    });
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "index 17");
  }
  EXPECT_THROW(core::parallel_for(100, 4, [](long i) {
                 if (i == 50) throw std::runtime_error("x");
               }),
               std::runtime_error);
}

TEST(Progress, CountsFromSeveralThreadsAndFormatsTheBar) {
  core::ProgressReporter progress("align", 200, /*terminal=*/0, std::chrono::hours(1));
  core::parallel_for(200, 4, [&](long) { progress.advance(); });
  EXPECT_EQ(progress.done(), 200u);
  const std::string line = progress.status_line();
  EXPECT_NE(line.find("align"), std::string::npos);
  EXPECT_NE(line.find("100%"), std::string::npos);
  EXPECT_NE(line.find("200/200"), std::string::npos);
  progress.finish();
}

TEST(Progress, CallbackTakesAbsoluteCounts) {
  core::ProgressReporter progress("sim", 10, 0, std::chrono::hours(1));
  auto callback = progress.callback();
  callback(3, 10);
  callback(7, 10);
  callback(5, 10);  // late report from a slower thread never goes backwards
  EXPECT_EQ(progress.done(), 7u);
  EXPECT_NE(progress.status_line().find(" 70%"), std::string::npos);
}

}  // namespace
}  // namespace surfcap
