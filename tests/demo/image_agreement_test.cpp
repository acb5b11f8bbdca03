// The OpenGL renderer and the Embree ray caster draw the same picture of the same view:
// the terrain/sky masks differ in under 0.5% of the pixels, and the colours agree.
#include <cmath>
#include <cstdlib>

#include <gtest/gtest.h>

#include <polder/platform/osmesa_context.hpp>
#include <polder/query/query_scene.hpp>
#include <polder/query/reference_renderer.hpp>
#include <polder/render/renderer.hpp>
#include <polder/terrain/full_resolution_mesh.hpp>
#include <polder/terrain/generator.hpp>

namespace polder {
namespace {

struct Comparison {
  double maskMismatch = 0.0;     // share of pixels terrain in one image and sky in the other
  double meanColourDelta = 0.0;  // mean |difference| over RGB of pixels terrain in both, 0..255
};

Comparison compare(const RgbaImage& a, const RgbaImage& b) {
  Comparison result;
  std::size_t mismatched = 0, both = 0;
  double delta = 0.0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      const bool terrainA = a.at(x, y)[3] > 127, terrainB = b.at(x, y)[3] > 127;
      if (terrainA != terrainB) ++mismatched;
      if (terrainA && terrainB) {
        ++both;
        for (int c = 0; c < 3; ++c) delta += std::abs(int(a.at(x, y)[c]) - int(b.at(x, y)[c]));
      }
    }
  result.maskMismatch = double(mismatched) / double(a.width * a.height);
  result.meanColourDelta = both ? delta / double(3 * both) : 0.0;
  return result;
}

class ImageAgreement : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    terrain::GeneratorOptions options;
    options.size = 257;
    options.spacingM = 40.0;
    options.seed = 11;
    auto field = terrain::generateTerrain(options);
    ASSERT_TRUE(field.ok()) << field.error().message;
    s_field = new terrain::Heightfield(std::move(*field));
  }
  static void TearDownTestSuite() {
    delete s_field;
    s_field = nullptr;
  }
  static inline terrain::Heightfield* s_field = nullptr;
};

TEST_F(ImageAgreement, OpenGlAndRayCastMasksAgreeOnSeveralViews) {
  const terrain::Heightfield& field = *s_field;
  auto context = platform::OsmesaContext::create(320, 240);
  ASSERT_TRUE(context.ok()) << context.error().message;
  auto renderer = render::Renderer::create(&platform::OsmesaContext::getProcAddress);
  ASSERT_TRUE(renderer.ok()) << renderer.error().message;
  std::vector<render::MeshHandle> meshes;
  for (const auto& chunk : terrain::buildFullResolutionMeshes(field)) {
    auto handle = (*renderer)->upload(chunk);
    ASSERT_TRUE(handle.ok()) << handle.error().message;
    meshes.push_back(*handle);
  }
  auto scene = query::QueryScene::create(field);
  ASSERT_TRUE(scene.ok()) << scene.error().message;

  float low = field.heights[0], high = low;
  for (float h : field.heights) low = std::min(low, h), high = std::max(high, h);
  TerrainStyle style;
  style.minHeightM = low;
  style.maxHeightM = high;
  style.fogDensity = fogDensityForDistance(float(field.extentX()));

  struct View {
    glm::dvec3 position;
    double yaw, pitch;
  };
  const double cx = 0.5 * field.extentX(), cy = 0.5 * field.extentY();
  const std::vector<View> views = {
      {{cx, -2000.0, high + 800.0}, 0.0, -12.0},       // from the south, horizon in view
      {{cx, cy, high + 3000.0}, 30.0, -70.0},          // steeply down
      {{-1500.0, -1500.0, high + 400.0}, 45.0, -8.0},  // grazing, from the south-west corner
      {{cx, cy, double(high) + 150.0}, 200.0, -20.0},  // low, inside the terrain
  };
  for (const View& view : views) {
    Camera camera;
    camera.widthPx = 320;
    camera.heightPx = 240;
    camera.fovYDeg = 55.0;
    camera.position = view.position;
    camera.yawDeg = view.yaw;
    camera.pitchDeg = view.pitch;
    camera.nearM = 1.0;
    camera.farM = 1e5;

    (*renderer)->beginFrame(camera, style);
    for (auto mesh : meshes) (*renderer)->draw(mesh);
    ASSERT_TRUE((*renderer)->endFrame().ok());
    RgbaImage raster;
    ASSERT_TRUE((*renderer)->readPixels(raster).ok());
    const RgbaImage reference = query::renderReference(**scene, field, camera, style);

    const Comparison result = compare(raster, reference);
    EXPECT_LT(result.maskMismatch, 0.005) << "view yaw " << view.yaw << " pitch " << view.pitch;
    EXPECT_LT(result.meanColourDelta, 4.0) << "view yaw " << view.yaw << " pitch " << view.pitch;
    // The view must actually show terrain and (for the first) sky, or the test proves nothing.
    std::size_t terrainPixels = 0;
    for (int y = 0; y < raster.height; ++y)
      for (int x = 0; x < raster.width; ++x) terrainPixels += raster.at(x, y)[3] > 127;
    EXPECT_GT(terrainPixels, std::size_t(raster.width * raster.height / 10));
  }
}

}  // namespace
}  // namespace polder
