#pragma once

#include <atomic>
#include <exception>
#include <latch>
#include <mutex>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

#include "common/error.hpp"

namespace rpu {

// Runs worker(i) for i in [0, n) on n host threads, the caller's being i = 0, and once
// all have returned rethrows the first exception one of them threw. An exception must
// not leave a std::jthread (the process would end in std::terminate): an error on any
// thread reaches the caller, as on one thread. The threads wait at a gate until all are
// started, so that when the host refuses one (EAGAIN under a limit on processes or
// memory) none has begun the work: the started ones leave, and the refusal is an
// rpu::Error.
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
  std::latch gate(1);
  std::atomic<bool> abandoned = false;
  {
    std::vector<std::jthread> pool;
    try {
      for (int i = 1; i < n; ++i) {
        pool.emplace_back([&, i] {
          gate.wait();
          if (!abandoned) guarded(i);
        });
      }
    } catch (const std::system_error& e) {
      abandoned = true;
      gate.count_down();
      const std::size_t started = pool.size() + 1;
      pool.clear();
      throw Error("cannot start " + std::to_string(n) + " host threads: the host started " + std::to_string(started) +
                  " (" + e.code().message() + "); ask for fewer with --threads");
    }
    gate.count_down();
    guarded(0);
  }
  if (first) std::rethrow_exception(first);
}

}  // namespace rpu
