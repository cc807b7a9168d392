#pragma once
// Data-parallel loops with an explicit thread count (OpenMP). Each index writes its own output
// slot, so results do not depend on the thread count or the schedule.

#include <omp.h>

#include <exception>
#include <mutex>

namespace surfcap::core {

/// Threads to use for a requested count: ≤ 0 means all hardware threads.
inline int resolve_threads(int requested) { return requested > 0 ? requested : omp_get_num_procs(); }

/// Calls body(i) for i in [0, count) on `threads` threads (≤ 0: all). After a failure the
/// remaining iterations are skipped and the exception of the lowest failed index is rethrown.
template <class Body>
void parallel_for(long count, int threads, Body&& body) {
  const int workers = resolve_threads(threads);
  if (workers == 1 || count <= 1) {
    for (long i = 0; i < count; ++i) body(i);
    return;
  }
  std::exception_ptr failure;
  long failed_index = count;
  std::mutex failure_mutex;
  bool failed = false;
#pragma omp parallel for schedule(dynamic, 1) num_threads(workers)
  for (long i = 0; i < count; ++i) {
    bool skip;
#pragma omp atomic read
    skip = failed;
    if (skip) continue;
    try {
      body(i);
    } catch (...) {
      std::lock_guard lock(failure_mutex);
      if (i < failed_index) {
        failure = std::current_exception();
        failed_index = i;
      }
#pragma omp atomic write
      failed = true;
    }
  }
  if (failure) std::rethrow_exception(failure);
}

}  // namespace surfcap::core
