// Triangle geometry the builders share, on their normalized positions and three corners a
// triangle (builder_setup.hpp): a triangle's cross product, its area-weighted plane (with
// the fans, set up together), and the plane along a boundary edge that holds the outline.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "halves.hpp"
#include "polder/thread_pool.hpp"
#include "quadric.hpp"
#include "triangle_fans.hpp"

namespace polder::mesh {

// (b - a) x (c - a) for the triangle with corners a, b, c: its normal, twice its area long.
inline glm::dvec3 triangleCross(const std::vector<glm::dvec3>& position, const std::uint32_t* corner) {
  const glm::dvec3& a = position[corner[0]];
  return glm::cross(position[corner[1]] - a, position[corner[2]] - a);
}

// A plane n.p + offset = 0 (n unit) with a weight.
struct WeightedPlane {
  glm::dvec3 normal{0.0};
  double offset = 0.0;
  double weight = 0.0;
};

// The triangle's plane, weighted by its area (zero for a flat triangle).
inline WeightedPlane trianglePlane(const std::vector<glm::dvec3>& position, const std::uint32_t* corner) {
  const glm::dvec3 cross = triangleCross(position, corner);
  const double length = glm::length(cross);
  if (length <= 0.0) return {};
  const glm::dvec3 n = cross / length;
  return {n, -glm::dot(n, position[corner[0]]), 0.5 * length};
}

// Every vertex's fan (its triangles in triangle order) and every triangle's plane, by
// halves on `pool`: fans by vertex, planes by triangle.
inline std::vector<WeightedPlane> fillFansAndPlanes(core::ThreadPool& pool, const std::vector<glm::dvec3>& position,
                                                    const std::vector<std::uint32_t>& corner, TriangleFans& fan) {
  const auto vertexCount = static_cast<std::uint32_t>(position.size());
  const auto triangleCount = static_cast<std::uint32_t>(corner.size() / 3);
  fan.clearAll(vertexCount);
  std::vector<WeightedPlane> plane(triangleCount);
  pool.runHalves([&](int half) {
    const auto [vertexBegin, vertexEnd] = halfOf(vertexCount, half);
    fan.fill(corner, vertexBegin, vertexEnd);
    const auto [begin, end] = halfOf(triangleCount, half);
    for (std::uint32_t t = begin; t < end; ++t) plane[t] = trianglePlane(position, &corner[3 * t]);
  });
  return plane;
}

// Adds the plane through the boundary edge (a, b), perpendicular to its triangle's normal
// `faceNormal` (any length), to both ends' quadrics with weight `boundaryWeight` times the
// edge length squared. It keeps the outline; it does not count in Quadric::weight, so it
// does not dilute the mean surface error.
inline void addBoundaryEdgeQuadric(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& faceNormal,
                                   double boundaryWeight, Quadric& atA, Quadric& atB) {
  const glm::dvec3 edge = b - a;
  const glm::dvec3 planeNormal = glm::cross(edge, faceNormal);
  const double length = glm::length(planeNormal);
  if (length <= 0.0) return;
  const glm::dvec3 n = planeNormal / length;
  Quadric q;
  q.addPlane(n, -glm::dot(n, a), boundaryWeight * glm::dot(edge, edge));
  q.weight = 0.0;
  atA += q;
  atB += q;
}

}  // namespace polder::mesh
