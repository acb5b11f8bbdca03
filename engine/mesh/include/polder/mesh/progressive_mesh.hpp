// A progressive mesh with regions: the multiresolution sequence of ASLOD
// (D. Schmalstieg and A. Fuhrmann, "Coarse View-Dependent Levels of Detail for Hierarchical and Deformable Models",
// 1999, sections 2 and 4), assembled from a builder's steps.
//
// Every region owns its own sequence: its triangles (those holding two of its vertices)
// ordered so the triangles alive after m of its steps are a prefix, and per step the
// triangle corners that change vertex (the step's representative replaces the removed
// vertices). A region's border vertices, the ones other regions' triangles use, sit in a
// lookup table that follows the region's own steps; a triangle of region A that uses a
// vertex of region B reads that table, so B's collapses reach A's border triangles and
// regions at independent levels meet without cracks. Steps never join vertices of two
// regions, which is what makes that sound.
//
// Levels count refinements from the base mesh: level 0 is the coarsest mesh the builder
// reached, level levelCount() the original. The vertex table is the original's, reordered
// so that each region's vertices are contiguous and the vertices alive at any level are a
// prefix of the region's range (the ones removed last come first).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "polder/mesh/region_partition.hpp"
#include "polder/mesh/simplification_steps.hpp"
#include "polder/mesh/triangle_mesh.hpp"
#include "polder/result.hpp"

namespace polder::mesh {

// One index-buffer slot changing vertex in a step: `before` at the finer level, `after` at
// the coarser one.
struct CornerChange {
  std::uint32_t slot = 0;
  std::uint32_t before = 0;
  std::uint32_t after = 0;
};

// A corner of this region's triangle that holds another region's vertex: it reads entry
// `entry` of region `region`'s border table.
struct ForeignCorner {
  std::uint32_t slot = 0;
  std::uint32_t region = 0;
  std::uint32_t entry = 0;
};

class RegionSequence {
 public:
  std::uint32_t levelCount() const { return static_cast<std::uint32_t>(m_stepCount); }
  // Triangles, active vertices and error at a level (0 ... levelCount()).
  std::uint32_t trianglesAt(std::uint32_t level) const { return m_trianglesAfterSteps[m_stepCount - level]; }
  std::uint32_t verticesAt(std::uint32_t level) const { return m_verticesAfterSteps[m_stepCount - level]; }
  // Object-space error of the level: the largest builder estimate of the steps it lacks
  // (so it never grows with the level).
  float errorAt(std::uint32_t level) const { return m_errorAfterSteps[m_stepCount - level]; }
  // The finest level with at most `triangles` triangles (0 when even the base has more).
  std::uint32_t levelForTriangles(std::uint32_t triangles) const;
  // The coarsest level whose error is at most `error`.
  std::uint32_t levelForError(float error) const;

  std::uint32_t vertexBegin() const { return m_vertexBegin; }
  std::uint32_t vertexEnd() const { return m_vertexEnd; }
  // The region's triangles at full resolution, in survival order (3 indices each; foreign
  // corners hold the original foreign vertex).
  std::span<const std::uint32_t> fullIndices() const { return m_fullIndices; }
  std::span<const ForeignCorner> foreignCorners() const { return m_foreignCorners; }
  // Vertices other regions' triangles use.
  std::span<const std::uint32_t> borderVertices() const { return m_borderVertices; }
  // The regions whose border triangles read this region's table, ascending.
  std::span<const std::uint32_t> readers() const { return m_readers; }
  // The corner and border-table changes of step `step` (0 is the first step taken from the
  // original, i.e. the change between levels levelCount() and levelCount() - 1).
  std::span<const CornerChange> cornerChanges(std::size_t step) const {
    return {m_cornerChanges.data() + m_cornerChangeBegin[step],
            m_cornerChangeBegin[step + 1] - m_cornerChangeBegin[step]};
  }
  std::span<const CornerChange> borderChanges(std::size_t step) const {
    return {m_borderChanges.data() + m_borderChangeBegin[step],
            m_borderChangeBegin[step + 1] - m_borderChangeBegin[step]};
  }
  std::size_t memoryBytes() const;

 private:
  friend class ProgressiveMeshAssembler;
  std::size_t m_stepCount = 0;
  std::uint32_t m_vertexBegin = 0, m_vertexEnd = 0;
  std::vector<std::uint32_t> m_trianglesAfterSteps;  // per m = 0 ... stepCount
  std::vector<std::uint32_t> m_verticesAfterSteps;
  std::vector<float> m_errorAfterSteps;
  std::vector<std::uint32_t> m_fullIndices;
  std::vector<ForeignCorner> m_foreignCorners;
  std::vector<std::uint32_t> m_borderVertices;
  std::vector<std::uint32_t> m_readers;
  std::vector<std::uint32_t> m_cornerChangeBegin{0};
  std::vector<CornerChange> m_cornerChanges;
  std::vector<std::uint32_t> m_borderChangeBegin{0};
  std::vector<CornerChange> m_borderChanges;
};

class ProgressiveMesh {
 public:
  // Assembles the sequence from a builder's steps over `mesh` (validated: indices in
  // range, steps that only join active vertices of one region onto an active
  // representative of that region). Degenerate input triangles are dropped.
  static Result<ProgressiveMesh> assemble(const TriangleMesh& mesh, const RegionPartition& partition,
                                          const SimplificationSteps& steps);

  // The reordered vertex table (with attributes) and the full-resolution triangles in
  // region order; vertices()[i] is the original's vertex originalVertex()[i].
  const TriangleMesh& vertices() const { return m_vertices; }
  std::span<const std::uint32_t> originalVertex() const { return m_originalVertex; }
  std::span<const std::uint32_t> regionOfVertex() const { return m_vertexRegion; }

  std::uint32_t regionCount() const { return static_cast<std::uint32_t>(m_regions.size()); }
  const RegionSequence& region(std::uint32_t r) const { return m_regions[r]; }
  std::size_t stepCount() const { return m_stepCount; }
  std::size_t memoryBytes() const;

 private:
  friend class ProgressiveMeshAssembler;
  TriangleMesh m_vertices;
  std::vector<std::uint32_t> m_originalVertex;
  std::vector<std::uint32_t> m_vertexRegion;
  std::vector<RegionSequence> m_regions;
  std::size_t m_stepCount = 0;
};

}  // namespace polder::mesh
