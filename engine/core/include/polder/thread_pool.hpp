// The one pool of worker threads every parallel part of Polder runs on.
//
// It runs on oneTBB: a ThreadPool is a task arena over oneTBB's single set of workers, so
// the pools that different parts make (the terrain engine's, a mesh build's, a host's own
// oneTBB work) share those threads instead of each starting its own. A pool's size caps how
// many threads its work uses at once; making one is cheap. Work given to a pool never relies
// on running concurrently: with one thread it all runs on the calling thread, in turn, and
// gives the same result. ThreadSanitizer builds (POLDER_SANITIZE_THREAD) run it on std::thread
// workers instead, since that tool cannot see oneTBB's synchronisation.
//
// Exceptions thrown by the work reach the caller once every part of the call has ended (the
// first one, where several throw).
#pragma once

#include <cstddef>
#include <functional>
#include <memory>

namespace polder::core {

class ThreadPool {
 public:
  // `threads` <= 0, or more than the hardware threads this process may use: that many.
  explicit ThreadPool(int threads = 0);
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  // The most threads this pool's work runs on at once, the calling thread included.
  int threadCount() const noexcept;

  // Calls body(begin, end) on ranges that together cover [0, count) once each, on up to
  // threadCount() threads. `grain`: the items worth a task of their own; ranges are split
  // no finer than about that (all of [0, count) in one call where count <= grain).
  template <class Body>
  void forRanges(std::size_t count, std::size_t grain, const Body& body) {
    if (count == 0) return;
    if (threadCount() <= 1 || count <= grain) {  // one range, on the calling thread
      body(std::size_t(0), count);
      return;
    }
    forRangesErased(count, grain, &body, [](const void* f, std::size_t begin, std::size_t end) {
      (*static_cast<const Body*>(f))(begin, end);
    });
  }

  // Calls half(0) and half(1), at once where a second thread is free.
  template <class Half>
  void runHalves(const Half& half) {
    runHalvesErased(&half, [](const void* f, int which) { (*static_cast<const Half*>(f))(which); });
  }

  // Runs `lead` on the calling thread, while the background tasks it starts through the
  // given handle run on the pool's other threads, or on the calling thread once `lead` has
  // returned where no other thread is free; returns once all have ended. A background task
  // must not wait for `lead` to go on (it may find no thread to run on until `lead` ends);
  // the work `lead` does through this pool meanwhile runs isolated from them, so that a
  // thread waiting inside it never takes up a background task.
  class Background {
   public:
    virtual void start(std::function<void()> task) = 0;

   protected:
    ~Background() = default;
  };
  void runWithBackground(const std::function<void(Background&)>& lead);

 private:
  using RangeCall = void (*)(const void*, std::size_t, std::size_t);
  using HalfCall = void (*)(const void*, int);
  void forRangesErased(std::size_t count, std::size_t grain, const void* body, RangeCall call);
  void runHalvesErased(const void* half, HalfCall call);

  struct Arena;
  std::unique_ptr<Arena> m_arena;
};

}  // namespace polder::core
