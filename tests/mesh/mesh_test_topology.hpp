// What the progressive-mesh tests look at: the triangles an instance draws, how many
// triangles use each edge, and which way a drawn triangle faces.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <map>
#include <span>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "polder/mesh/progressive_mesh_instance.hpp"

namespace polder::test {

using Edge = std::pair<std::uint32_t, std::uint32_t>;

// All triangles an instance draws, over every region.
inline std::vector<std::uint32_t> drawnIndices(const mesh::ProgressiveMeshInstance& instance) {
  std::vector<std::uint32_t> out;
  for (std::uint32_t r = 0; r < instance.mesh().regionCount(); ++r) {
    auto idx = instance.indices(r);
    out.insert(out.end(), idx.begin(), idx.end());
  }
  return out;
}

// Undirected edge -> number of triangles using it.
inline std::map<Edge, int> edgeUse(const std::vector<std::uint32_t>& indices) {
  std::map<Edge, int> use;
  for (std::size_t t = 0; t + 2 < indices.size(); t += 3)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = indices[t + k], b = indices[t + (k + 1) % 3];
      ++use[{std::min(a, b), std::max(a, b)}];
    }
  return use;
}

inline std::size_t openEdgeCount(const std::vector<std::uint32_t>& indices) {
  std::size_t open = 0;
  for (const auto& [edge, count] : edgeUse(indices)) open += count == 1;
  return open;
}

// Whether the triangle at indices[slot..slot+2] repeats a vertex.
inline bool isDegenerate(std::span<const std::uint32_t> indices, std::size_t slot) {
  return mesh::isDegenerate(indices[slot], indices[slot + 1], indices[slot + 2]);
}

// Pairs of drawn triangles on the same three vertices facing apart: a fin standing out of
// the surface (degenerate triangles aside).
inline std::size_t foldedPairCount(const std::vector<std::uint32_t>& indices) {
  std::map<std::array<std::uint32_t, 3>, std::pair<int, int>> facing;  // sorted corners -> (even, odd) windings
  for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
    if (isDegenerate(indices, t)) continue;
    std::array<std::uint32_t, 3> c = {indices[t], indices[t + 1], indices[t + 2]};
    // The winding's parity: rotate the smallest corner first; then ascending or not.
    while (c[0] > c[1] || c[0] > c[2]) std::rotate(c.begin(), c.begin() + 1, c.end());
    const bool ascending = c[1] < c[2];
    std::sort(c.begin(), c.end());
    auto& [even, odd] = facing[c];
    ++(ascending ? even : odd);
  }
  std::size_t pairs = 0;
  for (const auto& [corners, windings] : facing) pairs += std::size_t(std::min(windings.first, windings.second));
  return pairs;
}

// The triangles that are not degenerate (a flattened pair is drawn as nothing).
inline std::vector<std::uint32_t> withoutDegenerate(const std::vector<std::uint32_t>& indices) {
  std::vector<std::uint32_t> out;
  for (std::size_t t = 0; t + 2 < indices.size(); t += 3)
    if (!isDegenerate(indices, t)) out.insert(out.end(), {indices[t], indices[t + 1], indices[t + 2]});
  return out;
}

// The normal of the triangle at indices[slot..slot+2], twice its area long.
inline glm::dvec3 triangleNormal(const std::vector<glm::vec3>& positions, std::span<const std::uint32_t> indices,
                                 std::size_t slot) {
  const glm::dvec3 a(positions[indices[slot]]), b(positions[indices[slot + 1]]), c(positions[indices[slot + 2]]);
  return glm::cross(b - a, c - a);
}

}  // namespace polder::test
