// TerrainDrawer under OSMesa: one GPU mesh per piece, uploads of exactly the created and
// changed pieces, nothing uploaded while the camera holds still, and flights over generated
// and real DEMs whose frames have no background pixel enclosed by terrain.
#include <polder/terrain_drawer.hpp>

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include <polder/camera_path.hpp>
#include <polder/enclosed_background.hpp>
#include <polder/platform/osmesa_context.hpp>
#include <polder/query/frame_cracks.hpp>
#include <polder/terrain/dem_reader.hpp>
#include <polder/terrain/generator.hpp>
#include <polder/terrain/heightfield_crop.hpp>
#include <polder/terrain_engine.hpp>

#include "test_support.hpp"

// Sanitizer builds: OSMesa keeps a record per buffer made current for the whole process.
extern "C" const char* __lsan_default_suppressions() { return "leak:libOSMesa.so\n"; }

namespace polder {
namespace {

std::shared_ptr<const terrain::Heightfield> generated(int size, std::uint64_t seed, double spacingM) {
  terrain::GeneratorOptions options;
  options.size = size;
  options.seed = seed;
  options.spacingM = spacingM;
  auto field = terrain::generateTerrain(options);
  EXPECT_TRUE(field.ok());
  return std::make_shared<const terrain::Heightfield>(std::move(*field));
}

class TerrainDrawerTest : public ::testing::Test {
 protected:
  void open(int width, int height) {
    auto context = platform::OsmesaContext::create(width, height);
    ASSERT_TRUE(context.ok()) << context.error().message;
    m_context = std::move(*context);
    auto renderer = render::Renderer::create(&platform::OsmesaContext::getProcAddress);
    ASSERT_TRUE(renderer.ok()) << renderer.error().message;
    m_renderer = std::move(*renderer);
  }

  // Flies the built-in loop over `field` and returns the cracks summed over the frames
  // (query/frame_cracks.hpp); `terrainShare` gets the smallest share of terrain pixels in a
  // frame, and `enclosedBackground` all enclosed background pixels, silhouette notches too.
  std::size_t flyAndCountCracks(const std::shared_ptr<const terrain::Heightfield>& field, double altitudeM, int frames,
                                double& terrainShare, std::size_t& enclosedBackground) {
    open(640, 360);
    auto engine = TerrainEngine::create(field, {});
    EXPECT_TRUE(engine.ok());
    if (!engine.ok()) return ~std::size_t(0);
    FlyoverOptions flight;
    flight.altitudeM = altitudeM;
    flight.speedMps = 0.02 * std::hypot(field->extentX(), field->extentY());
    auto ground = [&](double x, double y) {
      const int i = std::clamp(int(x / field->spacingX), 0, field->width - 1);
      const int j = std::clamp(int(y / field->spacingY), 0, field->height - 1);
      return double(field->at(i, j));
    };
    const CameraPath path = makeFlyoverLoop(field->extentX(), field->extentY(), ground, flight).value();
    const TerrainStyle style = defaultTerrainStyle(*field);
    TerrainDrawer drawer(*m_renderer);
    std::size_t cracks = 0;
    enclosedBackground = 0;
    terrainShare = 1.0;
    RgbaImage image;
    for (int frame = 0; frame < frames; ++frame) {
      Camera camera;
      camera.widthPx = 640;
      camera.heightPx = 360;
      camera = path.at(frame * path.durationS() / frames).placed(camera);
      camera.farM = 4.0 * std::hypot(field->extentX(), field->extentY());
      camera.nearM = std::max(0.1, camera.farM * 2e-6);
      const TerrainFrame& terrain = (*engine)->update(camera);
      EXPECT_TRUE(drawer.sync(terrain).ok());
      m_renderer->beginFrame(camera, style);
      drawer.draw(terrain);
      EXPECT_TRUE(m_renderer->endFrame().ok());
      EXPECT_TRUE(m_renderer->readPixels(image).ok());
      auto frameMesh = query::QueryScene::createFromMeshes((*engine)->frameMeshes());
      EXPECT_TRUE(frameMesh.ok());
      if (!frameMesh.ok()) return ~std::size_t(0);
      const query::FrameCracks found = query::findFrameCracks(image, **frameMesh, camera);
      cracks += found.cracks;
      enclosedBackground += found.enclosedBackground;
      std::size_t terrainPixels = 0;
      for (std::size_t i = 3; i < image.pixels.size(); i += 4) terrainPixels += image.pixels[i] != 0;
      terrainShare = std::min(terrainShare, double(terrainPixels) / double(image.width * image.height));
    }
    return cracks;
  }

