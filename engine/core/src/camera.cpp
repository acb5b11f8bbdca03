#include <polder/camera.hpp>

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>

namespace polder {

namespace {
constexpr double kDegToRad = 3.14159265358979323846 / 180.0;
}

glm::dvec3 Camera::forward() const {
  const double yaw = yawDeg * kDegToRad;
  const double pitch = pitchDeg * kDegToRad;
  return {std::sin(yaw) * std::cos(pitch), std::cos(yaw) * std::cos(pitch), std::sin(pitch)};
}

glm::dvec3 Camera::right() const {
  const double yaw = yawDeg * kDegToRad;
  return {std::cos(yaw), -std::sin(yaw), 0.0};
}

glm::dvec3 Camera::up() const { return glm::cross(right(), forward()); }

double Camera::projectionConstant() const { return double(heightPx) / (2.0 * std::tan(0.5 * fovYDeg * kDegToRad)); }

double Camera::errorProjectionConstant() const {
  const double halfHeight = std::tan(0.5 * fovYDeg * kDegToRad);
  const double halfDiagonalSquared = halfHeight * halfHeight * (1.0 + aspect() * aspect());
  return projectionConstant() * (1.0 + halfDiagonalSquared);
}

glm::dmat4 Camera::viewRotation() const {
  const glm::dvec3 f = forward(), r = right(), u = up();
  glm::dmat4 view(1.0);
  // Rows are the eye axes: x = right, y = up, z = -forward.
  view[0][0] = r.x;
  view[1][0] = r.y;
  view[2][0] = r.z;
  view[0][1] = u.x;
  view[1][1] = u.y;
  view[2][1] = u.z;
  view[0][2] = -f.x;
  view[1][2] = -f.y;
  view[2][2] = -f.z;
  return view;
}

glm::dmat4 Camera::projection() const { return glm::perspective(fovYDeg * kDegToRad, aspect(), nearM, farM); }

glm::dvec3 Camera::pixelRay(double px, double py) const {
  const double halfHeight = std::tan(0.5 * fovYDeg * kDegToRad);
  const double ndcX = 2.0 * px / double(widthPx) - 1.0;
  const double ndcY = 1.0 - 2.0 * py / double(heightPx);
  const glm::dvec3 dir = forward() + right() * (ndcX * halfHeight * aspect()) + up() * (ndcY * halfHeight);
  return glm::normalize(dir);
}

}  // namespace polder
