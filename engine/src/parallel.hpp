// Private to the engine's sources: a minimal parallel loop shared by the
// coefficient fit (fit.cpp) and the diagnosis's fits (diagnose_fit.cpp).
#pragma once

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace pteromys {
namespace detail {

/// Runs f(0..n-1) on up to `threads` threads, each taking the next index;
/// rethrows the first exception once every thread has stopped (the others
/// take no new index after it).
template <class F>
void parallel_for(int n, int threads, F&& f) {
  if (threads <= 1 || n <= 1) {
    for (int i = 0; i < n; ++i) f(i);
    return;
  }
  std::atomic<int> next{0};
  std::exception_ptr err;
  std::mutex mu;
  std::vector<std::thread> pool;
  const int nt = std::min(threads, n);
  for (int t = 0; t < nt; ++t)
    pool.emplace_back([&] {
      for (;;) {
        const int i = next++;
        if (i >= n) break;
        try {
          f(i);
        } catch (...) {
          std::lock_guard<std::mutex> lk(mu);
          if (!err) err = std::current_exception();
          next = n;
        }
      }
    });
  for (auto& th : pool) th.join();
  if (err) std::rethrow_exception(err);
}

}  // namespace detail
}  // namespace pteromys
