#include <polder/thread_pool.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

namespace polder::core {
namespace {

TEST(ThreadPool, SizeIsWhatWasAskedUpToTheHardware) {
  const int all = ThreadPool(0).threadCount();
  EXPECT_GE(all, 1);
  EXPECT_LE(unsigned(all), std::max(1u, std::thread::hardware_concurrency()));
  EXPECT_EQ(ThreadPool(1).threadCount(), 1);
  EXPECT_EQ(ThreadPool(2).threadCount(), std::min(2, all));
  EXPECT_EQ(ThreadPool(1 << 20).threadCount(), all);
  EXPECT_EQ(ThreadPool(-5).threadCount(), all);
}

TEST(ThreadPool, RangesCoverEveryIndexOnce) {
  for (int threads : {1, 2, 4, 8}) {
    ThreadPool pool(threads);
    for (std::size_t count : {std::size_t(0), std::size_t(1), std::size_t(7), std::size_t(1000), std::size_t(100003)}) {
      std::vector<std::atomic<int>> visits(count);
      std::atomic<std::size_t> emptyRanges{0};
      pool.forRanges(count, 16, [&](std::size_t begin, std::size_t end) {
        if (begin >= end) ++emptyRanges;
        for (std::size_t i = begin; i < end; ++i) ++visits[i];
      });
      EXPECT_EQ(emptyRanges.load(), 0u);
      for (std::size_t i = 0; i < count; ++i) ASSERT_EQ(visits[i].load(), 1) << "index " << i << " of " << count;
    }
  }
}

TEST(ThreadPool, OneThreadRunsEverythingOnTheCallerInOneRange) {
  ThreadPool pool(1);
  const std::thread::id caller = std::this_thread::get_id();
  std::vector<std::pair<std::size_t, std::size_t>> ranges;
  pool.forRanges(500, 4, [&](std::size_t begin, std::size_t end) {
    EXPECT_EQ(std::this_thread::get_id(), caller);
    ranges.emplace_back(begin, end);
  });
  ASSERT_EQ(ranges.size(), 1u);
  EXPECT_EQ(ranges[0], std::make_pair(std::size_t(0), std::size_t(500)));

  std::vector<int> halves;
  pool.runHalves([&](int half) {
    EXPECT_EQ(std::this_thread::get_id(), caller);
    halves.push_back(half);
  });
  EXPECT_EQ(halves, (std::vector<int>{0, 1}));
}

TEST(ThreadPool, FewItemsAreOneRange) {
  ThreadPool pool(4);
  std::atomic<int> calls{0};
  pool.forRanges(10, 10, [&](std::size_t begin, std::size_t end) {
    ++calls;
    EXPECT_EQ(begin, 0u);
    EXPECT_EQ(end, 10u);
  });
  EXPECT_EQ(calls.load(), 1);
}

TEST(ThreadPool, WorkNestsWithoutDeadlock) {
  ThreadPool pool(4);
  std::atomic<std::size_t> sum{0};
  pool.runHalves([&](int half) {
    pool.forRanges(1000, 8, [&](std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i) sum += i + std::size_t(half) * 1000;
    });
  });
  std::size_t expected = 0;
  for (std::size_t i = 0; i < 2000; ++i) expected += i;
  EXPECT_EQ(sum.load(), expected);
}

TEST(ThreadPool, ExceptionsReachTheCallerAfterTheWorkEnds) {
  for (int threads : {1, 4}) {
    ThreadPool pool(threads);
    std::atomic<int> finished{0};  // the ranges without item 17 may or may not run
    EXPECT_THROW(pool.forRanges(64, 1,
                                [&](std::size_t begin, std::size_t end) {
                                  if (begin <= 17 && 17 < end) throw std::runtime_error("item 17");
                                  ++finished;
                                }),
                 std::runtime_error);
    EXPECT_THROW(pool.runHalves([&](int half) {
      if (half == 1) throw std::out_of_range("half 1");
    }),
                 std::out_of_range);
    EXPECT_THROW(pool.runWithBackground([&](ThreadPool::Background& background) {
      background.start([] { throw std::logic_error("background"); });
    }),
                 std::logic_error);
    // The pool is still usable afterwards.
    std::atomic<std::size_t> count{0};
    pool.forRanges(100, 1, [&](std::size_t begin, std::size_t end) { count += end - begin; });
    EXPECT_EQ(count.load(), 100u);
  }
}

TEST(ThreadPool, WithOneThreadBackgroundTasksRunAfterTheLead) {
  ThreadPool pool(1);
  std::vector<int> order;
  pool.runWithBackground([&](ThreadPool::Background& background) {
    for (int task = 1; task <= 3; ++task) background.start([&order, task] { order.push_back(task); });
    order.push_back(0);
  });
  ASSERT_EQ(order.size(), 4u);
  EXPECT_EQ(order[0], 0);  // the lead finished before any background task began
  std::vector<int> tasks(order.begin() + 1, order.end());
  std::sort(tasks.begin(), tasks.end());
  EXPECT_EQ(tasks, (std::vector<int>{1, 2, 3}));
}

TEST(ThreadPool, BackgroundTasksRunWhileTheLeadWorks) {
  if (std::thread::hardware_concurrency() < 2) GTEST_SKIP() << "needs a second hardware thread";
  ThreadPool pool(2);
  std::atomic<bool> backgroundRan{false};
  bool sawItDuringLead = false;
  pool.runWithBackground([&](ThreadPool::Background& background) {
    background.start([&] { backgroundRan = true; });
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (!backgroundRan && std::chrono::steady_clock::now() < deadline) std::this_thread::yield();
    sawItDuringLead = backgroundRan;
  });
  EXPECT_TRUE(sawItDuringLead);
  EXPECT_TRUE(backgroundRan);
}

}  // namespace
}  // namespace polder::core
