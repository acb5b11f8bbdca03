// core::ThreadPool on std::thread workers, for ThreadSanitizer builds only
// (POLDER_SANITIZE_THREAD): oneTBB's scheduler synchronises through code ThreadSanitizer does
// not see, so every hand-over of work between its threads would read as a race. Here each
// hand-over goes through a mutex and a condition variable, which it does see, and what is
// left to check is Polder's own sharing of data between tasks. Same contract as the oneTBB
// pool (thread_pool.cpp): a waiting thread only runs parts of the call it waits for.
#include "polder/thread_pool.hpp"

#include <algorithm>
#include <condition_variable>
#include <deque>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace polder::core {
namespace {

// One call's parts, handed out (`next`) and counted when they end (`finished`) under the
// pool's lock.
struct Batch {
  std::size_t parts = 0;
  std::size_t next = 0;
  std::size_t finished = 0;
  std::function<void(std::size_t)> run;
  std::exception_ptr failure;
};

}  // namespace

struct ThreadPool::Arena {
  explicit Arena(int threads) {
    const int hardware = std::max(1, int(std::thread::hardware_concurrency()));
    threadCount = threads > 0 ? std::min(threads, hardware) : hardware;
    for (int i = 1; i < threadCount; ++i) workers.emplace_back([this] { work(); });
  }
  ~Arena() {
    {
      std::lock_guard lock(mutex);
      stopping = true;
    }
    wake.notify_all();
    for (std::thread& worker : workers) worker.join();
  }

  // Runs one part of `batch` if one is left; false when none is.
  bool runOne(const std::shared_ptr<Batch>& batch, std::unique_lock<std::mutex>& lock) {
    if (batch->next >= batch->parts) return false;
    const std::size_t part = batch->next++;
    if (batch->next == batch->parts) queue.erase(std::find(queue.begin(), queue.end(), batch));
    lock.unlock();
    std::exception_ptr failure;
    try {
      batch->run(part);
    } catch (...) {
      failure = std::current_exception();
    }
    lock.lock();
    if (failure && !batch->failure) batch->failure = failure;
    ++batch->finished;
    done.notify_all();
    return true;
  }

  void work() {
    std::unique_lock lock(mutex);
    while (true) {
      wake.wait(lock, [&] { return stopping || !queue.empty(); });
      if (stopping) return;
      const std::shared_ptr<Batch> batch = queue.front();
      runOne(batch, lock);
    }
  }

  // Runs what is left of the batch on the calling thread, waits for the parts others took.
  void helpAndWait(const std::shared_ptr<Batch>& batch) {
    std::unique_lock lock(mutex);
    while (runOne(batch, lock)) {
    }
    done.wait(lock, [&] { return batch->finished == batch->parts; });
    if (batch->failure) std::rethrow_exception(batch->failure);
  }

  void enqueue(std::shared_ptr<Batch> batch) {
    {
      std::lock_guard lock(mutex);
      queue.push_back(std::move(batch));
    }
    wake.notify_all();
  }

  void runAndWait(const std::shared_ptr<Batch>& batch) {
    enqueue(batch);
    helpAndWait(batch);
  }

  int threadCount = 1;
  std::mutex mutex;
  std::condition_variable wake, done;
  std::deque<std::shared_ptr<Batch>> queue;
  bool stopping = false;
  std::vector<std::thread> workers;  // last: they start once the rest is made
};

ThreadPool::ThreadPool(int threads) : m_arena(std::make_unique<Arena>(threads)) {}
ThreadPool::~ThreadPool() = default;

int ThreadPool::threadCount() const noexcept { return m_arena->threadCount; }

void ThreadPool::forRangesErased(std::size_t count, std::size_t grain, const void* body, RangeCall call) {
  grain = std::max<std::size_t>(grain, 1);
  auto batch = std::make_shared<Batch>();
  batch->parts = (count + grain - 1) / grain;
  batch->run = [&](std::size_t part) { call(body, part * grain, std::min(count, (part + 1) * grain)); };
  m_arena->runAndWait(batch);
}

void ThreadPool::runHalvesErased(const void* half, HalfCall call) {
  if (threadCount() <= 1) {
    call(half, 0);
    call(half, 1);
    return;
  }
  auto batch = std::make_shared<Batch>();
  batch->parts = 2;
  batch->run = [&](std::size_t part) { call(half, int(part)); };
  m_arena->runAndWait(batch);
}

namespace {

// Background tasks gathered while `lead` runs, each queued as a batch of one part.
class QueuedBackground final : public ThreadPool::Background {
 public:
  explicit QueuedBackground(std::function<void(std::shared_ptr<Batch>)> queue) : m_queue(std::move(queue)) {}
  void start(std::function<void()> task) override {
    auto batch = std::make_shared<Batch>();
    batch->parts = 1;
    batch->run = [task = std::move(task)](std::size_t) { task(); };
    m_batches.push_back(batch);
    m_queue(batch);
  }
  const std::vector<std::shared_ptr<Batch>>& batches() const { return m_batches; }

 private:
  std::function<void(std::shared_ptr<Batch>)> m_queue;
  std::vector<std::shared_ptr<Batch>> m_batches;
};

}  // namespace

void ThreadPool::runWithBackground(const std::function<void(Background&)>& lead) {
  Arena& arena = *m_arena;
  QueuedBackground background([&arena](std::shared_ptr<Batch> batch) { arena.enqueue(std::move(batch)); });
  std::exception_ptr failure;
  try {
    lead(background);
  } catch (...) {
    failure = std::current_exception();
  }
  // What no worker took yet runs here; then every task has ended.
  for (const std::shared_ptr<Batch>& batch : background.batches()) {
    try {
      arena.helpAndWait(batch);
    } catch (...) {
      if (!failure) failure = std::current_exception();
    }
  }
  if (failure) std::rethrow_exception(failure);
}

}  // namespace polder::core
