// Errors of the dikes (dikes.hpp): the exact vertical error of every dike triangle against the
// full-resolution surface, and an a-priori bound per quadtree node on the dike triangles it
// owns. The dikes follow J.-H. Chuang (莊榮宏), "Level-of-Detail Modeling Technique for Virtual
// Reality (I)", NSC 89-2218-E-009-012 final report, National Chiao Tung University, 2001,
// part B (dikes.hpp).
//
// Errors (docs/design.md "Errors are honest"). dikeTriangleErrors() gives every dike triangle's
// exact vertical error against the full-resolution surface; the terrain engine's dike check
// (engine/runtime/terrain_engine/src/dike_check.hpp) holds every drawn one within tau on screen by
// pinning the blocks' side vertices where needed. dikeErrorBound() is an a-priori
// bound per quadtree node, independent of every block's LOD and of the neighbours' levels.
// Each dike triangle has an owner (DikeMesh::owners): for a zipper triangle the coarser of
// its two nodes, for a junction triangle the coarsest node around its junction polygon. It
// lies in its owner's bound region (dikeBoundRegion), so its error is at most the height
// range there: its plane interpolates three samples of the region, and the surface at any
// point of the region interpolates samples of the region. The bound must allow the worst a node's dikes may
// draw: a sliver between a fine side and a coarse side with only its corners kept deviates
// from the surface by about slope x side length, so an LOD-independent bound is about a
// range, not a curvature. See dike_errors.cpp ("Why the bound holds") for what is proved and
// what is argued and tested.
#pragma once

#include <cstddef>
#include <vector>

#include <polder/result.hpp>
#include <polder/terrain/block_layout.hpp>
#include <polder/terrain/dikes.hpp>
#include <polder/terrain/heightfield.hpp>

namespace polder::terrain {

// Exact vertical error of every dike triangle against the full-resolution surface, as
// rtin.hpp defines it for block triangles: the largest |surface - plane| over the closed
// triangle, the plane through its three vertices' heights, the surface heightfield.hpp's
// triangulation of the samples. Both are linear between the vertices of their overlay, so
// the scan covers every sample in the triangle (this alone is the samples-only error) and
// every point where a triangle edge crosses a cell edge or a cell's cut diagonal. Writes one
// value per triangle into `perTriangle` when it is given (resized) and returns the largest.
// Cost: proportional to the samples under the dikes plus their edges' lengths.
float dikeTriangleErrors(const Heightfield& field, const DikeMesh& dikes, std::vector<float>* perTriangle = nullptr);
// The same for one triangle of full-resolution samples (either winding). Cost: the samples
// under it plus its edges' lengths.
float dikeTriangleError(const Heightfield& field, const DikeVertex& a, const DikeVertex& b, const DikeVertex& c);
// The samples-only part of it: the largest |sample - plane| over the samples in the closed
// triangle, what greedy and RTIN terrain simplifiers measure (a lower bound of the exact error).
float triangleSampleError(const Heightfield& field, const DikeVertex& a, const DikeVertex& b, const DikeVertex& c);

// The samples whose height range bounds every dike triangle a node owns (DikeMesh::owners),
// whatever the LODs and levels of the frame: the footprints of the node and of its west,
// south and south-west neighbours at its level, i.e. its footprint widened by one footprint
// (p * stride samples, p = 2^k + 1) westward and southward, clipped to the DEM. Owned
// triangles never reach east or north of the node's footprint: its dike lies there, east and
// north of its interior, while the gap along its west and south sides lies in its neighbours'
// dikes.
SampleRect dikeBoundRegion(const BlockLayout& layout, NodeId node);

// A-priori bound (metres) on the exact vertical error of every dike triangle `node` owns:
// max - min height over dikeBoundRegion(). Independent of every block's LOD and of the
// neighbours' levels, so the selection can use it per node before a frame is built
// (BlockQuadtreeOptions::dikeErrorBound). The triangles it covers may lie up to one footprint
// west or south of the node's own box: a screen-space test on this term should measure the
// distance to the region, not to the node's footprint. It also covers the samples a clipped interior
// leaves uncovered at the DEM's east and north edges: they lie in the node's dike and in
// its region. Scans the region: O(4 * footprint samples); DikeErrorBounds gives every node's
// bound at once.
float dikeErrorBound(const Heightfield& field, const BlockLayout& layout, NodeId node);

// dikeErrorBound of every node of a layout, from per-block height ranges: one pass over the
// field, then O(1) per node.
class DikeErrorBounds {
 public:
  static Result<DikeErrorBounds> build(const Heightfield& field, const BlockLayout& layout);
  float bound(NodeId node) const;  // asserts that the node exists

 private:
  BlockLayout m_layout;
  std::vector<std::size_t> m_levelOffset;
  std::vector<float> m_min, m_max;  // per node of every level, over its clipped footprint
};

}  // namespace polder::terrain
