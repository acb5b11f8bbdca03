// What both builders start from: positions scaled to a unit bounding-box diagonal (so
// weights and tolerances do not depend on the model's units), the live triangles (whose
// fans go into a TriangleFans), the corner walks round a fan, and texture-seam twins.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "polder/mesh/region_partition.hpp"
#include "polder/mesh/triangle_mesh.hpp"

namespace polder::mesh {

struct NormalizedPositions {
  std::vector<glm::dvec3> positions;  // (p - lo) / diagonal
  glm::dvec3 extent{0.0};             // of the bounding box, in the same units
  double diagonal = 1.0;              // the scale, in the mesh's units (1 for a point)
};

inline NormalizedPositions normalizePositions(const std::vector<glm::vec3>& positions) {
  NormalizedPositions out;
  const PositionBounds bounds = boundsOf(positions);
  const double diagonal = bounds.diagonal();
  out.diagonal = diagonal > 0.0 ? diagonal : 1.0;
  out.positions.resize(positions.size());
  for (std::size_t v = 0; v < positions.size(); ++v)
    out.positions[v] = (glm::dvec3(positions[v]) - bounds.lo) / out.diagonal;
  out.extent = (bounds.hi - bounds.lo) / out.diagonal;
  return out;
}

// The corners after and before v in triangle c (v is one of its three corners): walking
// them round a vertex's fan follows the triangles' winding. v's corner is found without a
// branch: which corner it is looks random to the branch predictor, and the mispredictions
// were the fan walks' largest cost.
inline int cornerIndex(const std::uint32_t* c, std::uint32_t v) { return int(c[1] == v) + 2 * int(c[2] == v); }
inline std::uint32_t cornerAfter(const std::uint32_t* c, std::uint32_t v) {
  const int k = cornerIndex(c, v);
  return c[k + 1 - 3 * int(k == 2)];
}
inline std::uint32_t cornerBefore(const std::uint32_t* c, std::uint32_t v) {
  const int k = cornerIndex(c, v);
  return c[k - 1 + 3 * int(k == 0)];
}

// The input's triangles without degenerate ones, three corners each.
inline std::vector<std::uint32_t> liveTriangleCorners(const TriangleMesh& mesh) {
  const std::size_t inputTriangles = mesh.triangleCount();
  std::vector<std::uint32_t> corners;
  corners.reserve(3 * inputTriangles);
  for (std::size_t t = 0; t < inputTriangles; ++t) {
    const std::uint32_t a = mesh.indices[3 * t], b = mesh.indices[3 * t + 1], c = mesh.indices[3 * t + 2];
    if (isDegenerate(a, b, c)) continue;
    corners.insert(corners.end(), {a, b, c});
  }
  return corners;
}

// Per vertex, the one other vertex at its bit-identical position (its twin across a texture
// seam, where the surface's vertices are split because their UVs differ), kNoTwin where
// it has none, kManyTwins where three or more share the position. The builders run on the
// locality-ordered copy, where vertices at one position are consecutive (locality_order.hpp
// orders equal Morton codes by position), so one pass over the numbering finds them.
inline constexpr std::uint32_t kNoTwin = 0xffffffffu, kManyTwins = 0xfffffffeu;
inline std::vector<std::uint32_t> positionTwins(const std::vector<glm::vec3>& positions) {
  const auto count = static_cast<std::uint32_t>(positions.size());
  std::vector<std::uint32_t> twin(count, kNoTwin);
  for (std::uint32_t first = 0, end; first < count; first = end) {
    end = first + 1;
    while (end < count && positions[end] == positions[first]) ++end;
    if (end - first == 2)
      twin[first] = first + 1, twin[first + 1] = first;
    else if (end - first > 2)
      std::fill(twin.begin() + first, twin.begin() + end, kManyTwins);
  }
  return twin;
}

// Keeps the twins (positionTwins) that make a texture seam, which the builders move in
// pairs: both are border vertices of the split surface (isBorder) in one region. Every
// other vertex sharing its position loses its twin (kNoTwin) and is returned, to be held
// in place: moving it alone would part the surface where the copies meet.
template <class IsBorder>
std::vector<std::uint32_t> keepSeamTwins(std::vector<std::uint32_t>& twin, const RegionPartition& partition,
                                         const IsBorder& isBorder) {
  std::vector<std::uint32_t> held;
  for (std::uint32_t v = 0; v < twin.size(); ++v) {
    const std::uint32_t other = twin[v];
    if (other == kNoTwin) continue;
    const bool seam =
        other != kManyTwins && isBorder(v) && isBorder(other) && partition.regionOf(v) == partition.regionOf(other);
    if (seam) continue;
    held.push_back(v);
    twin[v] = kNoTwin;
    if (other != kManyTwins) {
      held.push_back(other);
      twin[other] = kNoTwin;
    }
  }
  return held;
}

}  // namespace polder::mesh
