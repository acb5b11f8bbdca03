// The per-instance LOD cache of a progressive mesh (ASLOD's polygonal cache,
// Schmalstieg and Fuhrmann 1999, sections 2 and 6): one index buffer per region that
// moves back and forth in the region's sequence, writing only the corners that change
// between the old and the new level, plus the region's border lookup table. Several
// instances of one ProgressiveMesh sit at independent levels; the mesh is shared, read-only.
//
// Moving to level k gives the same triangles whatever path led there: every step's
// changes are undone exactly in reverse.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "polder/mesh/progressive_mesh.hpp"

namespace polder::mesh {

class ProgressiveMeshInstance {
 public:
  // Starts at full resolution. `mesh` must outlive the instance.
  explicit ProgressiveMeshInstance(const ProgressiveMesh& mesh);

  const ProgressiveMesh& mesh() const { return *m_mesh; }
  std::uint32_t level(std::uint32_t region) const { return m_regions[region].level; }

  // Moves a region to `level` (clamped to its levelCount()); cost proportional to the
  // corners that change. Regions whose border triangles read this region's table are
  // refreshed by the next resolveBorders().
  void setLevel(std::uint32_t region, std::uint32_t level);

  // Points border triangles at their neighbours' current representatives. Call once after
  // the frame's setLevel calls and before reading indices().
  //
  // A neighbour's step can join the far corners of two of this region's border triangles
  // that lie back to back on one of its edges (a strip of this region one edge wide, at a
  // finer level than the neighbour was when it took the step): the two then coincide,
  // facing apart, a fin standing out of the surface. Such a pair is flattened to two
  // degenerate triangles (drawn as nothing), which leaves every other edge as it was.
  void resolveBorders();

  // The region's triangles at its current level (3 indices each into mesh().vertices()).
  std::span<const std::uint32_t> indices(std::uint32_t region) const;
  std::uint32_t triangleCount(std::uint32_t region) const;
  std::uint64_t triangleCount() const;
  // Number of vertices in use by the region's own level (a prefix of its vertex range).
  std::uint32_t activeVertexCount(std::uint32_t region) const;

  // Heap bytes of the instance's own state (index buffers, border tables, scratch).
  std::size_t memoryBytes() const;

  // Index-buffer and table entries written since construction: the cost measure of moves.
  std::uint64_t writes() const { return m_writes; }

 private:
  // A drawn border triangle as resolveBorders sees it: its foreign corner's vertex, its
  // other two corners (lower first) and whether they run lower to higher.
  struct BorderTriangle {
    std::uint32_t foreign, lower, higher, slot;
    bool ascending;
  };
  struct RegionState {
    std::uint32_t level = 0;
    std::vector<std::uint32_t> indices;           // full size; the drawn part is a prefix
    std::vector<std::uint32_t> borderTable;       // current representative of each border vertex
    bool bordersStale = false;                    // a neighbour this region reads has moved
    bool foldsUnchecked = false;                  // moved, or its borders did, since the last fold check
    bool hasFlattenedPair = false;                // resolveBorders flattened a folded pair
    std::vector<BorderTriangle> borderTriangles;  // resolveBorders' room, one per foreign corner
  };

  void flattenFoldedPairs(std::uint32_t region);
  bool backToBackInTheInput(std::uint32_t region, std::uint32_t slotX, std::uint32_t slotY) const;

  const ProgressiveMesh* m_mesh;
  std::vector<RegionState> m_regions;
  std::uint64_t m_writes = 0;
};

}  // namespace polder::mesh
