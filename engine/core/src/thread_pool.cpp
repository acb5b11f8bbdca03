#include "polder/thread_pool.hpp"

#include <tbb/blocked_range.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <exception>

namespace polder::core {

struct ThreadPool::Arena {
  // Never more than oneTBB's worker limit allows: a larger arena gains nothing, and oneTBB
  // warns on stderr when asked for it.
  explicit Arena(int threads)
      : arena(threads > 0 ? std::min(threads, tbb::info::default_concurrency()) : tbb::task_arena::automatic) {
    arena.initialize();
  }
  tbb::task_arena arena;
};

ThreadPool::ThreadPool(int threads) : m_arena(std::make_unique<Arena>(threads)) {}
ThreadPool::~ThreadPool() = default;

int ThreadPool::threadCount() const noexcept { return m_arena->arena.max_concurrency(); }

void ThreadPool::forRangesErased(std::size_t count, std::size_t grain, const void* body, RangeCall call) {
  grain = std::max<std::size_t>(grain, 1);
  m_arena->arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, grain),
                      [&](const tbb::blocked_range<std::size_t>& range) { call(body, range.begin(), range.end()); });
  });
}

void ThreadPool::runHalvesErased(const void* half, HalfCall call) {
  if (threadCount() <= 1) {
    call(half, 0);
    call(half, 1);
    return;
  }
  m_arena->arena.execute([&] { tbb::parallel_invoke([&] { call(half, 0); }, [&] { call(half, 1); }); });
}

namespace {

class GroupBackground final : public ThreadPool::Background {
 public:
  explicit GroupBackground(tbb::task_group& group) : m_group(group) {}
  void start(std::function<void()> task) override { m_group.run(std::move(task)); }

 private:
  tbb::task_group& m_group;
};

}  // namespace

void ThreadPool::runWithBackground(const std::function<void(Background&)>& lead) {
  m_arena->arena.execute([&] {
    tbb::task_group group;
    GroupBackground background(group);
    std::exception_ptr leadFailed;
    try {
      tbb::this_task_arena::isolate([&] { lead(background); });
    } catch (...) {
      leadFailed = std::current_exception();
    }
    try {
      group.wait();
    } catch (...) {
      if (!leadFailed) leadFailed = std::current_exception();
    }
    if (leadFailed) std::rethrow_exception(leadFailed);
  });
}

}  // namespace polder::core
