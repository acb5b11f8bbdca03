// Ray/triangle intersection in double precision, used to refine the hits Embree finds in
// single precision (Moeller and Trumbore, "Fast, minimum storage ray-triangle
// intersection", 1997).
#pragma once

#include <cmath>
#include <optional>

#include <glm/glm.hpp>

namespace polder::query::detail {

struct TriangleHit {
  double t = 0.0;   // along the ray, in units of the direction's length
  double b1 = 0.0;  // weight of p1
  double b2 = 0.0;  // weight of p2 (p0 gets 1 - b1 - b2)
};

// The hit of the ray origin + t * direction with triangle (p0, p1, p2), both sides,
// accepting barycentric weights down to -tolerance (so a ray through a shared edge is not
// lost to rounding). nullopt when the ray misses or is parallel to the triangle.
inline std::optional<TriangleHit> intersectTriangle(const glm::dvec3& origin, const glm::dvec3& direction,
                                                    const glm::dvec3& p0, const glm::dvec3& p1, const glm::dvec3& p2,
                                                    double tolerance) {
  const glm::dvec3 e1 = p1 - p0;
  const glm::dvec3 e2 = p2 - p0;
  const glm::dvec3 pvec = glm::cross(direction, e2);
  const double det = glm::dot(e1, pvec);
  if (det == 0.0 || !std::isfinite(det)) return std::nullopt;
  const double invDet = 1.0 / det;
  const glm::dvec3 s = origin - p0;
  const double b1 = glm::dot(s, pvec) * invDet;
  if (b1 < -tolerance || b1 > 1.0 + tolerance) return std::nullopt;
  const glm::dvec3 qvec = glm::cross(s, e1);
  const double b2 = glm::dot(direction, qvec) * invDet;
  if (b2 < -tolerance || b1 + b2 > 1.0 + tolerance) return std::nullopt;
  return TriangleHit{glm::dot(e2, qvec) * invDet, b1, b2};
}

}  // namespace polder::query::detail
