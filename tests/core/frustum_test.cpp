#include <polder/frustum.hpp>

#include <cmath>
#include <random>

#include <gtest/gtest.h>
#include <glm/glm.hpp>

namespace polder {
namespace {

// Whether a camera-relative point lies in OpenGL's clip volume, computed the way a renderer
// would: projection * viewRotation, then |x|, |y|, |z| <= w. The reference the frustum must
// agree with.
bool insideClipVolume(const glm::dmat4& viewProjection, const glm::dvec3& relative) {
  const glm::dvec4 clip = viewProjection * glm::dvec4(relative, 1.0);
  return clip.w > 0.0 && std::abs(clip.x) <= clip.w && std::abs(clip.y) <= clip.w && std::abs(clip.z) <= clip.w;
}

Camera randomCamera(std::mt19937_64& rng, double originScale) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Camera camera;
  camera.position = glm::dvec3(originScale * (unit(rng) - 0.5), originScale * (unit(rng) - 0.5), 100.0 * unit(rng));
  camera.yawDeg = 360.0 * unit(rng);
  camera.pitchDeg = -89.0 + 178.0 * unit(rng);
  camera.fovYDeg = 20.0 + 100.0 * unit(rng);
  camera.widthPx = 320 + int(1600.0 * unit(rng));
  camera.heightPx = 240 + int(900.0 * unit(rng));
  camera.nearM = 0.1 + 5.0 * unit(rng);
  camera.farM = camera.nearM + 50.0 + 3000.0 * unit(rng);
  return camera;
}

// A box around the camera, sizes from tiny to larger than the view volume.
Aabb randomBox(std::mt19937_64& rng, const Camera& camera) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double reach = 1.3 * camera.farM;
  const glm::dvec3 centre =
      camera.position +
      glm::dvec3(reach * (2.0 * unit(rng) - 1.0), reach * (2.0 * unit(rng) - 1.0), reach * (2.0 * unit(rng) - 1.0));
  const double size = std::pow(10.0, -1.0 + 4.0 * unit(rng));
  const glm::dvec3 half = 0.5 * size * glm::dvec3(unit(rng), unit(rng), unit(rng));
  return Aabb{centre - half, centre + half};
}

TEST(Frustum, PlanesMatchTheClipVolume) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int c = 0; c < 50; ++c) {
    const Camera camera = randomCamera(rng, 1000.0);
    const Frustum frustum = Frustum::fromCamera(camera);
    const glm::dmat4 viewProjection = camera.projection() * camera.viewRotation();
    int agree = 0, total = 0;
    for (int i = 0; i < 2000; ++i) {
      const glm::dvec3 p = camera.farM * glm::dvec3(unit(rng), unit(rng), unit(rng));
      ++total;
      agree += frustum.containsRelative(p) == insideClipVolume(viewProjection, p);
    }
    EXPECT_EQ(agree, total);
    // The corners project onto the clip volume's corners.
    for (std::size_t i = 0; i < 8; ++i) {
      const glm::dvec4 clip = viewProjection * glm::dvec4(frustum.corners()[i], 1.0);
      EXPECT_NEAR(std::abs(clip.x / clip.w), 1.0, 1e-9);
      EXPECT_NEAR(std::abs(clip.y / clip.w), 1.0, 1e-9);
      EXPECT_NEAR(clip.z / clip.w, i < 4 ? -1.0 : 1.0, 1e-6);
    }
  }
}

