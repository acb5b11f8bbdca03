#include <polder/terrain_engine.hpp>

#include <random>

#include <gtest/gtest.h>

#include <polder/query/query_scene.hpp>
#include <polder/query/screen_error.hpp>
#include <polder/terrain/dem_reader.hpp>
#include <polder/terrain/heightfield_crop.hpp>

#include "allocation_counter.hpp"
#include "generated_terrain.hpp"
#include "test_support.hpp"

namespace polder {
namespace {

Camera randomCamera(std::mt19937& random, const terrain::Heightfield& field) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Camera camera;
  camera.widthPx = 320;
  camera.heightPx = 240;
  camera.fovYDeg = 30.0 + 60.0 * unit(random);
  camera.position = {field.extentX() * (1.4 * unit(random) - 0.2), field.extentY() * (1.4 * unit(random) - 0.2),
                     2600.0 + 3000.0 * unit(random)};
  camera.yawDeg = 360.0 * unit(random);
  camera.pitchDeg = -80.0 * unit(random) - 5.0;
  camera.nearM = 1.0;
  camera.farM = 1e6;
  return camera;
}

TEST(TerrainEngine, EveryFrameIsWatertightOverRandomViews) {
  auto field = test::sharedGeneratedTerrain(300, 5);  // 300 samples: blocks clip at the east and north edges
  for (int k : {4, 5}) {
    TerrainEngineOptions options;
    options.blockK = k;
    options.tauPx = 2.0;
    auto engine = TerrainEngine::create(field, options);
    ASSERT_TRUE(engine.ok()) << engine.error().message;
    std::mt19937 random(k);
    for (int view = 0; view < 40; ++view) {
      const TerrainFrame& frame = (*engine)->update(randomCamera(random, *field));
      const terrain::WatertightReport report = (*engine)->checkWatertight();
      ASSERT_TRUE(report.watertight()) << "k " << k << " view " << view << ": " << report.openEdges << " open edges, "
                                       << report.tJunctions << " T-junctions, " << report.samplesUncovered
                                       << " uncovered, " << report.samplesOverlapped << " overlapped";
      EXPECT_EQ(frame.stats.visibleBlocks, frame.blocks.size());
    }
  }
}

TEST(TerrainEngine, BudgetModeEndsEachFrameBetweenNinetyPercentAndTheBudget) {
  auto field = test::sharedGeneratedTerrain(257, 9);
  TerrainEngineOptions options;
  options.mode = LodMode::TriangleBudget;
  options.budgetTriangles = 20000;
  options.loading = BlockLoading::Immediate;
  auto engine = TerrainEngine::create(field, options);
  ASSERT_TRUE(engine.ok());
  std::mt19937 random(3);
  for (int view = 0; view < 30; ++view) {
    Camera camera = randomCamera(random, *field);
    camera.position = {field->extentX() * 0.5, field->extentY() * 0.5, 3000.0};  // terrain fills the view
    const TerrainFrame& frame = (*engine)->update(camera);
    const std::size_t total = frame.stats.triangles();
    if (frame.stats.visibleBlocks == 0) continue;
    EXPECT_LE(total, options.budgetTriangles) << "view " << view;
    // 0.9 P is reachable unless the visible blocks at full detail hold less than that.
    std::size_t fullDetail = frame.stats.dikeTriangles;
    for (const auto& block : frame.blocks) fullDetail += std::size_t(2 * block.mesh->cellsX * block.mesh->cellsY);
    if (fullDetail >= options.budgetTriangles) {
      EXPECT_GE(total, options.budgetTriangles * 9 / 10) << "view " << view;
    }
    EXPECT_TRUE((*engine)->checkWatertight().watertight());
  }
}

// Flies `views` short hops (the cache reuses meshes between them) and measures each last
// frame, blocks and dikes together, with Embree pixel rays against the true surface: the
// largest error in pixels over all views.
double worstMeasuredError(const std::shared_ptr<terrain::Heightfield>& field, double tauPx, int views,
                          std::uint32_t seed, double altitudeM, std::size_t& pixelsMeasured,
                          std::size_t& dikeTriangles) {
  auto truth = query::QueryScene::create(*field);
  EXPECT_TRUE(truth.ok());
  if (!truth.ok()) return 1e9;
  TerrainEngineOptions options;
  options.tauPx = tauPx;
  auto engine = TerrainEngine::create(field, options);
  EXPECT_TRUE(engine.ok());
  if (!engine.ok()) return 1e9;
  std::mt19937 random(seed);
  double worst = 0.0;
  float top = field->heights.front();
  for (const float h : field->heights) top = std::max(top, h);
  for (int view = 0; view < views; ++view) {
    Camera camera = randomCamera(random, *field);
    camera.position.z = double(top) + altitudeM * (0.3 + 0.5 * (view % 4));  // low over the hills to high above
    camera.pitchDeg = -15.0 - 6.0 * (view % 5);
    for (int step = 0; step < 3; ++step) {
      camera.position.x += 40.0;
      (void)(*engine)->update(camera);
    }
    dikeTriangles += (*engine)->updateSettled(camera).stats.dikeTriangles;
    auto lod = query::QueryScene::createFromMeshes((*engine)->frameMeshes());
    EXPECT_TRUE(lod.ok());
    if (!lod.ok()) return 1e9;
    const query::ScreenError error = query::measureScreenError(**lod, **truth, camera);
    worst = std::max(worst, error.maxPx);
    pixelsMeasured += error.pixelsMeasured;
  }
  return worst;
}

// Whole frames, block and dike triangles, reused or rebuilt, hold the measured screen-space
// error within tau: the blocks by their extraction, the dikes by the frame's dike check.
TEST(TerrainEngine, FramesStayWithinTauOnScreenOverAGeneratedDem) {
  auto field = test::sharedGeneratedTerrain(257, 13);
  std::size_t pixels = 0, dikes = 0;
  const double worst = worstMeasuredError(field, 1.0, 16, 21, 800.0, pixels, dikes);
  EXPECT_GT(pixels, 100000u);
  EXPECT_GT(dikes, 0u);
  EXPECT_LE(worst, 1.0 + 1e-6);
}

TEST(TerrainEngine, FramesStayWithinTauOnScreenOverARealDem) {
  POLDER_REQUIRE_SHARED_FILE(path, "dems/mt_rainier_90m_srtm3.tif");
  auto dem = terrain::readDem(path);
  ASSERT_TRUE(dem.ok()) << dem.error().message;
  auto crop = terrain::cropCentre(dem->field, 400, 400);  // the summit and its glaciers
  ASSERT_TRUE(crop.ok());
  auto field = std::make_shared<terrain::Heightfield>(std::move(*crop));
  std::size_t pixels = 0, dikes = 0;
  for (const double tau : {1.0, 2.0}) {
    const double worst = worstMeasuredError(field, tau, 12, 5, 1000.0, pixels, dikes);
    EXPECT_LE(worst, tau + 1e-6) << "tau " << tau;
  }
  EXPECT_GT(pixels, 100000u);
  EXPECT_GT(dikes, 0u);
}

TEST(TerrainEngine, SteadyStateFramesDoNotAllocate) {
  auto field = test::sharedGeneratedTerrain(257, 2);
  auto engine = TerrainEngine::create(field, {});
  ASSERT_TRUE(engine.ok());
  Camera camera;
  camera.widthPx = 320;
  camera.heightPx = 240;
  camera.position = {2000.0, -500.0, 2500.0};
  camera.yawDeg = 20.0;
  camera.pitchDeg = -30.0;
  (void)(*engine)->updateSettled(camera);
  for (int warm = 0; warm < 3; ++warm) (void)(*engine)->update(camera), (void)(*engine)->frameMeshes();
  const std::size_t before = test::allocationCount();
  for (int frame = 0; frame < 20; ++frame) {
    (void)(*engine)->update(camera);
    (void)(*engine)->frameMeshes();  // world meshes for measurement, too
  }
  EXPECT_EQ(test::allocationCount() - before, 0u);
  EXPECT_GT((*engine)->update(camera).stats.cacheHits, 0u);
}

}  // namespace
}  // namespace polder
