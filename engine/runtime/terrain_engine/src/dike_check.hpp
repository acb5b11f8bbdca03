// The dike check of a frame (error mode): every drawn dike triangle must keep its exact
// vertical error within tau on screen, like the blocks' triangles.
//
// Why a check. A dike is triangulated from the side vertices the two blocks' meshes kept, and
// each block chose those by its own error only. Where the terrain is rough at the sample
// scale, a side vertex can be worthless to its block (the side stays within tau without it)
// yet essential to the dike: without it the strip's cells are cut along their other diagonal,
// off by half the cell's twist, and a long dike triangle spans rows whose heights bend. No
// a-priori bound from one side alone holds, since the error depends on both sides' choices
// (dike_errors.hpp: an LOD-independent bound is a height range, far too loose to select with).
//
// What it does. For each drawn dike triangle T, e(T) is its exact error (dikeTriangleError,
// remembered across frames in terrain::DikeErrorCache) and d(T) the distance from the camera to T's
// bounding box widened by e(T) vertically, which holds the triangle and the surface under
// it; T passes when K e(T) / max(d(T), near) <= tau, K the view-wide constant of
// Camera::errorProjectionConstant, the bound the blocks keep. Each block with a vertex of a
// failing T gets its side vertices along T's extent pinned in the LOD cache (BoundaryPins):
// its next mesh keeps them, which refines the dike there. The engine then rebuilds those
// meshes, stitches again and checks again, a few rounds at most. Pins stay with the cached
// mesh until the camera recedes, so in steady state the first check passes.
//
// Where both blocks of a level-0 dike keep every side vertex over T's extent, the dike there
// is the surface itself (dikes.hpp: full-detail zippers cut like the surface), so pins always
// cure a level-0 zipper. Coarser dikes are strips several cells wide whose inner samples no
// side holds: where pins cannot cure a triangle, the coarsest node beside it of level 1 or
// more is reported for splitting (splits()), which the engine does at once, selecting again.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <polder/cache/lod_cache.hpp>
#include <polder/camera.hpp>
#include <polder/terrain/block_layout.hpp>
#include <polder/terrain/block_quadtree.hpp>

#include <polder/terrain/dike_error_cache.hpp>
#include <polder/terrain/dike_errors.hpp>
#include <polder/terrain/dike_stage.hpp>

#include "cut_index.hpp"

namespace polder {

// Pins go on where a triangle projects above tau / (1 + this): before it fails (dike_check.cpp).
inline constexpr double kPinHeadroom = 0.1;

struct DikeCheckResult {
  std::size_t failing = 0;  // drawn dike triangles over tau
  double worstPx = 0.0;     // the largest projected error of a drawn dike triangle
};

class DikeCheck {
 public:
  // Errors as `measure` gives them: exact over a heightfield, bounds from a pyramid's tiles.
  // `cutIndex` must index the cut each check() is given.
  DikeCheck(const terrain::DikeTriangleMeasure& measure, const terrain::BlockLayout& layout, const CutIndex& cutIndex,
            double spacingX, double spacingY);
  void reserve(std::size_t cutNodes);

  // Checks the frame's drawn dike triangles and pins the failing ones' sides in `cache`, and
  // those of triangles close to failing (kPinHeadroom). Afterwards repinned() lists the cut
  // indices whose meshes must be rebuilt for this frame.
  DikeCheckResult check(const Camera& camera, double tauPx, const terrain::DikeStage& dikes,
                        std::span<const terrain::SelectedNode> cut,
                        std::span<const terrain::BlockMesh* const> cutMeshes, cache::LodCache& cache);
  std::span<const std::uint32_t> repinned() const { return m_repinned; }
  // Nodes of level 1 or more beside failing triangles that pins could not refine: their dike
  // strips are wider than a cell, with samples inside that no side holds, and only finer
  // nodes cure them (SelectionOptions::forcedSplits).
  std::span<const terrain::NodeId> splits() const { return m_splits; }

 private:
  bool pinAround(std::uint32_t node, int tx0, int ty0, int tx1, int ty1, bool urgent,
                 std::span<const terrain::SelectedNode> cut, std::span<const terrain::BlockMesh* const> cutMeshes,
                 cache::LodCache& cache);

  terrain::BlockLayout m_layout;
  double m_spacingX = 1.0;
  double m_spacingY = 1.0;
  terrain::DikeErrorCache m_errors;
  std::vector<std::uint8_t> m_nodeRepinned;  // per cut index
  std::vector<std::uint32_t> m_repinned;
  std::vector<terrain::NodeId> m_splits;
  const CutIndex& m_cutIndex;
};

}  // namespace polder
