// The uniform-error mesh of a whole DEM: blocks plus dikes (J.-H. Chuang, "Level-of-Detail
// Modeling Technique for Virtual Reality (I)", 2001, part B; docs/design.md "Terrain") whose
// vertical error against the full-resolution surface is at most a bound everywhere, checked
// exactly, for baking static terrain (`polder mesh`).
//
// How (buildUniformMesh):
// 1. The cut. Every level-0 block's error hierarchy (rtin.hpp) is extracted at the bound. With
//    coarserLevels, a coarser quadtree node may stand for its four children where it can be
//    drawn within the bound at its stride (its finest mesh is: BlockLod::floorError) and
//    costs fewer triangles than the children's best cuts together, counting its mesh and
//    its kept side vertices (about one dike triangle each): bottom-up, level by level.
// 2. The dikes. The cut's gaps are stitched (dikes.hpp) and every dike triangle's exact error
//    is measured (dikeTriangleError). Where one exceeds the bound, the blocks it lies beside
//    keep their side vertices along it (BoundaryPins, sidesBesideDikeTriangle) and are
//    extracted again: the dike there is refined, down to the surface itself between level-0
//    blocks, where every side vertex is kept. Where no pin is left to add, the coarsest node
//    of level 1 or more the triangle touches is split into its children's best cuts (its dike
//    strip is wider than a cell, with samples no side holds). Repeat until no triangle fails.
// 3. The check. Every block triangle is measured too, with the same exact function as the
//    dike triangles, independently of the hierarchy's stored errors; a block whose triangle
//    fails (rounding at the bound) is extracted again below that triangle's error.
// The result is watertight by construction of the dikes (watertight.hpp checks it) and always
// exists: level-0 blocks at full detail with every side vertex kept are the full-resolution
// surface, blocks and dikes alike.
//
// Cost: about (levels tried) passes of BlockLod::build over the DEM, then a few stitching
// rounds, each re-extracting only the pinned blocks. Memory: the chosen meshes and per-node
// choices (a few bytes per node), never a hierarchy per node. Runs on the calling thread;
// concurrent calls share nothing.
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include <polder/mesh/triangle_mesh.hpp>
#include <polder/result.hpp>
#include <polder/terrain/block_layout.hpp>
#include <polder/terrain/block_mesh.hpp>
#include <polder/terrain/dikes.hpp>
#include <polder/terrain/heightfield.hpp>
#include <polder/terrain/watertight.hpp>

namespace polder::terrain {

// The accepted range of the bound: below a millimetre float heights carry no meaning (a
// float's spacing at 8 km), above 100 km every DEM on Earth is one plane.
inline constexpr double kUniformMeshMinErrorM = 1e-3;
inline constexpr double kUniformMeshMaxErrorM = 1e5;

struct UniformMeshOptions {
  double maxErrorM = 1.0;  // the bound, metres, within [kUniformMeshMinErrorM, kUniformMeshMaxErrorM]
  int blockK = 5;          // blocks of 2^k + 1 samples per side (BlockLayout: k in 1..7)
  bool coarserLevels = true;
  // Called on the calling thread with a fraction rising from 0 to 1.
  std::function<void(float)> progress;
};

struct UniformMeshStats {
  std::size_t blockTriangles = 0;
  std::size_t dikeTriangles = 0;
  float blockMaxErrorM = 0.0f;  // measured exactly, every triangle (rounded up to float)
  float dikeMaxErrorM = 0.0f;
  std::vector<std::size_t> nodesPerLevel;  // the cut's nodes by quadtree level
  std::size_t rounds = 0;                  // stitching rounds (1: no dike triangle failed)
  std::size_t pinnedNodes = 0;             // nodes that keep side vertices for their dikes
  std::size_t splitNodes = 0;              // coarse nodes split because of their dikes
  std::size_t reextractions = 0;           // block extractions after phase 1's (pins, lowered thresholds, splits)
};

struct UniformMesh {
  BlockLayout layout;
  std::vector<NodeId> nodes;      // the cut
  std::vector<BlockMesh> meshes;  // per node of the cut
  DikeMesh dikes;
  UniformMeshStats stats;

  std::size_t triangleCount() const { return stats.blockTriangles + stats.dikeTriangles; }
  float maxErrorM() const {
    return stats.blockMaxErrorM > stats.dikeMaxErrorM ? stats.blockMaxErrorM : stats.dikeMaxErrorM;
  }
};

// The mesh of the bound (see the top). InvalidArgument for a bound outside the range, a bad
// blockK or a field under 2 x 2 samples; InvalidData for a non-finite sample; OutOfMemory
// when the tables cannot be allocated.
Result<UniformMesh> buildUniformMesh(const Heightfield& field, const UniformMeshOptions& options);

// Every triangle of the mesh in global sample coordinates (for checkWatertight).
TriangleSoup uniformMeshSoup(const UniformMesh& mesh);

// The largest exact error (dikeTriangleError) of any triangle of a soup on the field's grid:
// a second measurement, from the triangles alone.
float soupMaxError(const Heightfield& field, const TriangleSoup& soup);

// The mesh in the world frame (docs/design.md "Coordinates"): each used sample once, at
// (x * spacingX, y * spacingY, height), with the full-resolution surface's normals
// (sampleNormal); triangles counter-clockwise seen from above.
mesh::TriangleMesh uniformMeshTriangles(const Heightfield& field, const UniformMesh& mesh);

}  // namespace polder::terrain
