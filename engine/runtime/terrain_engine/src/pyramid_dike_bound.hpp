// Bounds on dike triangles' errors from a pyramid's resident tiles, for the dike check when the
// engine streams (dike_check.hpp; docs/streaming.md "Dikes from tiles").
//
// The full resolution is not in memory, but every node of the cut has its tile: the level
// surface of its footprint at its stride, and per cell a residual, a bound on how far the full
// resolution lies from that surface over the cell. Over one level triangle the difference
// between a dike triangle's plane and the level surface is linear, so over the part of the
// dike triangle inside it, it is largest at a corner of that part (the dike triangle clipped
// to the level triangle). Hence, over the part of T in node N's footprint,
//
//   error <= min(max over N's cells c of (max over the corners in c of |plane - level surface|
//                                         + residual(c)),
//                the largest distance between T's vertex heights and N's height range),
//
// the second because the full resolution there lies in N's range. T's bound is the largest over
// the nodes whose footprints share part of T,
// provided those footprints cover all of T (where a node's tile stops short of its footprint,
// at the DEM's edge, only the range term holds); else it is the owner's dike range
// (PyramidNode::dikeRange), which holds every triangle the owner owns (dike_errors.hpp).
// The nodes are found among the nodes of T's vertices and the cut nodes at the
// corners of T's bounding box; coverage is checked by area, so a node that is missed only
// makes the bound fall back, never lie.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <polder/terrain/block_quadtree.hpp>
#include <polder/terrain/dike_error_cache.hpp>
#include <polder/terrain/pyramid.hpp>

#include "cut_index.hpp"
#include "sample_grid.hpp"

namespace polder {

class PyramidDikeBound final : public terrain::DikeTriangleMeasure {
 public:
  // `cutIndex` must index the cut setFrame() is given.
  PyramidDikeBound(const terrain::Pyramid& pyramid, const CutIndex& cutIndex)
      : m_pyramid(pyramid), m_layout(pyramid.layout()), m_cutIndex(cutIndex) {}

  // The frame the next calls are about: its cut and where each dike vertex's height is. Both
  // must outlive the calls.
  void setFrame(std::span<const terrain::SelectedNode> cut, const DikeVertexSamples& samples);

  float height(const terrain::DikeVertex& v, std::uint32_t index) const override {
    return m_samples->of(index, v).height(v.x, v.y);
  }
  float error(const terrain::DikeVertex& a, const terrain::DikeVertex& b, const terrain::DikeVertex& c,
              const terrain::DikeTriangleRef& where) const override;

 private:
  const terrain::Pyramid& m_pyramid;
  terrain::BlockLayout m_layout;
  std::span<const terrain::SelectedNode> m_cut;
  const DikeVertexSamples* m_samples = nullptr;
  const CutIndex& m_cutIndex;
};

}  // namespace polder
