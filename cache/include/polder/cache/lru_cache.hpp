// A cache of values by key under a byte budget, evicting the least recently used entry.
// The LOD cache (per-block meshes), tile residency and GPU buffer reuse build on it.
//
// Thread contract: not thread-safe; one owner (the frame thread) uses it.
#pragma once

#include <cassert>
#include <cstddef>
#include <cstdint>
#include <list>
#include <unordered_map>
#include <utility>

namespace polder::cache {

struct CacheCounters {
  std::uint64_t hits = 0;
  std::uint64_t misses = 0;
  std::uint64_t evictions = 0;
};

template <class Key, class Value, class Hash = std::hash<Key>>
class LruCache {
 public:
  explicit LruCache(std::size_t budgetBytes) : m_budgetBytes(budgetBytes) {}

  // The value for `key`, marked most recently used, or nullptr.
  Value* find(const Key& key) {
    const auto it = m_index.find(key);
    if (it == m_index.end()) {
      ++m_counters.misses;
      return nullptr;
    }
    ++m_counters.hits;
    m_entries.splice(m_entries.begin(), m_entries, it->second);
    return &it->second->value;
  }

  // The value for `key`, or nullptr, without counting a use or changing the order.
  const Value* peek(const Key& key) const {
    const auto it = m_index.find(key);
    return it == m_index.end() ? nullptr : &it->second->value;
  }

  // Inserts or replaces `key`, then evicts least recently used entries (never the new one)
  // until the total is within budget. An entry larger than the whole budget is kept
  // alone rather than refused: the caller asked for it this frame.
  Value& insert(const Key& key, Value value, std::size_t bytes) {
    erase(key);
    m_entries.push_front(Entry{key, std::move(value), bytes});
    m_index.emplace(key, m_entries.begin());
    m_bytes += bytes;
    evictToBudget();
    return m_entries.front().value;
  }

  // Whether `bytes` more fit in the budget once entries for which `evictable(value)` holds
  // are evicted, least recently used first, stopping at the first that is not: what insert()
  // would evict, asked before a value is made to give way to another.
  template <class Evictable>
  bool fitsEvicting(std::size_t bytes, Evictable evictable) const {
    std::size_t held = m_bytes + bytes;
    for (auto it = m_entries.rbegin(); held > m_budgetBytes && it != m_entries.rend(); ++it) {
      if (!evictable(it->value)) return false;
      held -= it->bytes;
    }
    return held <= m_budgetBytes;
  }

  bool erase(const Key& key) {
    const auto it = m_index.find(key);
    if (it == m_index.end()) return false;
    m_bytes -= it->second->bytes;
    m_entries.erase(it->second);
    m_index.erase(it);
    return true;
  }

  void setBudget(std::size_t budgetBytes) {
    m_budgetBytes = budgetBytes;
    evictToBudget();
  }

  std::size_t bytes() const { return m_bytes; }
  std::size_t budgetBytes() const { return m_budgetBytes; }
  std::size_t size() const { return m_index.size(); }
  const CacheCounters& counters() const { return m_counters; }

 private:
  struct Entry {
    Key key;
    Value value;
    std::size_t bytes;
  };

  void evictToBudget() {
    while (m_bytes > m_budgetBytes && m_entries.size() > 1) {
      Entry& victim = m_entries.back();
      m_bytes -= victim.bytes;
      m_index.erase(victim.key);
      m_entries.pop_back();
      ++m_counters.evictions;
    }
  }

  std::size_t m_budgetBytes;
  std::size_t m_bytes = 0;
  std::list<Entry> m_entries;  // most recently used first
  std::unordered_map<Key, typename std::list<Entry>::iterator, Hash> m_index;
  CacheCounters m_counters;
};

}  // namespace polder::cache
