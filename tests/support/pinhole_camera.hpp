// An independent pinhole model of polder::Camera, for tests that check measurements: the eye
// frame from forward/right/up and the tangent of half the vertical field of view, without the
// library's view and projection matrices.
#pragma once

#include <cmath>

#include <glm/glm.hpp>

#include <polder/camera.hpp>

namespace polder::test {

struct PinholePixel {
  glm::dvec2 pixel{0.0};  // x right, y down, pixel units
  bool onScreen = false;  // in front of the near plane and inside the viewport
};

inline PinholePixel pinholePixel(const Camera& camera, const glm::dvec3& point) {
  const glm::dvec3 d = point - camera.position;
  const double tanHalf = std::tan(0.5 * camera.fovYDeg * std::acos(-1.0) / 180.0);
  const double aspect = double(camera.widthPx) / double(camera.heightPx);
  const double depth = glm::dot(d, camera.forward());
  const double ndcX = glm::dot(d, camera.right()) / (depth * tanHalf * aspect);
  const double ndcY = glm::dot(d, camera.up()) / (depth * tanHalf);
  PinholePixel out;
  out.pixel = {(ndcX * 0.5 + 0.5) * camera.widthPx, (0.5 - ndcY * 0.5) * camera.heightPx};
  out.onScreen = depth >= camera.nearM && std::abs(ndcX) <= 1.0 && std::abs(ndcY) <= 1.0;
  return out;
}

}  // namespace polder::test
