#include "polder/mesh/triangle_mesh.hpp"

#include <cmath>
#include <limits>

namespace polder::mesh {

namespace {

bool attributeSizeFits(std::size_t attributeCount, std::size_t vertexCount) {
  return attributeCount == 0 || attributeCount == vertexCount;
}

}  // namespace

Status validateMesh(const TriangleMesh& mesh, const std::string& what) {
  const std::size_t vertexCount = mesh.positions.size();
  if (vertexCount > std::numeric_limits<std::uint32_t>::max())
    return makeError(ErrorKind::Unsupported, what + ": more than 2^32 - 1 vertices");
  if (mesh.indices.size() % 3 != 0)
    return makeError(ErrorKind::InvalidData, what + ": the index count is not a multiple of 3");
  if (!attributeSizeFits(mesh.normals.size(), vertexCount) || !attributeSizeFits(mesh.colours.size(), vertexCount) ||
      !attributeSizeFits(mesh.uvs.size(), vertexCount))
    return makeError(ErrorKind::InvalidData, what + ": a vertex attribute does not have one entry per vertex");
  for (std::size_t i = 0; i < vertexCount; ++i) {
    const glm::vec3& p = mesh.positions[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      return makeError(ErrorKind::InvalidData, what + ": vertex " + std::to_string(i) + " has a non-finite position");
  }
  for (std::size_t i = 0; i < mesh.indices.size(); ++i) {
    if (mesh.indices[i] >= vertexCount)
      return makeError(ErrorKind::InvalidData, what + ": triangle " + std::to_string(i / 3) + " refers to vertex " +
                                                   std::to_string(mesh.indices[i]) + " of " +
                                                   std::to_string(vertexCount));
  }
  return {};
}

std::vector<glm::vec3> computeVertexNormals(const std::vector<glm::vec3>& positions,
                                            const std::vector<std::uint32_t>& indices) {
  std::vector<glm::dvec3> sums(positions.size(), glm::dvec3(0.0));
  for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
    const glm::dvec3 a(positions[indices[t]]), b(positions[indices[t + 1]]), c(positions[indices[t + 2]]);
    const glm::dvec3 areaNormal = glm::cross(b - a, c - a);  // length = twice the area
    for (int k = 0; k < 3; ++k) sums[indices[t + k]] += areaNormal;
  }
  std::vector<glm::vec3> normals(positions.size());
  for (std::size_t i = 0; i < sums.size(); ++i) {
    const double length = glm::length(sums[i]);
    normals[i] = length > 0.0 ? glm::vec3(sums[i] / length) : glm::vec3(0.0f, 0.0f, 1.0f);
  }
  return normals;
}

PositionBounds boundsOf(const std::vector<glm::vec3>& positions) {
  PositionBounds bounds;
  if (positions.empty()) return bounds;
  bounds.lo = bounds.hi = glm::dvec3(positions.front());
  for (const glm::vec3& p : positions) {
    bounds.lo = glm::min(bounds.lo, glm::dvec3(p));
    bounds.hi = glm::max(bounds.hi, glm::dvec3(p));
  }
  return bounds;
}

double boundingBoxDiagonal(const std::vector<glm::vec3>& positions) { return boundsOf(positions).diagonal(); }

}  // namespace polder::mesh
