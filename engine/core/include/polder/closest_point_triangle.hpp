// The exact closest point on a triangle to a point, in double precision (C. Ericson,
// "Real-Time Collision Detection", 2005, section 5.1.5: the point's Voronoi region of the
// triangle — a vertex, an edge or the face — decides the answer).
//
// The region tests use the triple-product form of Ericson's barycentric numerators,
// n . (x cross y) with n the triangle's normal, which loses less to cancellation on thin
// triangles than his difference of dot products. Degenerate triangles (zero area:
// coincident or collinear vertices) are the union of their edges, so they are answered
// from the closest of the three segments.
#pragma once

#include <glm/glm.hpp>

namespace polder {

struct TrianglePoint {
  glm::dvec3 point{0.0};
  glm::dvec3 weights{1.0, 0.0, 0.0};  // barycentric weights of a, b, c: non-negative, sum 1
};

namespace detail {

// The closest point to p on segment [x, y], as the weight of y (0 for a zero-length segment).
inline double closestOnSegment(const glm::dvec3& p, const glm::dvec3& x, const glm::dvec3& y) {
  const glm::dvec3 xy = y - x;
  const double lengthSquared = glm::dot(xy, xy);
  if (!(lengthSquared > 0.0)) return 0.0;
  return glm::clamp(glm::dot(p - x, xy) / lengthSquared, 0.0, 1.0);
}

// A zero-area triangle is its three edges: the closest point on any of them.
inline TrianglePoint closestOnDegenerateTriangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
                                                 const glm::dvec3& c) {
  const double tab = closestOnSegment(p, a, b);
  const double tbc = closestOnSegment(p, b, c);
  const double tca = closestOnSegment(p, c, a);
  const TrianglePoint candidates[3] = {
      {glm::mix(a, b, tab), {1.0 - tab, tab, 0.0}},
      {glm::mix(b, c, tbc), {0.0, 1.0 - tbc, tbc}},
      {glm::mix(c, a, tca), {tca, 0.0, 1.0 - tca}},
  };
  TrianglePoint best = candidates[0];
  double bestDistance = glm::dot(p - best.point, p - best.point);
  for (int i = 1; i < 3; ++i) {
    const glm::dvec3 d = p - candidates[i].point;
    const double distance = glm::dot(d, d);
    if (distance < bestDistance) best = candidates[i], bestDistance = distance;
  }
  return best;
}

}  // namespace detail

// The point of triangle (a, b, c) closest to p, with its barycentric weights.
inline TrianglePoint closestPointOnTriangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
                                            const glm::dvec3& c) {
  const glm::dvec3 ab = b - a, ac = c - a;
  const glm::dvec3 normal = glm::cross(ab, ac);
  if (!(glm::dot(normal, normal) > 0.0)) return detail::closestOnDegenerateTriangle(p, a, b, c);

  const glm::dvec3 ap = p - a;
  const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) return {a, {1.0, 0.0, 0.0}};

  const glm::dvec3 bp = p - b;
  const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return {b, {0.0, 1.0, 0.0}};

  const double vc = glm::dot(normal, glm::cross(ap, bp));  // = d1 * d4 - d3 * d2
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double v = d1 - d3 > 0.0 ? d1 / (d1 - d3) : 0.0;
    return {a + v * ab, {1.0 - v, v, 0.0}};
  }

  const glm::dvec3 cp = p - c;
  const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return {c, {0.0, 0.0, 1.0}};

  const double vb = glm::dot(normal, glm::cross(cp, ap));  // = d5 * d2 - d1 * d6
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double w = d2 - d6 > 0.0 ? d2 / (d2 - d6) : 0.0;
    return {a + w * ac, {1.0 - w, 0.0, w}};
  }

  const double va = glm::dot(normal, glm::cross(bp, cp));  // = d3 * d6 - d5 * d4
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) {
    const double denominator = (d4 - d3) + (d5 - d6);
    const double w = denominator > 0.0 ? (d4 - d3) / denominator : 0.0;
    return {b + w * (c - b), {0.0, 1.0 - w, w}};
  }

  // Inside the face: all three numerators are positive in exact arithmetic. A sum that
  // rounding left non-positive means a triangle too thin to have a face worth the name.
  const double sum = va + vb + vc;
  if (!(sum > 0.0)) return detail::closestOnDegenerateTriangle(p, a, b, c);
  const double v = glm::max(vb, 0.0) / sum, w = glm::max(vc, 0.0) / sum;
  const double u = glm::max(1.0 - v - w, 0.0);
  return {a + v * ab + w * ac, {u, v, w}};
}

}  // namespace polder
