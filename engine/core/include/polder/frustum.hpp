// The camera's view volume as six planes, and conservative box culling against it
// (docs/design.md "One frame", step 1: the quadtree selection culls node boxes with it).
//
// Camera-relative. The planes are kept in the camera's own translated frame (world minus
// Camera::position), in double, and boxes are moved into that frame before the test: a box
// 100 km from the origin is tested as precisely as one beside it, and the four side planes
// pass exactly through the origin. The planes are built from the camera's axes and field of
// view, the same quantities Camera::projection() * Camera::viewRotation() uses, so "inside"
// here is "inside the OpenGL clip volume" there, near and far planes included.
//
// Conservative. classify() never says Outside for a box that shares a point with the view
// volume. It runs two separating-axis passes:
//   1. the six frustum planes against the box's p-vertex (the corner farthest along each
//      plane's normal): all of the box behind one plane -> Outside;
//   2. the three box axes against the frustum's eight corners: all corners beyond one box
//      face -> Outside. This removes most false positives of pass 1 (big boxes beside the
//      frustum's edges, which no single plane separates).
// What remains are boxes separated only along a cross product of a box edge and a frustum
// edge: they are reported as intersecting (a false positive costs a little drawing, a false
// negative is a hole). Both passes allow a relative slack of about 1e-12 of the coordinates,
// so rounding can only ever turn Outside into Intersecting, never the reverse.
//
// Threads: a Frustum is an immutable value; any number of threads may test against it.
#pragma once

#include <array>

#include <glm/glm.hpp>

#include <polder/camera.hpp>

namespace polder {

// An axis-aligned box, world frame or camera-relative as the function taking it says.
// minCorner <= maxCorner componentwise (asserted where it matters); degenerate boxes are fine.
struct Aabb {
  glm::dvec3 minCorner{0.0};
  glm::dvec3 maxCorner{0.0};
};

// A plane {p : dot(normal, p) + offset = 0}; the frustum's inside is where that is >= 0.
// normal is unit length, so the value is a signed distance in metres.
struct Plane {
  glm::dvec3 normal{0.0, 0.0, 1.0};
  double offset = 0.0;

  double distance(const glm::dvec3& p) const { return glm::dot(normal, p) + offset; }
};

enum class FrustumTest : int {
  Outside = 0,       // no point of the box is in the view volume
  Intersecting = 1,  // the box may cross the view volume's boundary (conservative)
  Inside = 2,        // every point of the box is in the view volume
};

class Frustum {
 public:
  enum PlaneIndex : int { Left = 0, Right = 1, Bottom = 2, Top = 3, Near = 4, Far = 5 };

  Frustum() = default;
  // The view volume of `camera`: its field of view and aspect, between nearM and farM.
  // Asserts 0 < nearM < farM and 0 < fovYDeg < 180.
  static Frustum fromCamera(const Camera& camera);

  // The world position the frustum is relative to (the camera's position).
  const glm::dvec3& origin() const { return m_origin; }
  // Planes and corners, camera-relative. Corners: near plane then far plane, each
  // bottom-left, bottom-right, top-left, top-right as seen through the camera.
  const std::array<Plane, 6>& planes() const { return m_planes; }
  const std::array<glm::dvec3, 8>& corners() const { return m_corners; }

  // The box relative to origin() (world box minus camera position: what BlockQuadtree
  // and other callers that already work camera-relative pass).
  FrustumTest classifyRelative(const Aabb& box) const;
  bool intersectsRelative(const Aabb& box) const { return classifyRelative(box) != FrustumTest::Outside; }

  // A world-frame box; moved to the camera's frame in double first.
  FrustumTest classify(const Aabb& worldBox) const {
    return classifyRelative(Aabb{worldBox.minCorner - m_origin, worldBox.maxCorner - m_origin});
  }
  bool intersects(const Aabb& worldBox) const { return classify(worldBox) != FrustumTest::Outside; }

  // Whether a camera-relative point is in the view volume (no slack).
  bool containsRelative(const glm::dvec3& p) const;

 private:
  glm::dvec3 m_origin{0.0};
  std::array<Plane, 6> m_planes{};
  std::array<glm::dvec3, 8> m_corners{};
  glm::dvec3 m_cornerMin{0.0};  // bounding box of the corners, for pass 2
  glm::dvec3 m_cornerMax{0.0};
};

// Euclidean distance from camera-relative point 0 (the camera) to the box; 0 when the camera
// is inside it or on it.
double distanceToOrigin(const Aabb& relativeBox);

}  // namespace polder