  // Declared first so it is destroyed last: the renderer needs its context current to die.
  std::unique_ptr<platform::OsmesaContext> m_context;
  std::unique_ptr<render::Renderer> m_renderer;
};

TEST(EnclosedBackground, CountsGapsBetweenTerrainPixelsOnly) {
  RgbaImage image(5, 5);
  for (int y = 2; y < 5; ++y)
    for (int x = 0; x < 5; ++x) image.at(x, y)[3] = 255;  // terrain below the horizon
  EXPECT_EQ(countEnclosedBackground(image), 0u) << "sky above terrain is no gap";
  image.at(2, 3)[3] = 0;  // a hole inside the terrain
  image.at(3, 2)[3] = 0;  // a notch in the horizon: terrain left and right
  EXPECT_EQ(countEnclosedBackground(image), 2u);
}

TEST_F(TerrainDrawerTest, UploadsExactlyTheCreatedAndChangedPiecesAndNothingWhileStill) {
  open(320, 240);
  auto field = generated(300, 3, 30.0);
  auto engine = TerrainEngine::create(field, {});
  ASSERT_TRUE(engine.ok());
  TerrainDrawer drawer(*m_renderer);
  Camera camera;
  camera.widthPx = 320;
  camera.heightPx = 240;
  camera.pitchDeg = -30.0;
  for (int frame = 0; frame < 90; ++frame) {
    const bool still = frame >= 60;
    camera.position = {200.0 + 60.0 * std::min(frame, 60), 500.0 + 20.0 * std::min(frame, 60), 2500.0};
    camera.yawDeg = 30.0 + 0.5 * std::min(frame, 60);
    const TerrainFrame& terrain = (*engine)->update(camera);
    std::size_t expected = 0;
    for (const auto list : {terrain.created, terrain.changed})
      for (const std::uint32_t i : list)
        expected += terrain.pieces[i].mesh.vertices.size_bytes() + terrain.pieces[i].mesh.indices.size_bytes();
    const std::uint64_t before = m_renderer->stats().uploadedBytes;
    ASSERT_TRUE(drawer.sync(terrain).ok());
    EXPECT_EQ(drawer.stats().uploadedBytes, expected) << "frame " << frame;
    EXPECT_EQ(m_renderer->stats().uploadedBytes - before, expected) << "frame " << frame;
    EXPECT_EQ(drawer.stats().piecesUploaded, terrain.created.size() + terrain.changed.size());
    EXPECT_EQ(m_renderer->stats().meshCount, terrain.pieces.size()) << "one GPU mesh per piece, retired ones freed";
    if (still && frame > 62) {
      EXPECT_EQ(drawer.stats().uploadedBytes, 0u) << "frame " << frame;
    }
    m_renderer->beginFrame(camera, defaultTerrainStyle(*field));
    drawer.draw(terrain);
    ASSERT_TRUE(m_renderer->endFrame().ok());
    EXPECT_EQ(m_renderer->stats().drawCalls, terrain.pieces.size());
  }
  drawer.clear();
  EXPECT_EQ(m_renderer->stats().meshCount, 0u);
}

TEST_F(TerrainDrawerTest, ASkippedFrameIsCaughtUpByVersions) {
  open(320, 240);
  auto field = generated(257, 5, 30.0);
  auto engine = TerrainEngine::create(field, {});
  ASSERT_TRUE(engine.ok());
  TerrainDrawer drawer(*m_renderer);
  Camera camera;
  camera.widthPx = 320;
  camera.heightPx = 240;
  camera.pitchDeg = -40.0;
  camera.position = {1000.0, 1000.0, 3000.0};
  ASSERT_TRUE(drawer.sync((*engine)->update(camera)).ok());
  camera.position = {6000.0, 6000.0, 1500.0};  // far: most pieces retire and new ones come
  (void)(*engine)->update(camera);             // not synced
  camera.position.x += 100.0;
  const TerrainFrame& terrain = (*engine)->update(camera);
  ASSERT_TRUE(drawer.sync(terrain).ok());
  EXPECT_EQ(m_renderer->stats().meshCount, terrain.pieces.size());
  EXPECT_EQ(drawer.stats().residentPieces, terrain.pieces.size());
}

TEST_F(TerrainDrawerTest, FlightsOverAGeneratedDemShowNoCracks) {
  double terrainShare = 0.0;
  std::size_t enclosed = 0;
  EXPECT_EQ(flyAndCountCracks(generated(769, 11, 40.0), 300.0, 48, terrainShare, enclosed), 0u);
  EXPECT_GT(terrainShare, 0.3);
  // The flight sees silhouettes against the sky, so the crack test had notches to tell apart.
  EXPECT_GT(enclosed, 0u);
}

TEST_F(TerrainDrawerTest, FlightsOverMountRainierShowNoCracks) {
  POLDER_REQUIRE_SHARED_FILE(path, "dems/mt_rainier_90m_srtm3.tif");
  auto dem = terrain::readDem(path);
  ASSERT_TRUE(dem.ok()) << dem.error().message;
  auto field = std::make_shared<const terrain::Heightfield>(std::move(dem->field));
  double terrainShare = 0.0;
  std::size_t enclosed = 0;
  EXPECT_EQ(flyAndCountCracks(field, 500.0, 48, terrainShare, enclosed), 0u);
  EXPECT_GT(terrainShare, 0.3);
}

}  // namespace
}  // namespace polder
