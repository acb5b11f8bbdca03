// Regions of a mesh (ASLOD, D. Schmalstieg and A. Fuhrmann, "Coarse View-Dependent Levels of Detail for Hierarchical
// and Deformable Models", 1999, section 4): the vertices are partitioned into disjoint regions; a triangle belongs to
// the region holding at least two of its vertices (three different regions: the lowest region id). Steps never join
// vertices of different regions, so every region can take its own level of detail.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "polder/mesh/triangle_mesh.hpp"
#include "polder/result.hpp"

namespace polder::mesh {

struct RegionPartition {
  std::uint32_t regionCount = 1;
  std::vector<std::uint32_t> vertexRegion;  // per vertex, < regionCount; empty: all in region 0

  std::uint32_t regionOf(std::uint32_t vertex) const { return vertexRegion.empty() ? 0 : vertexRegion[vertex]; }
};

// The owner of triangle (a, b, c) under the rule above.
inline std::uint32_t triangleRegion(const RegionPartition& partition, std::uint32_t a, std::uint32_t b,
                                    std::uint32_t c) {
  const std::uint32_t ra = partition.regionOf(a), rb = partition.regionOf(b), rc = partition.regionOf(c);
  if (ra == rb || ra == rc) return ra;
  if (rb == rc) return rb;
  return std::min(ra, std::min(rb, rc));
}

// One region: the whole mesh.
RegionPartition singleRegion();

// A grid of cells over the bounding box's two or three longest axes (cells[i] per axis,
// 1 leaves an axis uncut); empty cells are dropped and region ids renumbered densely in
// cell order. E.g. {6, 6, 1} cuts a terrain-like mesh lying in x/y into 6 x 6 regions.
// Axes take at most 2^20 cells; memory follows the vertices, not the cells.
RegionPartition gridPartition(const std::vector<glm::vec3>& positions, std::array<std::uint32_t, 3> cells);

// About `regionCount` compact regions (no more than there are vertices): a grid over the
// bounding box whose cells are near-cubic, refined until it has at least that many non-empty
// cells. Time and memory follow the vertex count, whatever the count asked for.
RegionPartition automaticPartition(const std::vector<glm::vec3>& positions, std::uint32_t regionCount);

// Checks sizes and ids; `what` names the source in the message.
Status validatePartition(const RegionPartition& partition, std::size_t vertexCount, const std::string& what);

}  // namespace polder::mesh
