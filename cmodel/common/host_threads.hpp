#pragma once

#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace rpu {

// Runs worker(i) for i in [0, n) on n host threads, the caller's being i = 0, and once
// all have returned rethrows the first exception one of them threw. An exception must
// not leave a std::jthread (the process would end in std::terminate): an error on any
// thread reaches the caller, as on one thread.
template <class Worker>
void run_host_threads(int n, Worker&& worker) {
  std::mutex mutex;
  std::exception_ptr first;
  const auto guarded = [&](int i) {
    try {
      worker(i);
    } catch (...) {
      const std::lock_guard lock(mutex);
      if (!first) first = std::current_exception();
    }
  };
  {
    std::vector<std::jthread> pool;
    for (int i = 1; i < n; ++i) pool.emplace_back(guarded, i);
    guarded(0);
  }
  if (first) std::rethrow_exception(first);
}

}  // namespace rpu
