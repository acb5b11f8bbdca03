// Garland & Heckbert's quadric error metric (SIGGRAPH 1997): the sum of squared distances
// to a set of planes, Q(p) = p^T A p + 2 b.p + c, each plane weighted (by triangle area).
#pragma once

#include <glm/glm.hpp>

namespace polder::mesh {

struct Quadric {
  double a00 = 0, a01 = 0, a02 = 0, a11 = 0, a12 = 0, a22 = 0;
  double b0 = 0, b1 = 0, b2 = 0;
  double c = 0;
  double weight = 0;  // total plane weight (area), to turn the sum into a mean

  // Adds the plane n.p + d = 0 (n unit) with weight w.
  void addPlane(const glm::dvec3& n, double d, double w) {
    a00 += w * n.x * n.x;
    a01 += w * n.x * n.y;
    a02 += w * n.x * n.z;
    a11 += w * n.y * n.y;
    a12 += w * n.y * n.z;
    a22 += w * n.z * n.z;
    b0 += w * n.x * d;
    b1 += w * n.y * d;
    b2 += w * n.z * d;
    c += w * d * d;
    weight += w;
  }

  Quadric& operator+=(const Quadric& q) {
    a00 += q.a00, a01 += q.a01, a02 += q.a02, a11 += q.a11, a12 += q.a12, a22 += q.a22;
    b0 += q.b0, b1 += q.b1, b2 += q.b2, c += q.c, weight += q.weight;
    return *this;
  }

  // Weighted sum of squared distances from p to the planes (never negative).
  double evaluate(const glm::dvec3& p) const {
    const double rx = a00 * p.x + a01 * p.y + a02 * p.z + b0;
    const double ry = a01 * p.x + a11 * p.y + a12 * p.z + b1;
    const double rz = a02 * p.x + a12 * p.y + a22 * p.z + b2;
    const double q = p.x * rx + p.y * ry + p.z * rz + (b0 * p.x + b1 * p.y + b2 * p.z) + c;
    return q > 0.0 ? q : 0.0;
  }
};

}  // namespace polder::mesh
