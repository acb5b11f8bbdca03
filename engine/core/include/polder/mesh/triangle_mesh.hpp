// An indexed triangle mesh with optional per-vertex attributes: what mesh import produces,
// what the progressive-mesh builders consume, and what `polder simplify` writes out.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "polder/result.hpp"

namespace polder::mesh {

// Attributes are either empty or hold exactly one entry per position.
struct TriangleMesh {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;      // unit length
  std::vector<glm::vec4> colours;      // RGBA in [0, 1]
  std::vector<glm::vec2> uvs;          // texture coordinates
  std::vector<std::uint32_t> indices;  // three per triangle, counter-clockwise seen from outside

  std::size_t vertexCount() const { return positions.size(); }
  std::size_t triangleCount() const { return indices.size() / 3; }
  bool hasNormals() const { return !normals.empty(); }
  bool hasColours() const { return !colours.empty(); }
  bool hasUvs() const { return !uvs.empty(); }
};

// Whether a triangle repeats a vertex (it has no area to draw and no edges of its own).
inline bool isDegenerate(std::uint32_t a, std::uint32_t b, std::uint32_t c) { return a == b || b == c || a == c; }

// Checks the invariants above plus finite positions and indices in range. `what` names the
// mesh (usually its file) in the error message.
Status validateMesh(const TriangleMesh& mesh, const std::string& what);

// Area-weighted vertex normals from the triangles (unit; vertices without an area-bearing
// triangle get +Z).
std::vector<glm::vec3> computeVertexNormals(const std::vector<glm::vec3>& positions,
                                            const std::vector<std::uint32_t>& indices);

// The axis-aligned bounding box of the positions, in double (both corners 0 when empty).
struct PositionBounds {
  glm::dvec3 lo{0.0}, hi{0.0};
  double diagonal() const { return glm::length(hi - lo); }
};
PositionBounds boundsOf(const std::vector<glm::vec3>& positions);

// Diagonal of the axis-aligned bounding box of the positions (0 for an empty mesh).
double boundingBoxDiagonal(const std::vector<glm::vec3>& positions);

}  // namespace polder::mesh
