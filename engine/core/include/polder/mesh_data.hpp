// Plain triangle data exchanged between modules: what terrain and mesh objects produce and
// what the renderer and the query scene consume.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

namespace polder {

// An indexed triangle mesh whose positions are relative to `origin` (world frame, double),
// so the floats stay small however far the mesh lies from the world origin.
struct MeshData {
  glm::dvec3 origin{0.0};
  std::vector<glm::vec3> positions;    // relative to origin
  std::vector<glm::vec3> normals;      // unit, one per position (may be empty)
  std::vector<std::uint32_t> indices;  // three per triangle, counter-clockwise seen from outside/above

  std::size_t triangleCount() const { return indices.size() / 3; }
};

// A non-owning view of mesh data: the unit the renderer draws. Spans point into storage
// the caller keeps alive until the draw call returns.
struct DrawItem {
  glm::dvec3 origin{0.0};
  std::span<const glm::vec3> positions;
  std::span<const glm::vec3> normals;
  std::span<const std::uint32_t> indices;
  glm::vec3 tint{1.0f};  // multiplies the shaded colour (debug colouring)
  // Object frame to world, applied before `origin`: world = origin + linear * position. A rigid
  // instance draws its model's shared vertices with its rotation and scale here.
  glm::mat3 linear{1.0f};
};

inline DrawItem drawItemOf(const MeshData& mesh) {
  return DrawItem{mesh.origin, mesh.positions, mesh.normals, mesh.indices, glm::vec3(1.0f)};
}

}  // namespace polder
