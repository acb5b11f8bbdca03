#include <polder/cache/cache_stats.hpp>
#include <polder/cache/lru_cache.hpp>

#include <string>

#include <gtest/gtest.h>

namespace polder::cache {
namespace {

TEST(LruCache, EvictsLeastRecentlyUsedToStayWithinBudget) {
  LruCache<int, std::string> cache(100);
  cache.insert(1, "a", 40);
  cache.insert(2, "b", 40);
  ASSERT_NE(cache.find(1), nullptr);  // 1 is now more recent than 2
  cache.insert(3, "c", 40);           // 120 > 100: evicts 2
  EXPECT_EQ(cache.find(2), nullptr);
  ASSERT_NE(cache.find(1), nullptr);
  ASSERT_NE(cache.find(3), nullptr);
  EXPECT_EQ(cache.bytes(), 80u);
  EXPECT_EQ(cache.counters().evictions, 1u);
}

TEST(LruCache, ReplacingAKeyUpdatesItsBytes) {
  LruCache<int, int> cache(100);
  cache.insert(7, 1, 30);
  cache.insert(7, 2, 50);
  EXPECT_EQ(cache.size(), 1u);
  EXPECT_EQ(cache.bytes(), 50u);
  EXPECT_EQ(*cache.find(7), 2);
}

TEST(LruCache, KeepsAnOversizedEntryAlone) {
  LruCache<int, int> cache(10);
  cache.insert(1, 1, 5);
  cache.insert(2, 2, 50);
  EXPECT_EQ(cache.size(), 1u);
  EXPECT_NE(cache.find(2), nullptr);
}

TEST(LruCache, ShrinkingTheBudgetEvicts) {
  LruCache<int, int> cache(100);
  for (int i = 0; i < 10; ++i) cache.insert(i, i, 10);
  cache.setBudget(35);
  EXPECT_EQ(cache.size(), 3u);
  EXPECT_LE(cache.bytes(), 35u);
  EXPECT_NE(cache.find(9), nullptr);
  EXPECT_EQ(cache.find(0), nullptr);
}

TEST(LruCache, CountsHitsAndMisses) {
  LruCache<int, int> cache(100);
  cache.insert(1, 1, 1);
  (void)cache.find(1);
  (void)cache.find(1);
  (void)cache.find(2);
  EXPECT_EQ(cache.counters().hits, 2u);
  EXPECT_EQ(cache.counters().misses, 1u);
  EXPECT_DOUBLE_EQ(hitRate(cache.counters()), 2.0 / 3.0);
}

}  // namespace
}  // namespace polder::cache
