// How a DEM is cut into blocks and quadtree nodes (docs/design.md "Grid and dikes"; Chuang 2001,
// part B: blocks with a dike between each pair of neighbours).
//
// Level-0 blocks have 2^k cells (2^k + 1 samples) per side and do not share samples: they
// sit at a pitch of 2^k + 1 samples, so a dike strip one cell wide lies between neighbours.
// A node of quadtree level L stands for 2^L x 2^L level-0 blocks and samples its area with
// stride s = 2^L. For node (L, bx, by), in full-resolution sample coordinates:
//
//   footprint  [x0, x0 + pitch*s] x [y0, y0 + pitch*s], x0 = bx * pitch * s, y0 = by * pitch * s,
//              clipped to the DEM [0, width-1] x [0, height-1];
//   interior   [x0, x0 + 2^k*s] x [y0, y0 + 2^k*s]: what the node's BlockLod draws (clipped
//              to the largest strided rectangle inside the DEM, see rtin.hpp);
//   dike       the rest of the footprint: a strip s cells wide along the interior's east and
//              north sides (plus whatever a clipped interior leaves before the DEM's edge).
//
// The footprints of any quadtree cut (a set of nodes none of which contains another, that
// together cover the root) tile the DEM. The interiors are the blocks' meshes; everything
// between them — the gap network — is covered by the dikes.
//
// The footprint of a level-L node is the union of its four children's footprints, since
// pitch * 2^L = 2 * pitch * 2^(L-1); its interior's corner (x0, y0) is its south-west child's.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include <polder/result.hpp>
#include <polder/terrain/block_mesh.hpp>

namespace polder::terrain {

struct NodeId {
  std::uint8_t level = 0;
  std::uint32_t bx = 0;  // column of the node among the nodes of its level, west to east
  std::uint32_t by = 0;  // row, south to north

  friend bool operator==(const NodeId&, const NodeId&) = default;
  NodeId child(int quadrant) const {  // 0 SW, 1 SE, 2 NW, 3 NE
    return NodeId{std::uint8_t(level - 1), 2 * bx + std::uint32_t(quadrant & 1), 2 * by + std::uint32_t(quadrant >> 1)};
  }
  NodeId parent() const { return NodeId{std::uint8_t(level + 1), bx / 2, by / 2}; }
};

// A node as one number, unique within any layout (columns and rows below 2^28): for hash keys.
inline std::uint64_t nodeKey(const NodeId& node) {
  return (std::uint64_t(node.level) << 56) | (std::uint64_t(node.bx) << 28) | std::uint64_t(node.by);
}

// A rectangle of full-resolution sample coordinates, both ends inclusive.
struct SampleRect {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  bool empty() const { return x1 < x0 || y1 < y0; }
  friend bool operator==(const SampleRect&, const SampleRect&) = default;
};

class BlockLayout {
 public:
  // A DEM of width x height samples (each >= 2) in blocks of 2^k cells, k in 1..7.
  static Result<BlockLayout> create(int width, int height, int k = 5) {
    if (width < 2 || height < 2)
      return makeError(ErrorKind::InvalidArgument, "a block layout needs at least 2 x 2 samples");
    if (k < 1 || k > 7)
      return makeError(ErrorKind::InvalidArgument, "block size must be 2^k + 1 samples with k in 1..7");
    BlockLayout layout;
    layout.m_width = width;
    layout.m_height = height;
    layout.m_k = k;
    // A level-0 block exists where its interior has at least one cell inside the DEM.
    const int pitch = layout.pitch();
    layout.m_blocksX = (width - 2) / pitch + 1;
    layout.m_blocksY = (height - 2) / pitch + 1;
    while ((1 << layout.m_rootLevel) < std::max(layout.m_blocksX, layout.m_blocksY)) ++layout.m_rootLevel;
    return layout;
  }

  int width() const { return m_width; }
  int height() const { return m_height; }
  int k() const { return m_k; }
  int cells() const { return 1 << m_k; }        // per side of a block's interior
  int pitch() const { return (1 << m_k) + 1; }  // samples from one level-0 block to the next
  int rootLevel() const { return m_rootLevel; }
  NodeId root() const { return NodeId{std::uint8_t(m_rootLevel), 0, 0}; }

  // Nodes of a level per side (those whose footprint holds at least one level-0 block).
  int nodesX(int level) const { return (m_blocksX + (1 << level) - 1) >> level; }
  int nodesY(int level) const { return (m_blocksY + (1 << level) - 1) >> level; }
  bool exists(const NodeId& node) const {
    return node.level <= m_rootLevel && int(node.bx) < nodesX(node.level) && int(node.by) < nodesY(node.level);
  }

  int stride(const NodeId& node) const { return 1 << node.level; }

  // How many nodes a frame's storage is first sized for: the level-0 blocks, at most
  // kReservedCutNodes. A cut follows the view and is far smaller than the blocks of a large
  // DEM; a larger one grows the storage once, and the frames after it reuse it.
  static constexpr std::size_t kReservedCutNodes = std::size_t(1) << 15;
  std::size_t reservedCutNodes() const {
    return std::min(std::size_t(m_blocksX) * std::size_t(m_blocksY), kReservedCutNodes);
  }

  SampleRect footprint(const NodeId& node) const {
    const int span = pitch() * stride(node);
    const int x0 = int(node.bx) * span, y0 = int(node.by) * span;
    return SampleRect{x0, y0, std::min(x0 + span, m_width - 1), std::min(y0 + span, m_height - 1)};
  }

  // What the node's BlockLod reads and draws (before clipping to the DEM; rtin.hpp clips).
  BlockFootprint interior(const NodeId& node) const {
    const SampleRect area = footprint(node);
    return BlockFootprint{area.x0, area.y0, m_k, stride(node)};
  }

 private:
  int m_width = 0;
  int m_height = 0;
  int m_k = 5;
  int m_blocksX = 0;
  int m_blocksY = 0;
  int m_rootLevel = 0;
};

}  // namespace polder::terrain
