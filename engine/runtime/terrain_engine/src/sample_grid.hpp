// Heights and normals at full-resolution sample positions, from a grid that holds them at a
// stride: the whole heightfield (stride 1), or one node's pyramid tile (its footprint at the
// node's stride, docs/streaming.md). A sample of a level surface is the full-resolution sample
// at the same place, so every grid that holds a position gives it the same height; normals
// come from the grid's own neighbours, so they are the level surface's.
#pragma once

#include <cassert>
#include <cstdint>
#include <span>

#include <glm/glm.hpp>

#include <polder/terrain/dike_stage.hpp>
#include <polder/terrain/heightfield.hpp>
#include <polder/terrain/normals.hpp>

namespace polder {

struct SampleGrid {
  const terrain::Heightfield* samples = nullptr;
  int x0 = 0;  // the full-resolution sample of samples(0, 0)
  int y0 = 0;
  int stride = 1;
  // A pyramid tile's bound on |full resolution - level surface| per cell of `samples`
  // (PyramidTile::cellResidual); empty where `samples` is the full resolution.
  std::span<const float> cellResidual;

  float residual(int i, int j) const {
    return cellResidual.empty() ? 0.0f
                                : cellResidual[std::size_t(j) * std::size_t(samples->width - 1) + std::size_t(i)];
  }

  bool holds(int x, int y) const {
    const int dx = x - x0, dy = y - y0;
    return samples && dx >= 0 && dy >= 0 && dx % stride == 0 && dy % stride == 0 && dx / stride < samples->width &&
           dy / stride < samples->height;
  }
  float height(int x, int y) const {
    assert(holds(x, y) && "SampleGrid: the position is not on the grid");
    return samples->at((x - x0) / stride, (y - y0) / stride);
  }
  glm::vec3 normal(int x, int y) const {
    assert(holds(x, y) && "SampleGrid: the position is not on the grid");
    return terrain::sampleNormal(*samples, (x - x0) / stride, (y - y0) / stride);
  }
};

// The grid holding each vertex of a frame's dikes (DikeStage::mesh()): a side vertex is on its
// node's grid, a DEM-border sample on the border's.
struct DikeVertexSamples {
  std::span<const SampleGrid> cut;            // per node of the cut
  const terrain::DikeStage* stage = nullptr;  // the frame's dikes
  SampleGrid eastBorder;                      // holds x = eastX
  SampleGrid northBorder;                     // holds the rest of y = height - 1
  int eastX = 0;                              // width - 1

  const SampleGrid& of(std::uint32_t vertex, const terrain::DikeVertex& v) const {
    const std::uint32_t node = stage->vertexNodes()[vertex];
    if (node != terrain::DikeStage::kNoNode) return cut[node];
    return v.x == eastX ? eastBorder : northBorder;
  }
};

}  // namespace polder
