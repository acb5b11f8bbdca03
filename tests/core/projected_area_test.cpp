// Projected box area (Schmalstieg & Tobler, JGT 1999; ASLOD Schmalstieg and Fuhrmann 1999
// section 3) against brute-force references: the convex hull of the eight corners pushed
// through the camera's own view and projection matrices, and pixel-ray coverage.
#include <polder/lod/projected_area.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace polder::lod {
namespace {

glm::dmat3 randomRotation(std::mt19937_64& rng) {
  std::normal_distribution<double> normal;
  const glm::dquat q = glm::normalize(glm::dquat(normal(rng), normal(rng), normal(rng), normal(rng)));
  return glm::mat3_cast(q);
}

std::array<glm::dvec3, 8> cornersOf(const OrientedBox& box) {
  std::array<glm::dvec3, 8> corners;
  for (int v = 0; v < 8; ++v) {
    corners[v] = box.centre;
    for (int k = 0; k < 3; ++k) corners[v] += box.axes[k] * (box.halfExtents[k] * ((v >> k & 1) ? 1.0 : -1.0));
  }
  return corners;
}

double cross(const glm::dvec2& o, const glm::dvec2& a, const glm::dvec2& b) {
  return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

// Area of the convex hull of points (Andrew's monotone chain; written apart from the
// engine's own so the two do not share a bug).
double hullArea(std::vector<glm::dvec2> points) {
  std::sort(points.begin(), points.end(),
            [](const glm::dvec2& a, const glm::dvec2& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
  std::vector<glm::dvec2> hull(2 * points.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  for (std::size_t i = points.size() - 1, t = k + 1; i-- > 0;) {
    while (k >= t && cross(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  hull.resize(k > 0 ? k - 1 : 0);
  double twice = 0.0;
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const glm::dvec2& a = hull[i];
    const glm::dvec2& b = hull[(i + 1) % hull.size()];
    twice += a.x * b.y - a.y * b.x;
  }
  return 0.5 * std::abs(twice);
}

// Pixel position of a world point through the renderer's matrices (as camera_test does),
// or nothing when it is not in front of the near plane.
bool toPixels(const Camera& camera, const glm::dvec3& world, glm::dvec2& pixel) {
  const glm::dvec4 clip = camera.projection() * camera.viewRotation() * glm::dvec4(world - camera.position, 1.0);
  if (clip.w < camera.nearM) return false;
  pixel = {(clip.x / clip.w * 0.5 + 0.5) * camera.widthPx, (0.5 - clip.y / clip.w * 0.5) * camera.heightPx};
  return true;
}

// Brute force for a box wholly in front of the near plane; false when it is not.
bool referenceArea(const OrientedBox& box, const Camera& camera, double& area) {
  std::vector<glm::dvec2> points;
  for (const glm::dvec3& corner : cornersOf(box)) {
    glm::dvec2 pixel;
    if (!toPixels(camera, corner, pixel)) return false;
    points.push_back(pixel);
  }
  area = hullArea(points);
  return true;
}

Camera randomCamera(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Camera camera;
  camera.position = {2000.0 * unit(rng) - 1000.0, 2000.0 * unit(rng) - 1000.0, 500.0 * unit(rng)};
  camera.yawDeg = 360.0 * unit(rng);
  camera.pitchDeg = 170.0 * unit(rng) - 85.0;
  camera.fovYDeg = 20.0 + 80.0 * unit(rng);
  camera.widthPx = 320 + int(2240 * unit(rng));
  camera.heightPx = 240 + int(1200 * unit(rng));
  camera.nearM = 0.1 + 5.0 * unit(rng);
  return camera;
}

TEST(ProjectedArea, MatchesHullOfProjectedCornersForRandomBoxes) {
  std::mt19937_64 rng(1999);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int checked = 0;
  while (checked < 3000) {
    const Camera camera = randomCamera(rng);
    const double distance = camera.nearM + 3000.0 * unit(rng) * unit(rng);
    OrientedBox box;
    box.centre = camera.position + camera.forward() * distance + camera.right() * (distance * (2.0 * unit(rng) - 1.0)) +
                 camera.up() * (distance * (unit(rng) - 0.5));
    box.axes = randomRotation(rng);
    box.halfExtents = {distance * unit(rng), distance * unit(rng), distance * 0.2 * unit(rng)};
    double expected = 0.0;
    if (!referenceArea(box, camera, expected)) continue;  // crosses the near plane: other tests
    ++checked;
    const double area = projectedAreaPx(box, camera);
    ASSERT_NEAR(area, expected, 1e-6 * expected) << "case " << checked;
    ASSERT_EQ(area, projectedAreaPx(box, makeAreaView(camera)));
  }
}

TEST(ProjectedArea, EveryOneOfThe26EyeRegionsMatchesTheHull) {
  OrientedBox box;
  box.centre = {100.0, -40.0, 30.0};
  box.axes = glm::mat3_cast(glm::angleAxis(0.7, glm::normalize(glm::dvec3(1.0, 2.0, 3.0))));
  box.halfExtents = {10.0, 6.0, 3.0};
  int regions = 0;
  for (int i = -1; i <= 1; ++i) {
    for (int j = -1; j <= 1; ++j) {
      for (int k = -1; k <= 1; ++k) {
        if (i == 0 && j == 0 && k == 0) continue;
        // An eye in region (i, j, k), off-centre so no face is seen exactly edge-on.
        const glm::dvec3 local = glm::dvec3(i * 25.0 + 1.3, j * 20.0 - 0.7, k * 15.0 + 0.4);
        Camera camera;
        camera.position = box.centre + box.axes * local;
        const glm::dvec3 look = glm::normalize(box.centre - camera.position);
        camera.yawDeg = glm::degrees(std::atan2(look.x, look.y));
        camera.pitchDeg = glm::degrees(std::asin(look.z));
        double expected = 0.0;
        ASSERT_TRUE(referenceArea(box, camera, expected));
        EXPECT_NEAR(projectedAreaPx(box, camera), expected, 1e-9 * expected) << i << " " << j << " " << k;
        ++regions;
      }
    }
  }
  EXPECT_EQ(regions, 26);
}

TEST(ProjectedArea, EyeInsideTheBoxCoversTheWholeScreen) {
  Camera camera;
  camera.position = {5.0, 5.0, 5.0};
  camera.widthPx = 640;
  camera.heightPx = 480;
  const OrientedBox box = orientedBoxFromAabb({0.0, 0.0, 0.0}, {100.0, 100.0, 10.0});
  EXPECT_EQ(projectedAreaPx(box, camera), 640.0 * 480.0);
  EXPECT_EQ(visibleAreaPx(box, camera), 640.0 * 480.0);
}

TEST(ProjectedArea, ShrinksMonotonicallyWithDistance) {
  std::mt19937_64 rng(7);
  for (int trial = 0; trial < 50; ++trial) {
    const Camera camera = randomCamera(rng);
    OrientedBox box;
    box.axes = randomRotation(rng);
    box.halfExtents = {20.0, 5.0, 12.0};
    double previous = std::numeric_limits<double>::infinity();
    for (double distance = 40.0 + camera.nearM; distance < 1e5; distance *= 1.1) {
      box.centre = camera.position + camera.forward() * distance + camera.right() * 15.0;
      const double area = projectedAreaPx(box, camera);
      ASSERT_GT(area, 0.0);
      ASSERT_LT(area, previous) << "distance " << distance;
      previous = area;
    }
  }
}

TEST(ProjectedArea, BoxCrossingTheNearPlaneIsClippedAsAWhole) {
  // Eye at the origin looking north (+y = depth), right = +x, up = +z, near plane at 1.
  // The box x in [1, 2], z in [-1, 1] reaches from depth -0.5 (behind the eye) to 3. Only
  // its x = 1 face is a front face, but after the clip at depth 1 the cut exposes the
  // rest: outline (1/3, -1/3) (1, -1) (2, -1) (2, 1) (1, 1) (1/3, 1/3), area 26/9 in units
  // of the image plane at distance 1. Its clipped front face alone would give 8/9.
  Camera camera;
  camera.widthPx = 800;
  camera.heightPx = 600;
  camera.nearM = 1.0;
  const OrientedBox box = orientedBoxFromAabb({1.0, -0.5, -1.0}, {2.0, 3.0, 1.0});
  const double k = camera.projectionConstant();
  EXPECT_NEAR(projectedAreaPx(box, camera), 26.0 / 9.0 * k * k, 1e-9 * k * k);
}

TEST(ProjectedArea, BoxWhollyBehindTheNearPlaneHasNoArea) {
  Camera camera;
  camera.nearM = 2.0;
  EXPECT_EQ(projectedAreaPx(orientedBoxFromAabb({-5.0, -30.0, -5.0}, {5.0, -10.0, 5.0}), camera), 0.0);
  EXPECT_EQ(projectedAreaPx(orientedBoxFromAabb({-5.0, 0.5, -5.0}, {5.0, 1.5, 5.0}), camera), 0.0);  // before near
  EXPECT_EQ(visibleAreaPx(orientedBoxFromAabb({-5.0, -30.0, -5.0}, {5.0, -10.0, 5.0}), camera), 0.0);
}

// Pixels whose centre ray meets the box at a depth of at least the near plane: what a
// rasterizer with near clipping covers.
double coveredPixels(const OrientedBox& box, const Camera& camera) {
  const glm::dvec3 origin = glm::transpose(box.axes) * (camera.position - box.centre);
  const glm::dvec3 forward = camera.forward();
  double count = 0.0;
  for (int py = 0; py < camera.heightPx; ++py) {
    for (int px = 0; px < camera.widthPx; ++px) {
      const glm::dvec3 ray = camera.pixelRay(px + 0.5, py + 0.5);
      const glm::dvec3 dir = glm::transpose(box.axes) * ray;
      double enter = -std::numeric_limits<double>::infinity(), leave = std::numeric_limits<double>::infinity();
      bool miss = false;
      for (int k = 0; k < 3 && !miss; ++k) {
        const double h = box.halfExtents[k];
        if (std::abs(dir[k]) < 1e-15) {
          miss = std::abs(origin[k]) > h;
          continue;
        }
        double t0 = (-h - origin[k]) / dir[k], t1 = (h - origin[k]) / dir[k];
        if (t0 > t1) std::swap(t0, t1);
        enter = std::max(enter, t0);
        leave = std::min(leave, t1);
      }
      if (!miss && enter <= leave && leave * glm::dot(ray, forward) >= camera.nearM) count += 1.0;
    }
  }
  return count;
}

TEST(ProjectedArea, VisibleAreaMatchesPixelCoverageAlsoAcrossTheNearPlane) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int crossing = 0, checked = 0;
  while (checked < 60) {
    Camera camera;
    camera.position = {10.0, 20.0, 30.0};
    camera.yawDeg = 360.0 * unit(rng);
    camera.pitchDeg = 120.0 * unit(rng) - 60.0;
    camera.fovYDeg = 40.0 + 50.0 * unit(rng);
    camera.widthPx = 400;
    camera.heightPx = 300;
    camera.nearM = 0.1 + 3.0 * unit(rng);
    OrientedBox box;
    box.centre = camera.position + camera.forward() * (60.0 * unit(rng) - 20.0) +
                 camera.right() * (60.0 * unit(rng) - 30.0) + camera.up() * (40.0 * unit(rng) - 20.0);
    box.axes = randomRotation(rng);
    box.halfExtents = {1.0 + 25.0 * unit(rng), 1.0 + 25.0 * unit(rng), 1.0 + 10.0 * unit(rng)};
    const glm::dvec3 eyeLocal = glm::transpose(box.axes) * (camera.position - box.centre);
    if (glm::all(glm::lessThanEqual(glm::abs(eyeLocal), box.halfExtents))) continue;  // eye inside: own test
    double unused = 0.0;
    if (!referenceArea(box, camera, unused)) ++crossing;
    ++checked;
    const double area = visibleAreaPx(box, camera);
    const double pixels = coveredPixels(box, camera);
    // Pixel centres miss or gain at most a half-pixel band along the outline, whose
    // perimeter inside the screen is at most the screen's.
    EXPECT_NEAR(area, pixels, double(camera.widthPx + camera.heightPx)) << "case " << checked;
    EXPECT_LE(area, double(camera.widthPx) * camera.heightPx + 1e-6);
  }
  EXPECT_GT(crossing, 10);  // the near-plane path was exercised
}

TEST(ProjectedArea, VisibleAreaEqualsProjectedAreaForBoxesOnScreen) {
  Camera camera;
  camera.position = {0.0, 0.0, 100.0};
  camera.pitchDeg = -30.0;
  const OrientedBox box = orientedBoxFromAabb({-20.0, 150.0, -5.0}, {20.0, 200.0, 15.0});
  const double projected = projectedAreaPx(box, camera);
  EXPECT_GT(projected, 100.0);
  EXPECT_NEAR(visibleAreaPx(box, camera), projected, 1e-9 * projected);
  // Pushed to the side until half of it leaves the screen, the visible part shrinks.
  OrientedBox aside = box;
  aside.centre += camera.right() * 240.0;
  EXPECT_LT(visibleAreaPx(aside, camera), 0.9 * projectedAreaPx(aside, camera));
}

TEST(ProjectedArea, AabbHelperGivesCentreAndHalfExtents) {
  const OrientedBox box = orientedBoxFromAabb({1.0, 2.0, 3.0}, {5.0, 4.0, 3.0});
  EXPECT_EQ(box.centre, glm::dvec3(3.0, 3.0, 3.0));
  EXPECT_EQ(box.halfExtents, glm::dvec3(2.0, 1.0, 0.0));
  EXPECT_EQ(box.axes, glm::dmat3(1.0));
}

}  // namespace
}  // namespace polder::lod
