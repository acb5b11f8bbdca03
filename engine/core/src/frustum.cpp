#include <polder/frustum.hpp>

#include <algorithm>
#include <cassert>
#include <cmath>

namespace polder {
namespace {

constexpr double kDegToRad = 3.14159265358979323846 / 180.0;
// Relative slack of the culling tests. A plane distance of coordinates of size c carries a
// rounding error of a few 1e-16 * c, and the planes differ from the projection matrix's by
// as much again; 1e-12 * c covers both with room, and is far below anything visible.
constexpr double kRelativeSlack = 1e-12;

double maxAbs(const glm::dvec3& v) { return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)}); }

Plane makePlane(const glm::dvec3& normal, double offset) {
  const double length = glm::length(normal);
  return Plane{normal / length, offset / length};
}

}  // namespace

Frustum Frustum::fromCamera(const Camera& camera) {
  assert(camera.nearM > 0.0 && camera.farM > camera.nearM && "Frustum::fromCamera: need 0 < nearM < farM");
  assert(camera.fovYDeg > 0.0 && camera.fovYDeg < 180.0 && "Frustum::fromCamera: fovYDeg must be in (0, 180)");
  assert(camera.widthPx > 0 && camera.heightPx > 0 && "Frustum::fromCamera: empty viewport");

  const glm::dvec3 f = camera.forward(), r = camera.right(), u = camera.up();
  const double tanY = std::tan(0.5 * camera.fovYDeg * kDegToRad);
  const double tanX = tanY * camera.aspect();

  Frustum frustum;
  frustum.m_origin = camera.position;
  // Inside the left plane: x_eye >= -tanX * depth, i.e. dot(p, r + tanX f) >= 0; likewise
  // for the others. Side planes pass through the camera, so their offsets are exactly 0.
  frustum.m_planes[Left] = makePlane(r + tanX * f, 0.0);
  frustum.m_planes[Right] = makePlane(-r + tanX * f, 0.0);
  frustum.m_planes[Bottom] = makePlane(u + tanY * f, 0.0);
  frustum.m_planes[Top] = makePlane(-u + tanY * f, 0.0);
  frustum.m_planes[Near] = Plane{f, -camera.nearM};
  frustum.m_planes[Far] = Plane{-f, camera.farM};

  int index = 0;
  for (const double depth : {camera.nearM, camera.farM}) {
    for (const double sy : {-1.0, 1.0}) {
      for (const double sx : {-1.0, 1.0}) {
        frustum.m_corners[std::size_t(index++)] = depth * (f + sx * tanX * r + sy * tanY * u);
      }
    }
  }
  frustum.m_cornerMin = frustum.m_cornerMax = frustum.m_corners[0];
  for (const glm::dvec3& c : frustum.m_corners) {
    frustum.m_cornerMin = glm::min(frustum.m_cornerMin, c);
    frustum.m_cornerMax = glm::max(frustum.m_cornerMax, c);
  }
  return frustum;
}

FrustumTest Frustum::classifyRelative(const Aabb& box) const {
  assert(box.minCorner.x <= box.maxCorner.x && box.minCorner.y <= box.maxCorner.y &&
         box.minCorner.z <= box.maxCorner.z && "Frustum::classifyRelative: box corners out of order");
  const double scale = std::max(maxAbs(box.minCorner), maxAbs(box.maxCorner));

  // Pass 2 first: it is three interval comparisons, and it rejects most boxes behind or
  // beside the camera before any dot product.
  const glm::dvec3 cornerSlack = kRelativeSlack * (glm::abs(m_cornerMin) + glm::abs(m_cornerMax) + scale);
  for (int axis = 0; axis < 3; ++axis) {
    if (box.minCorner[axis] > m_cornerMax[axis] + cornerSlack[axis] ||
        box.maxCorner[axis] < m_cornerMin[axis] - cornerSlack[axis]) {
      return FrustumTest::Outside;
    }
  }

  // Pass 1: p-vertex (farthest along the normal) and n-vertex (nearest) of each plane.
  bool inside = true;
  for (const Plane& plane : m_planes) {
    glm::dvec3 pVertex, nVertex;
    for (int axis = 0; axis < 3; ++axis) {
      const bool positive = plane.normal[axis] >= 0.0;
      pVertex[axis] = positive ? box.maxCorner[axis] : box.minCorner[axis];
      nVertex[axis] = positive ? box.minCorner[axis] : box.maxCorner[axis];
    }
    const double slack = kRelativeSlack * (3.0 * scale + std::abs(plane.offset));
    if (plane.distance(pVertex) < -slack) return FrustumTest::Outside;
    if (plane.distance(nVertex) <= slack) inside = false;
  }
  return inside ? FrustumTest::Inside : FrustumTest::Intersecting;
}

bool Frustum::containsRelative(const glm::dvec3& p) const {
  for (const Plane& plane : m_planes) {
    if (plane.distance(p) < 0.0) return false;
  }
  return true;
}

double distanceToOrigin(const Aabb& relativeBox) {
  // Per axis, how far 0 lies outside [min, max].
  const glm::dvec3 below = glm::max(relativeBox.minCorner, glm::dvec3(0.0));
  const glm::dvec3 above = glm::max(-relativeBox.maxCorner, glm::dvec3(0.0));
  return glm::length(below + above);
}

}  // namespace polder
