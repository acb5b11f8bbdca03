// One terrain block's triangle mesh at some level of detail: the output of the per-block
// LOD (rtin.hpp) and the input of the dikes and the LOD cache. Plain data in block-local
// grid coordinates, so a cached mesh stays valid wherever the camera goes.
#pragma once

#include <algorithm>
#include <array>
#include <bitset>
#include <cassert>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace polder::terrain {

// The full-resolution samples a block reads. Block-local vertex (i, j), 0 <= i, j <= 2^k, is
// full-resolution sample (x0 + i * stride, y0 + j * stride). A block of quadtree level L has
// stride 2^L and spans 2^k * stride + 1 full-resolution samples per side.
struct BlockFootprint {
  int x0 = 0;  // full-resolution sample of block-local vertex (0, 0), its south-west corner
  int y0 = 0;
  int k = 5;       // 2^k cells, 2^k + 1 vertices per side (k = 5: the 33 x 33 blocks of docs/design.md)
  int stride = 1;  // full-resolution samples from one vertex to the next, a power of two

  int cells() const { return 1 << k; }
  int verticesPerSide() const { return (1 << k) + 1; }
};

// A block-local vertex: sample indices, i east and j north, 0..2^k.
struct GridVertex {
  std::uint16_t i = 0;
  std::uint16_t j = 0;
};

// The four sides of a block, in the order of BlockMesh::edges.
enum class BlockEdge : int { South = 0, East = 1, North = 2, West = 3 };

// Upper bounds on what one extraction writes for a block of 2^k cells per side, for
// BlockMesh::reserve (meshoptimizer's ...Bound() idiom).
inline std::size_t blockMeshVertexBound(int k) {
  const std::size_t side = (std::size_t(1) << k) + 1;
  return side * side;
}
inline std::size_t blockMeshTriangleBound(int k) { return std::size_t(2) << (2 * k); }
inline std::size_t blockMeshEdgeBound(int k) { return (std::size_t(1) << k) + 1; }

struct BlockMesh {
  BlockFootprint footprint;
  // The mesh covers block-local [0, cellsX] x [0, cellsY]: all 2^k cells per side, or fewer
  // where the block runs past the DEM's east or north edge (rtin.hpp, "Clipped blocks").
  int cellsX = 0;
  int cellsY = 0;

  std::vector<GridVertex> vertices;    // each used vertex once
  std::vector<std::uint32_t> indices;  // three per triangle, counter-clockwise seen from above (+z)
  // Per side (index with BlockEdge), indices into `vertices` of the vertices on that side,
  // sorted west to east (South, North) or south to north (West, East); both corners of a
  // side are always present. The dikes stitch these to the neighbouring blocks.
  std::array<std::vector<std::uint32_t>, 4> edges;
  // Largest exact vertical error (metres) of any triangle against the full-resolution
  // samples it covers.
  float maxError = 0.0f;
  // Which build this is: the LOD cache numbers every mesh it builds, so a host can tell a
  // rebuilt mesh from the one it already holds (0: not built by a cache). clear() keeps it.
  std::uint64_t revision = 0;

  std::size_t triangleCount() const { return indices.size() / 3; }
  const std::vector<std::uint32_t>& edge(BlockEdge side) const { return edges[std::size_t(side)]; }

  // Room for any mesh of a block with 2^k cells per side: extractions into a reserved mesh
  // do not allocate.
  void reserve(int k) {
    assert(k >= 1 && k <= 8 && "BlockMesh::reserve: k must be in 1..8");
    vertices.reserve(blockMeshVertexBound(k));
    indices.reserve(3 * blockMeshTriangleBound(k));
    for (auto& side : edges) side.reserve(blockMeshEdgeBound(k));
  }

  // Empties the mesh and keeps its capacity.
  void clear() {
    vertices.clear();
    indices.clear();
    for (auto& side : edges) side.clear();
    maxError = 0.0f;
  }
};

// Side vertices a mesh must keep whatever its level of detail (BlockLod::extractView): the
// frame pins them where the dike beside the block would otherwise exceed the tolerance
// (the engine's dike check). Per side (BlockEdge), by position along the side: i on South
// and North, j on West and East, 0..2^k.
struct BoundaryPins {
  static constexpr int kMaxPositions = 257;  // 2^8 + 1: blocks up to kRtinMaxK

  std::array<std::bitset<kMaxPositions>, 4> sides;

  bool any() const { return sides[0].any() || sides[1].any() || sides[2].any() || sides[3].any(); }
  bool pinned(BlockEdge side, int position) const { return sides[std::size_t(side)][std::size_t(position)]; }
  // Pins positions from..to (inclusive, clamped to the side); true when one was not pinned yet.
  bool pin(BlockEdge side, int from, int to) {
    from = std::max(from, 0);
    to = std::min(to, kMaxPositions - 1);
    bool added = false;
    for (int p = from; p <= to; ++p) {
      added |= !sides[std::size_t(side)][std::size_t(p)];
      sides[std::size_t(side)][std::size_t(p)] = true;
    }
    return added;
  }
  void clear() {
    for (auto& side : sides) side.reset();
  }
  friend bool operator==(const BoundaryPins&, const BoundaryPins&) = default;
};

}  // namespace polder::terrain