// The property culling must have: any box holding a point of the view volume is never
// reported outside. A dense lattice of each box's points stands in for "any point".
TEST(Frustum, NeverCullsABoxWithAPointInTheViewVolume) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int boxesWithVisiblePoints = 0, outside = 0, inside = 0;
  for (int c = 0; c < 40; ++c) {
    const Camera camera = randomCamera(rng, c < 20 ? 1000.0 : 4.0e6);  // half of them far from the origin
    const Frustum frustum = Frustum::fromCamera(camera);
    const glm::dmat4 viewProjection = camera.projection() * camera.viewRotation();
    for (int b = 0; b < 400; ++b) {
      const Aabb box = randomBox(rng, camera);
      const FrustumTest result = frustum.classify(box);
      constexpr int kSteps = 8;
      bool anyInside = false, allInside = true;
      for (int i = 0; i <= kSteps; ++i) {
        for (int j = 0; j <= kSteps; ++j) {
          for (int k = 0; k <= kSteps; ++k) {
            const glm::dvec3 t(double(i) / kSteps, double(j) / kSteps, double(k) / kSteps);
            const glm::dvec3 p = box.minCorner + t * (box.maxCorner - box.minCorner) - camera.position;
            const bool in = insideClipVolume(viewProjection, p);
            anyInside |= in;
            allInside &= in;
          }
        }
      }
      // And some random points, which land off the lattice's planes.
      for (int i = 0; i < 64; ++i) {
        const glm::dvec3 t(unit(rng), unit(rng), unit(rng));
        const glm::dvec3 p = box.minCorner + t * (box.maxCorner - box.minCorner) - camera.position;
        const bool in = insideClipVolume(viewProjection, p);
        anyInside |= in;
        allInside &= in;
      }
      boxesWithVisiblePoints += anyInside;
      outside += result == FrustumTest::Outside;
      inside += result == FrustumTest::Inside;
      if (anyInside) {
        EXPECT_NE(result, FrustumTest::Outside) << "camera " << c << " box " << b;
      }
      if (result == FrustumTest::Inside) {
        EXPECT_TRUE(allInside) << "camera " << c << " box " << b;
      }
    }
  }
  // The random boxes exercise all three answers.
  EXPECT_GT(boxesWithVisiblePoints, 500);
  EXPECT_GT(outside, 3000);
  EXPECT_GT(inside, 50);
}

TEST(Frustum, CullsObviousCases) {
  Camera camera;
  camera.position = glm::dvec3(5.0e5, -3.0e5, 200.0);
  camera.yawDeg = 90.0;  // looking east
  camera.pitchDeg = 0.0;
  camera.nearM = 1.0;
  camera.farM = 1000.0;
  const Frustum frustum = Frustum::fromCamera(camera);
  auto boxAt = [&](glm::dvec3 offset, double half) {
    return Aabb{camera.position + offset - half, camera.position + offset + half};
  };
  EXPECT_EQ(frustum.classify(boxAt({100.0, 0.0, 0.0}, 1.0)), FrustumTest::Inside);
  EXPECT_EQ(frustum.classify(boxAt({-100.0, 0.0, 0.0}, 1.0)), FrustumTest::Outside);        // behind
  EXPECT_EQ(frustum.classify(boxAt({0.5, 0.0, 0.0}, 0.2)), FrustumTest::Outside);           // before near
  EXPECT_EQ(frustum.classify(boxAt({1100.0, 0.0, 0.0}, 50.0)), FrustumTest::Outside);       // beyond far
  EXPECT_EQ(frustum.classify(boxAt({100.0, 0.0, 500.0}, 1.0)), FrustumTest::Outside);       // far above
  EXPECT_EQ(frustum.classify(boxAt({100.0, 500.0, 0.0}, 1.0)), FrustumTest::Outside);       // far north = left
  EXPECT_EQ(frustum.classify(boxAt({0.0, 0.0, 0.0}, 10.0)), FrustumTest::Intersecting);     // around the eye
  EXPECT_EQ(frustum.classify(boxAt({1000.0, 0.0, 0.0}, 10.0)), FrustumTest::Intersecting);  // across far
  // Beside the frustum's top-left edge and across its far plane: no single plane separates
  // it (pass 1 alone says Intersecting), the frustum's corners do.
  EXPECT_EQ(frustum.classify(Aabb{camera.position + glm::dvec3(600.0, 600.0, 600.0),
                                  camera.position + glm::dvec3(1500.0, 700.0, 1000.0)}),
            FrustumTest::Outside);
  // A slab far under the eye reaching forward.
  EXPECT_EQ(frustum.classify(Aabb{camera.position + glm::dvec3(-10.0, -10.0, -2000.0),
                                  camera.position + glm::dvec3(2000.0, 10.0, -1900.0)}),
            FrustumTest::Outside);
}

TEST(Frustum, DistanceToBox) {
  EXPECT_DOUBLE_EQ(distanceToOrigin(Aabb{{-1.0, -1.0, -1.0}, {1.0, 1.0, 1.0}}), 0.0);
  EXPECT_DOUBLE_EQ(distanceToOrigin(Aabb{{3.0, -1.0, -1.0}, {4.0, 1.0, 1.0}}), 3.0);
  EXPECT_DOUBLE_EQ(distanceToOrigin(Aabb{{-5.0, -6.0, 0.0}, {-3.0, -4.0, 1.0}}), 5.0);
  EXPECT_DOUBLE_EQ(distanceToOrigin(Aabb{{1.0, 2.0, 2.0}, {9.0, 9.0, 9.0}}), 3.0);
}

}  // namespace
}  // namespace polder
