// A watertightness checker for a frame's terrain mesh (block meshes and dikes), or any
// triangle soup on the full-resolution sample grid of a width x height DEM.
//
// What it checks (WatertightReport), all in exact integer arithmetic:
//   - degenerate (zero-area) and clockwise (seen from +z) triangles;
//   - edge use, with vertices keyed by their grid coordinates: an edge off the DEM's outer
//     border must be used by exactly two triangles, in opposite directions; an edge on the
//     border by one, running counter-clockwise around the DEM;
//   - T-junctions: a vertex strictly inside some triangle's edge (searched along every edge
//     that is not shared cleanly, which is where a T-junction shows);
//   - coverage of [0, width-1] x [0, height-1] exactly once. Proven, not sampled: if every
//     triangle is counter-clockwise, every inner edge is shared by two triangles in opposite
//     directions, and the unshared edges run once counter-clockwise around the DEM's border,
//     the triangles' winding numbers add up to that of the border, 1 inside and 0 outside, so
//     each point is covered exactly once; the summed area is checked as well. Optionally it
//     also counts, at random non-grid points, how many triangles contain each point.
//
// Cost: O(n) expected (n = triangles): vertices merged in a hash map on 64-bit keys, edges
// counted through per-vertex half-edge lists; plus the points along edges that are not shared
// cleanly, plus O(samples * triangles per bucket) when sampling. polder bench runs it on
// measured frames.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <polder/terrain/block_mesh.hpp>
#include <polder/terrain/dikes.hpp>

namespace polder::terrain {

// A full-resolution sample in global coordinates.
struct GridPoint {
  std::int32_t x = 0;
  std::int32_t y = 0;
};

// Triangles on the sample grid; vertices may repeat (they are merged by coordinates).
struct TriangleSoup {
  std::vector<GridPoint> points;
  std::vector<std::uint32_t> indices;  // three per triangle

  std::size_t triangleCount() const { return indices.size() / 3; }
  void clear() {
    points.clear();
    indices.clear();
  }
  // Appends a block's triangles, converted from block-local to global sample coordinates.
  void addBlock(const BlockMesh& mesh);
  // Appends a frame's dike triangles.
  void addDikes(const DikeMesh& dikes);
  void addTriangle(GridPoint a, GridPoint b, GridPoint c);
};

struct WatertightOptions {
  // Random points (never on a grid line) at which to count covering triangles; 0 skips.
  std::size_t samplePoints = 0;
  std::uint64_t seed = 1;
};

struct WatertightReport {
  std::size_t triangles = 0;
  std::size_t vertices = 0;              // distinct grid points used
  std::size_t outsidePoints = 0;         // vertices outside [0, width-1] x [0, height-1]
  std::size_t degenerate = 0;            // zero-area triangles
  std::size_t wrongWinding = 0;          // clockwise seen from +z
  std::size_t openEdges = 0;             // off the border, used by one triangle
  std::size_t overSharedEdges = 0;       // used by more than two triangles
  std::size_t flippedEdges = 0;          // shared by two triangles running the same way
  std::size_t tJunctions = 0;            // (vertex, edge) pairs with the vertex strictly inside the edge
  std::size_t borderErrors = 0;          // border edges running clockwise, or border stretches covered 0 or 2+ times
  std::int64_t doubledArea = 0;          // sum of the triangles' signed doubled areas
  std::int64_t expectedDoubledArea = 0;  // 2 (width-1) (height-1)
  bool coversExactly = false;            // the proof above went through
  std::size_t samplesTested = 0;
  std::size_t samplesUncovered = 0;   // sample points in no triangle
  std::size_t samplesOverlapped = 0;  // sample points in two or more

  bool watertight() const {
    return coversExactly && outsidePoints == 0 && degenerate == 0 && wrongWinding == 0 && openEdges == 0 &&
           overSharedEdges == 0 && flippedEdges == 0 && tJunctions == 0 && borderErrors == 0 && samplesUncovered == 0 &&
           samplesOverlapped == 0;
  }
};

WatertightReport checkWatertight(const TriangleSoup& soup, int width, int height,
                                 const WatertightOptions& options = {});

}  // namespace polder::terrain
