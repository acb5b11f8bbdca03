// The ray-cast reference renderer: terrain pixels carry shadeTerrain's colours, sky is
// transparent, near/far planes clip like GL, threads do not change the picture.
#include <polder/query/reference_renderer.hpp>

#include <cmath>
#include <cstdlib>

#include <gtest/gtest.h>

#include <polder/terrain/normals.hpp>

#include "query_test_fields.hpp"

namespace polder::query {
namespace {

std::uint8_t byteOf(float value) { return std::uint8_t(std::lround(std::clamp(value, 0.0f, 1.0f) * 255.0f)); }

void expectPixel(const RgbaImage& image, int x, int y, const glm::vec3& colour, std::uint8_t alpha) {
  const std::uint8_t* pixel = image.at(x, y);
  EXPECT_LE(std::abs(int(pixel[0]) - int(byteOf(colour.r))), 1) << x << "," << y;
  EXPECT_LE(std::abs(int(pixel[1]) - int(byteOf(colour.g))), 1) << x << "," << y;
  EXPECT_LE(std::abs(int(pixel[2]) - int(byteOf(colour.b))), 1) << x << "," << y;
  EXPECT_EQ(pixel[3], alpha) << x << "," << y;
}

struct PlaneSetup {
  terrain::Heightfield field = test::makeField(65, 65, 10.0, 10.0, [](double, double) { return 100.0; });
  std::unique_ptr<QueryScene> scene = std::move(QueryScene::create(field)).value();
  TerrainStyle style;
  Camera camera;
  PlaneSetup() {
    style.minHeightM = 0.0f;
    style.maxHeightM = 400.0f;
    style.fogDensity = fogDensityForDistance(500.0f);
    camera.widthPx = 64;
    camera.heightPx = 48;
  }
};

TEST(ReferenceRenderer, LookingDownAtAPlaneIsAllTerrain) {
  PlaneSetup setup;
  setup.camera.position = glm::dvec3(320.0, 320.0, 400.0);
  setup.camera.yawDeg = 30.0;
  setup.camera.pitchDeg = -90.0;
  const RgbaImage image = renderReference(*setup.scene, setup.field, setup.camera, setup.style, 2);
  ASSERT_EQ(image.width, 64);
  ASSERT_EQ(image.height, 48);
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const glm::dvec3 ray = setup.camera.pixelRay(x + 0.5, y + 0.5);
      const float distance = float(300.0 / -ray.z);
      expectPixel(image, x, y, shadeTerrain(setup.style, glm::vec3(0.0f, 0.0f, 1.0f), 100.0f, distance), 255);
    }
  }
}

TEST(ReferenceRenderer, HorizonPutsSkyAboveTerrain) {
  PlaneSetup setup;
  setup.camera.position = glm::dvec3(320.0, 20.0, 150.0);
  setup.camera.yawDeg = 0.0;
  setup.camera.pitchDeg = 0.0;
  const RgbaImage image = renderReference(*setup.scene, setup.field, setup.camera, setup.style, 3);
  for (int x = 0; x < image.width; ++x) {
    for (int y = 0; y < image.height / 2; ++y) expectPixel(image, x, y, setup.style.skyColour, 0);
    // Looking down 29 degrees, the bottom row meets the plane 90 m ahead.
    EXPECT_EQ(image.at(x, image.height - 1)[3], 255);
    // Down each column: sky, then terrain to the bottom (the plane ends 620 m ahead).
    bool terrain = false;
    for (int y = 0; y < image.height; ++y) {
      if (image.at(x, y)[3] == 255) terrain = true;
      EXPECT_EQ(image.at(x, y)[3], terrain ? 255 : 0) << x << "," << y;
    }
  }
}

TEST(ReferenceRenderer, NearAndFarPlanesClipLikeGl) {
  PlaneSetup setup;
  setup.camera.position = glm::dvec3(320.0, 320.0, 400.0);
  setup.camera.pitchDeg = -90.0;
  setup.camera.farM = 299.0;  // the plane is 300 m below
  RgbaImage image = renderReference(*setup.scene, setup.field, setup.camera, setup.style);
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) ASSERT_EQ(image.at(x, y)[3], 0);
  }
  setup.camera.farM = 1000.0;
  setup.camera.nearM = 301.0;
  image = renderReference(*setup.scene, setup.field, setup.camera, setup.style);
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) ASSERT_EQ(image.at(x, y)[3], 0);
  }
  // Eye depth, not ray length: with far at 301 m every pixel still sees the plane,
  // although corner rays travel about 350 m to it.
  setup.camera.nearM = 1.0;
  setup.camera.farM = 301.0;
  image = renderReference(*setup.scene, setup.field, setup.camera, setup.style);
  EXPECT_EQ(image.at(0, 0)[3], 255);
  EXPECT_EQ(image.at(63, 47)[3], 255);
}

TEST(ReferenceRenderer, InterpolatesSampleNormalsAndIgnoresThreadCount) {
  const auto field = test::makeField(41, 41, 5.0, 5.0, test::sinusoid);
  auto scene = QueryScene::create(field);
  ASSERT_TRUE(scene.ok());
  TerrainStyle style;
  style.minHeightM = -20.0f;
  style.maxHeightM = 25.0f;
  Camera camera;
  camera.position = glm::dvec3(100.0, 40.0, 80.0);
  camera.yawDeg = 10.0;
  camera.pitchDeg = -35.0;
  camera.widthPx = 40;
  camera.heightPx = 30;
  const RgbaImage one = renderReference(**scene, field, camera, style, 1);
  const RgbaImage three = renderReference(**scene, field, camera, style, 3);
  EXPECT_EQ(one.pixels, three.pixels);

  // Recompute a few pixels by hand: hit, triangle, barycentric vertex normals.
  for (const glm::ivec2 px : {glm::ivec2(20, 15), glm::ivec2(3, 27), glm::ivec2(33, 20)}) {
    const auto hit = (*scene)->raycast(camera.position, camera.pixelRay(px.x + 0.5, px.y + 0.5));
    ASSERT_TRUE(hit);
    const double sx = hit->point.x / field.spacingX, sy = hit->point.y / field.spacingY;
    const int cx = int(sx), cy = int(sy);
    const double a = sx - cx, b = sy - cy;
    const auto n = [&](int dx, int dy) { return glm::dvec3(terrain::sampleNormal(field, cx + dx, cy + dy)); };
    const glm::dvec3 normal = a + b <= 1.0 ? (1.0 - a - b) * n(0, 0) + a * n(1, 0) + b * n(0, 1)
                                           : (a + b - 1.0) * n(1, 1) + (1.0 - a) * n(0, 1) + (1.0 - b) * n(1, 0);
    expectPixel(one, px.x, px.y, shadeTerrain(style, glm::vec3(normal), float(hit->point.z), float(hit->distance)),
                255);
  }
}

}  // namespace
}  // namespace polder::query
