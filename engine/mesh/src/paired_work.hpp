// Runs two halves of a job at once, many times over: half 0 on the calling thread, half 1
// on a helper thread kept waiting between jobs (a thread started per job may wait
// milliseconds for a core of its own). Where no helper thread starts, the halves run one
// after the other, which must give the same result. An exception from either half comes
// back to the caller, after both halves ended.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <system_error>
#include <thread>
#include <utility>

namespace polder::mesh {

class PairedWork {
 public:
  PairedWork() {
    try {
      m_helper = std::thread([this] { serve(); });
    } catch (const std::system_error&) {
    }
  }

  ~PairedWork() {
    if (!m_helper.joinable()) return;
    {
      std::lock_guard lock(m_mutex);
      m_closing = true;
    }
    m_changed.notify_all();
    m_helper.join();
  }

  PairedWork(const PairedWork&) = delete;
  PairedWork& operator=(const PairedWork&) = delete;

  // Calls half(0) and half(1), at once where the helper thread runs.
  void run(const std::function<void(int)>& half) {
    if (!m_helper.joinable()) {
      half(0);
      half(1);
      return;
    }
    {
      std::lock_guard lock(m_mutex);
      m_half = &half;
      m_helperFailed = nullptr;
      m_pending = true;
    }
    m_changed.notify_all();
    std::exception_ptr failed = runCaught(half, 0);
    std::unique_lock lock(m_mutex);
    m_changed.wait(lock, [&] { return !m_pending; });
    if (!failed) failed = m_helperFailed;
    lock.unlock();
    if (failed) std::rethrow_exception(failed);
  }

 private:
  // Runs half(which); returns what it threw, if anything.
  static std::exception_ptr runCaught(const std::function<void(int)>& half, int which) {
    try {
      half(which);
    } catch (...) {
      return std::current_exception();
    }
    return nullptr;
  }

  void serve() {
    std::unique_lock lock(m_mutex);
    for (;;) {
      m_changed.wait(lock, [&] { return m_pending || m_closing; });
      if (!m_pending) return;
      const std::function<void(int)>& half = *m_half;
      lock.unlock();
      std::exception_ptr failed = runCaught(half, 1);
      lock.lock();
      m_helperFailed = failed;
      m_pending = false;
      m_changed.notify_all();
    }
  }

  std::thread m_helper;
  std::mutex m_mutex;
  std::condition_variable m_changed;
  const std::function<void(int)>* m_half = nullptr;  // guarded by m_mutex
  bool m_pending = false;                            // a half(1) to run or running
  bool m_closing = false;
  std::exception_ptr m_helperFailed;
};

// The first (half 0) or second (half 1) half of the range [0, count).
inline std::pair<std::uint32_t, std::uint32_t> halfOf(std::uint32_t count, int half) {
  return half == 0 ? std::pair{0u, count / 2} : std::pair{count / 2, count};
}

}  // namespace polder::mesh
