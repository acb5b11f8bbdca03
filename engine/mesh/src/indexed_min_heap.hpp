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
  explicit IndexedMinHeap(std::uint32_t itemCount) : m_key(itemCount, 0.0f), m_position(itemCount, kAbsent) {
    m_heap.reserve(itemCount);
  }

  bool empty() const { return m_heap.empty(); }
  bool contains(std::uint32_t item) const { return m_position[item] != kAbsent; }
  std::uint32_t top() const { return m_heap.front(); }
  float key(std::uint32_t item) const { return m_key[item]; }

  // Inserts the item or moves it to its new key.
  void set(std::uint32_t item, float key) {
    m_key[item] = key;
    if (m_position[item] == kAbsent) {
      m_position[item] = static_cast<std::uint32_t>(m_heap.size());
      m_heap.push_back(item);
      siftUp(m_position[item]);
    } else {
      siftUp(m_position[item]);
      siftDown(m_position[item]);
    }
  }

  void remove(std::uint32_t item) {
    const std::uint32_t at = m_position[item];
    if (at == kAbsent) return;
    m_position[item] = kAbsent;
    const std::uint32_t last = m_heap.back();
    m_heap.pop_back();
    if (last == item) return;
    m_heap[at] = last;
    m_position[last] = at;
    siftUp(at);
    siftDown(m_position[last]);
  }

 private:
  static constexpr std::uint32_t kAbsent = std::numeric_limits<std::uint32_t>::max();

  void place(std::uint32_t at, std::uint32_t item) {
    m_heap[at] = item;
    m_position[item] = at;
  }
  void siftUp(std::uint32_t at) {
    const std::uint32_t item = m_heap[at];
    const float key = m_key[item];
    while (at > 0) {
      const std::uint32_t parent = (at - 1) / 2;
      if (!(key < m_key[m_heap[parent]])) break;
      place(at, m_heap[parent]);
      at = parent;
    }
    place(at, item);
  }
  void siftDown(std::uint32_t at) {
    const std::uint32_t item = m_heap[at];
    const float key = m_key[item];
    const auto size = static_cast<std::uint32_t>(m_heap.size());
    for (;;) {
      std::uint32_t child = 2 * at + 1;
      if (child >= size) break;
      if (child + 1 < size && m_key[m_heap[child + 1]] < m_key[m_heap[child]]) ++child;
      if (!(m_key[m_heap[child]] < key)) break;
      place(at, m_heap[child]);
      at = child;
    }
    place(at, item);
  }

  std::vector<float> m_key;
  std::vector<std::uint32_t> m_position;
  std::vector<std::uint32_t> m_heap;
};

}  // namespace polder::mesh
