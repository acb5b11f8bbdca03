// Running one work function on several threads at once, for work the threads share out
// among themselves (e.g. by taking items from an atomic counter).
#pragma once

#include <algorithm>
#include <cstddef>
#include <system_error>
#include <thread>
#include <vector>

namespace polder::query::detail {

// Runs `work()` on `threads` threads (0 or less = hardware concurrency), at most
// `maxThreads` and at least one, the calling thread among them, and returns once every call
// has returned. A thread that cannot be started is left out: the others, which share the
// work, do its part.
template <class Work>
void runOnThreads(int threads, std::size_t maxThreads, const Work& work) {
  const std::size_t wanted = threads > 0 ? std::size_t(threads) : std::size_t(std::thread::hardware_concurrency());
  const std::size_t count = std::clamp<std::size_t>(wanted, 1, std::max<std::size_t>(maxThreads, 1));
  std::vector<std::thread> workers;
  workers.reserve(count - 1);
  for (std::size_t i = 1; i < count; ++i) {
    try {
      workers.emplace_back([&work] { work(); });
    } catch (const std::system_error&) {
      break;
    }
  }
  work();
  for (std::thread& worker : workers) worker.join();
}

}  // namespace polder::query::detail
