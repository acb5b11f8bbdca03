// Which node of a frame's cut holds a sample: the cut's nodes hashed by node, indexed when the
// first question of a frame comes (most frames ask none), and each question answered by
// looking up the one node of every level whose footprint holds the sample, finest first.
#pragma once

#include <algorithm>
#include <bit>
#include <cstdint>
#include <span>
#include <vector>

#include <polder/mix_bits.hpp>
#include <polder/terrain/block_quadtree.hpp>

namespace polder {

class CutIndex {
 public:
  static constexpr std::uint32_t kNone = 0xffffffffu;

  explicit CutIndex(const terrain::BlockLayout& layout) : m_layout(layout) {}

  // The cut the next questions are about; it must outlive them.
  void setCut(std::span<const terrain::SelectedNode> cut) {
    m_cut = cut;
    m_indexed = false;
  }

  // The index in the cut of the node whose footprint holds cell (x, y) (the cell whose
  // south-west corner is sample (x, y): footprints half-open), or kNone.
  std::uint32_t at(int x, int y) const {
    if (!m_indexed) index();
    const std::size_t mask = m_slots.size() - 1;
    for (int level = 0; level <= m_layout.rootLevel(); ++level) {
      const int span = m_layout.pitch() << level;
      const terrain::NodeId node{std::uint8_t(level), std::uint32_t(x / span), std::uint32_t(y / span)};
      if (!m_layout.exists(node)) continue;
      const std::uint64_t key = terrain::nodeKey(node);
      for (std::size_t slot = std::size_t(mixBits(key)) & mask; m_slots[slot].index != kNone; slot = (slot + 1) & mask)
        if (m_slots[slot].key == key) return m_slots[slot].index;
    }
    return kNone;
  }

 private:
  struct Slot {
    std::uint64_t key = 0;
    std::uint32_t index = kNone;
  };

  void index() const {
    const std::size_t size = std::bit_ceil(std::max<std::size_t>(4 * m_cut.size(), 64));
    if (m_slots.size() < size) m_slots.resize(size);
    std::fill(m_slots.begin(), m_slots.end(), Slot{});
    const std::size_t mask = m_slots.size() - 1;
    for (std::size_t i = 0; i < m_cut.size(); ++i) {
      const std::uint64_t key = terrain::nodeKey(m_cut[i].node);
      std::size_t slot = std::size_t(mixBits(key)) & mask;
      while (m_slots[slot].index != kNone) slot = (slot + 1) & mask;
      m_slots[slot] = Slot{key, std::uint32_t(i)};
    }
    m_indexed = true;
  }

  terrain::BlockLayout m_layout;
  std::span<const terrain::SelectedNode> m_cut;
  mutable std::vector<Slot> m_slots;
  mutable bool m_indexed = false;
};

}  // namespace polder
