// Exact closest points on a triangle mesh: Embree's BVH (rtcPointQuery) finds the
// candidate triangles near a point, closestPointOnTriangle() measures each in double.
//
// Thread contract as for QueryScene: create() builds and commits; afterwards closest() may
// run from any number of threads at once.
#pragma once

#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <span>

#include <glm/glm.hpp>

#include <polder/closest_point_triangle.hpp>
#include <polder/result.hpp>

namespace polder::query::detail {

struct ClosestTriangle {
  std::uint32_t triangle = 0;  // index of the triangle (its indices start at 3 * triangle)
  TrianglePoint closest;       // the closest point on it, with its weights
  double distanceSquared = 0.0;
};

class ClosestPointScene {
 public:
  // Copies the mesh. `indices` holds three per triangle, all below positions.size(), and
  // positions are finite (the caller validated the mesh). `buildThreads` 0 = Embree's
  // default. Fails with Embree's error (embree_device.hpp), mostly Environment or OutOfMemory.
  static Result<std::unique_ptr<ClosestPointScene>> create(std::span<const glm::vec3> positions,
                                                           std::span<const std::uint32_t> indices, int buildThreads);

  ~ClosestPointScene();
  ClosestPointScene(const ClosestPointScene&) = delete;
  ClosestPointScene& operator=(const ClosestPointScene&) = delete;

  // The closest point of the mesh to `point` (the first triangle found among equally close
  // ones). `within` is a distance the caller knows the answer lies within (the distance to
  // any point of the mesh will do): the search prunes by it from the start, which is much
  // faster than an open search. nullopt for a non-finite point, a mesh without triangles or
  // nothing within `within`.
  std::optional<ClosestTriangle> closest(const glm::dvec3& point,
                                         double within = std::numeric_limits<double>::infinity()) const;

 private:
  struct Impl;
  explicit ClosestPointScene(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> m_impl;
};

}  // namespace polder::query::detail
