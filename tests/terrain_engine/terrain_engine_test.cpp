#include <polder/terrain_engine.hpp>

#include <atomic>
#include <cstdlib>
#include <new>
#include <random>

#include <gtest/gtest.h>

#include <polder/query/query_scene.hpp>
#include <polder/query/screen_error.hpp>
#include <polder/terrain/generator.hpp>

// Counts heap allocations, to prove the steady-state frame allocates nothing.
namespace {
std::atomic<std::size_t> g_allocations{0};
}
void* operator new(std::size_t size) {
  ++g_allocations;
  if (void* p = std::malloc(size ? size : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace polder {
namespace {

std::shared_ptr<terrain::Heightfield> generated(int size, std::uint64_t seed) {
  terrain::GeneratorOptions options;
  options.size = size;
  options.seed = seed;
  options.spacingM = 30.0;
  auto field = terrain::generateTerrain(options);
  EXPECT_TRUE(field.ok());
  return std::make_shared<terrain::Heightfield>(std::move(*field));
}

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
  auto field = generated(300, 5);  // 300 samples: blocks clip at the east and north edges
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
  auto field = generated(257, 9);
  TerrainEngineOptions options;
  options.mode = LodMode::TriangleBudget;
  options.budgetTriangles = 20000;
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

// The blocks' meshes, reused or rebuilt, hold the measured screen-space error within tau.
// (Dike triangles are left out: their error is not yet bounded by tau.)
TEST(TerrainEngine, BlockMeshesStayWithinTauOnScreen) {
  auto field = generated(257, 13);
  auto truth = query::QueryScene::create(*field);
  ASSERT_TRUE(truth.ok());
  TerrainEngineOptions options;
  options.tauPx = 1.0;
  auto engine = TerrainEngine::create(field, options);
  ASSERT_TRUE(engine.ok());
  std::mt19937 random(21);
  double worst = 0.0;
  std::size_t measured = 0;
  for (int view = 0; view < 12; ++view) {
    Camera camera = randomCamera(random, *field);
    camera.position.z = 900.0 + 1500.0 * (view % 4);  // from low over the hills to high above
    camera.pitchDeg = -20.0 - 5.0 * (view % 5);
    for (int step = 0; step < 3; ++step) {  // small moves: the cache reuses meshes
      camera.position.x += 40.0;
      (void)(*engine)->update(camera);
    }
    const TerrainFrameMeshes meshes = (*engine)->frameMeshes();
    const std::vector<MeshData> blocks(meshes.blocks.begin(), meshes.blocks.end());
    auto lod = query::QueryScene::createFromMeshes(blocks);
    ASSERT_TRUE(lod.ok());
    const query::ScreenError error = query::measureScreenError(**lod, **truth, camera);
    worst = std::max(worst, error.maxPx);
    measured += error.pixelsMeasured;
  }
  EXPECT_GT(measured, 100000u);
  EXPECT_LE(worst, options.tauPx * (1.0 + 1e-6));
}

TEST(TerrainEngine, SteadyStateFramesDoNotAllocate) {
  auto field = generated(257, 2);
  auto engine = TerrainEngine::create(field, {});
  ASSERT_TRUE(engine.ok());
  Camera camera;
  camera.widthPx = 320;
  camera.heightPx = 240;
  camera.position = {2000.0, -500.0, 2500.0};
  camera.yawDeg = 20.0;
  camera.pitchDeg = -30.0;
  for (int warm = 0; warm < 3; ++warm) (void)(*engine)->update(camera), (void)(*engine)->frameMeshes();
  const std::size_t before = g_allocations.load();
  for (int frame = 0; frame < 20; ++frame) {
    (void)(*engine)->update(camera);
    (void)(*engine)->frameMeshes();  // the meshes a renderer would draw, too
  }
  EXPECT_EQ(g_allocations.load() - before, 0u);
  EXPECT_GT((*engine)->update(camera).stats.cacheHits, 0u);
}

}  // namespace
}  // namespace polder
