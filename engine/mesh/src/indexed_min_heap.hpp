// A binary min-heap of item ids keyed by float, with the position of every id kept so a
// key can change in place: each item sits in the heap at most once, so there are no stale
// entries to skip (the builders re-cost the same vertex many times).
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

namespace polder::mesh {

class IndexedMinHeap {
 public:
  explicit IndexedMinHeap(std::uint32_t itemCount) : m_position(itemCount, kAbsent) { m_heap.reserve(itemCount); }

  bool empty() const { return m_heap.empty(); }
  bool contains(std::uint32_t item) const { return m_position[item] != kAbsent; }
  std::uint32_t top() const { return m_heap.front().item; }
  float key(std::uint32_t item) const { return m_heap[m_position[item]].key; }  // item in the heap

  // Inserts the item or moves it to its new key.
  void set(std::uint32_t item, float key) {
    std::uint32_t at = m_position[item];
    if (at == kAbsent) {
      at = static_cast<std::uint32_t>(m_heap.size());
      m_heap.push_back({key, item});
      siftUp(at);
      return;
    }
    const float old = m_heap[at].key;
    m_heap[at].key = key;
    if (key < old)
      siftUp(at);
    else
      siftDown(at);
  }

  void clear() {
    for (const Entry& entry : m_heap) m_position[entry.item] = kAbsent;
    m_heap.clear();
  }

  void remove(std::uint32_t item) {
    const std::uint32_t at = m_position[item];
    if (at == kAbsent) return;
    m_position[item] = kAbsent;
    const Entry last = m_heap.back();
    m_heap.pop_back();
    if (last.item == item) return;
    m_heap[at] = last;
    m_position[last.item] = at;
    siftUp(at);
    siftDown(m_position[last.item]);
  }

 private:
  static constexpr std::uint32_t kAbsent = std::numeric_limits<std::uint32_t>::max();

  // Keys sit beside their items so a sift compares without looking elsewhere.
  struct Entry {
    float key;
    std::uint32_t item;
  };

  void place(std::uint32_t at, const Entry& entry) {
    m_heap[at] = entry;
    m_position[entry.item] = at;
  }
  void siftUp(std::uint32_t at) {
    const Entry entry = m_heap[at];
    while (at > 0) {
      const std::uint32_t parent = (at - 1) / 2;
      if (!(entry.key < m_heap[parent].key)) break;
      place(at, m_heap[parent]);
      at = parent;
    }
    place(at, entry);
  }
  void siftDown(std::uint32_t at) {
    const Entry entry = m_heap[at];
    const auto size = static_cast<std::uint32_t>(m_heap.size());
    for (;;) {
      std::uint32_t child = 2 * at + 1;
      if (child >= size) break;
      if (child + 1 < size)
        child += std::uint32_t(m_heap[child + 1].key < m_heap[child].key);  // no branch: a coin toss
      if (!(m_heap[child].key < entry.key)) break;
      place(at, m_heap[child]);
      at = child;
    }
    place(at, entry);
  }

  std::vector<std::uint32_t> m_position;  // per item: its place in m_heap, or kAbsent
  std::vector<Entry> m_heap;
};

}  // namespace polder::mesh
