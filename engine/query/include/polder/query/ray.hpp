// Rays and hits exchanged with the query scene: plain values in the world frame (double).
#pragma once

#include <limits>

#include <glm/glm.hpp>

namespace polder::query {

// A ray in the world frame. The direction need not be unit length (the scene normalises
// it); distances are metres along the ray, so only the segment [minDistance, maxDistance]
// is searched.
struct QueryRay {
  glm::dvec3 origin{0.0};
  glm::dvec3 direction{0.0, 0.0, -1.0};
  double minDistance = 0.0;
  double maxDistance = std::numeric_limits<double>::infinity();
};

// How a batch of rays is laid out, a hint for the traversal. Coherent: neighbours in the
// batch start close together and point the same way (camera rays in pixel order) — about
// 1.6x faster there, but slower than Incoherent on scattered rays.
enum class RayCoherence { Incoherent, Coherent };

// The nearest intersection of a ray with the surface.
struct RayHit {
  glm::dvec3 point{0.0};   // world frame
  glm::dvec3 normal{0.0};  // geometric normal of the hit triangle, unit, facing against the ray
  double distance = 0.0;   // metres from the ray origin
};

}  // namespace polder::query
