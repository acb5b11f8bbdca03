// What the engine keeps in memory for a node it may draw: the node's error hierarchy and,
// from a pyramid, the node's tile, which holds the heights of its footprint at its stride for
// the pieces' vertices and the dike check (docs/streaming.md "Run time").
#pragma once

#include <cstddef>
#include <cstdint>

#include <polder/terrain/pyramid.hpp>
#include <polder/terrain/rtin.hpp>

namespace polder {

struct ResidentBlock {
  terrain::BlockLod lod;
  terrain::PyramidTile tile;          // empty when the engine's source is a heightfield
  std::uint64_t lastNeededFrame = 0;  // the last frame whose selection or meshes used it

  std::size_t memoryBytes() const {
    return lod.memoryBytes() + (tile.samples.heights.capacity() + tile.cellResidual.capacity()) * sizeof(float);
  }
};

}  // namespace polder
