#include <polder/camera.hpp>

#include <cmath>

#include <gtest/gtest.h>
#include <glm/glm.hpp>

namespace polder {
namespace {

TEST(Camera, YawIsClockwiseFromNorthAndPitchIsUp) {
  Camera camera;
  camera.yawDeg = 0.0;
  EXPECT_NEAR(camera.forward().y, 1.0, 1e-12);  // north
  camera.yawDeg = 90.0;
  EXPECT_NEAR(camera.forward().x, 1.0, 1e-12);  // east
  camera.pitchDeg = 90.0;
  EXPECT_NEAR(camera.forward().z, 1.0, 1e-12);  // straight up
}

TEST(Camera, FrameIsRightHandedAndOrthonormal) {
  Camera camera;
  camera.yawDeg = 37.0;
  camera.pitchDeg = -21.0;
  const auto f = camera.forward(), r = camera.right(), u = camera.up();
  EXPECT_NEAR(glm::dot(f, r), 0.0, 1e-12);
  EXPECT_NEAR(glm::dot(f, u), 0.0, 1e-12);
  EXPECT_NEAR(glm::length(u), 1.0, 1e-12);
  EXPECT_GT(u.z, 0.0);
  EXPECT_NEAR(glm::length(glm::cross(r, f) - u), 0.0, 1e-12);
}

TEST(Camera, CentrePixelRayIsForwardAndProjectsToScreenCentre) {
  Camera camera;
  camera.widthPx = 800;
  camera.heightPx = 600;
  camera.yawDeg = 120.0;
  camera.pitchDeg = -10.0;
  const auto ray = camera.pixelRay(400.0, 300.0);
  EXPECT_NEAR(glm::length(ray - camera.forward()), 0.0, 1e-12);

  // A pixel ray pushed through view and projection lands back on its pixel.
  const auto corner = camera.pixelRay(10.5, 20.5);
  const glm::dvec4 clip = camera.projection() * camera.viewRotation() * glm::dvec4(corner * 50.0, 1.0);
  const double px = (clip.x / clip.w * 0.5 + 0.5) * camera.widthPx;
  const double py = (0.5 - clip.y / clip.w * 0.5) * camera.heightPx;
  EXPECT_NEAR(px, 10.5, 1e-6);
  EXPECT_NEAR(py, 20.5, 1e-6);
}

TEST(Camera, ProjectionConstantMatchesFieldOfView) {
  Camera camera;
  camera.heightPx = 800;
  camera.fovYDeg = 90.0;
  EXPECT_NEAR(camera.projectionConstant(), 400.0, 1e-9);
}

}  // namespace
}  // namespace polder

namespace polder {
namespace {

// A vertical segment anywhere in the view never covers more than
// errorProjectionConstant() * length / distance pixels.
TEST(Camera, ErrorProjectionConstantBoundsVerticalErrorsEverywhereInTheView) {
  Camera camera;
  camera.widthPx = 320;
  camera.heightPx = 240;
  camera.fovYDeg = 60.0;
  camera.yawDeg = 30.0;
  camera.pitchDeg = -35.0;
  const glm::dmat4 viewProjection = camera.projection() * camera.viewRotation();
  auto toPixels = [&](const glm::dvec3& p) {
    const glm::dvec4 clip = viewProjection * glm::dvec4(p, 1.0);
    return glm::dvec2((clip.x / clip.w * 0.5 + 0.5) * camera.widthPx, (0.5 - clip.y / clip.w * 0.5) * camera.heightPx);
  };
  double worstRatio = 0.0;
  for (int py = 0; py <= 240; py += 8)
    for (int px = 0; px <= 320; px += 8) {
      const glm::dvec3 p = camera.pixelRay(px, py) * 1000.0;
      const double pixels = glm::length(toPixels(p + glm::dvec3(0, 0, 0.01)) - toPixels(p));
      worstRatio = std::max(worstRatio, pixels / (0.01 / glm::length(p)));
    }
  EXPECT_LE(worstRatio, camera.errorProjectionConstant() * (1.0 + 1e-3));
  EXPECT_GT(worstRatio, camera.projectionConstant() * 1.2);  // the centre-of-screen K alone is not enough
}

}  // namespace
}  // namespace polder
