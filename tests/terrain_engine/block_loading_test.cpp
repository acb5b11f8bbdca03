// Background loading: blocks' error hierarchies are built by the engine's workers, and until
// a block's is resident the frame draws its resident ancestor, watertight and without a hole.
#include <polder/terrain_engine.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "generated_terrain.hpp"

namespace polder {
namespace {

// Rough hills without erosion: cheap to make at sizes where a few MB of budget bind.
std::shared_ptr<terrain::Heightfield> hills(int size) {
  auto field = std::make_shared<terrain::Heightfield>(size, size, 30.0, 30.0);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x)
      field->at(x, y) = float(400.0 * std::sin(x * 0.013) * std::cos(y * 0.011) + 25.0 * std::sin(x * 0.31 + y * 0.17) +
                              8.0 * std::sin(x * 1.7) * std::sin(y * 1.3));
  return field;
}

Camera lowCamera(const terrain::Heightfield& field, double x) {
  Camera camera;
  camera.widthPx = 320;
  camera.heightPx = 240;
  camera.position = {x, field.extentY() * 0.2, 1800.0};
  camera.yawDeg = 30.0;
  camera.pitchDeg = -20.0;
  camera.nearM = 1.0;
  camera.farM = 1e6;
  return camera;
}

void expectCoveredAndWatertight(const TerrainEngine& engine, const std::string& when) {
  const terrain::WatertightReport report = engine.checkWatertight();
  EXPECT_TRUE(report.watertight()) << when << ": " << report.openEdges << " open edges, " << report.tJunctions
                                   << " T-junctions, " << report.samplesUncovered << " uncovered, "
                                   << report.samplesOverlapped << " overlapped";
}

TEST(BlockLoading, TheFirstFrameFallsBackToTheRootAndLaterFramesReachTheSelectedLevel) {
  auto field = test::sharedGeneratedTerrain(513, 4);
  auto engine = TerrainEngine::create(field, {});
  ASSERT_TRUE(engine.ok()) << engine.error().message;
  const Camera camera = lowCamera(*field, field->extentX() * 0.4);

  // Nothing but the root is resident yet: the frame draws it, asks for the rest, and still
  // covers the whole DEM without a crack.
  const TerrainFrame& first = (*engine)->update(camera);
  EXPECT_EQ(first.stats.visibleBlocks, 1u);
  EXPECT_EQ(first.stats.blocksOnAncestor, 1u);
  EXPECT_GT(first.stats.loadsRequested, 0u);
  expectCoveredAndWatertight(**engine, "first frame");

  // Once the loads are in, no visible block is on an ancestor and the cut is finer.
  const TerrainFrame& settled = (*engine)->updateSettled(camera);
  EXPECT_EQ(settled.stats.blocksOnAncestor, 0u);
  EXPECT_GT(settled.stats.visibleBlocks, 8u);
  expectCoveredAndWatertight(**engine, "settled frame");
  const TerrainLoadStats& loads = (*engine)->loadStats();
  EXPECT_GT(loads.loads, 0u);
  EXPECT_EQ(loads.failures, 0u);
  EXPECT_EQ(loads.loadMs.size(), loads.loads);
}

// Settled frames draw the blocks Immediate loading draws. (Their meshes may differ: the LOD
// cache reuses what the frames before settling built, within tau.)
TEST(BlockLoading, SettledFramesSelectWhatImmediateLoadingSelects) {
  auto field = test::sharedGeneratedTerrain(257, 8);
  TerrainEngineOptions immediateOptions;
  immediateOptions.loading = BlockLoading::Immediate;
  auto background = TerrainEngine::create(field, {});
  auto immediate = TerrainEngine::create(field, immediateOptions);
  ASSERT_TRUE(background.ok() && immediate.ok());
  for (double x : {800.0, 2600.0, 5400.0}) {
    const Camera camera = lowCamera(*field, x);
    const TerrainFrame& a = (*background)->updateSettled(camera);
    const TerrainFrame& b = (*immediate)->update(camera);
    ASSERT_EQ(a.blocks.size(), b.blocks.size()) << "x " << x;
    for (std::size_t i = 0; i < a.blocks.size(); ++i) EXPECT_EQ(a.blocks[i].node, b.blocks[i].node) << "x " << x;
    expectCoveredAndWatertight(**background, "x " + std::to_string(x));
  }
}

// 1 MB of block hierarchies: far below what the views of a 513^2 DEM want.
TerrainEngineOptions withTightLodBudget() {
  TerrainEngineOptions options;
  options.lodDataBytes = std::size_t(1) << 20;
  return options;
}

// A budget far below the flight's needs: hierarchies are evicted and loaded again, the
// resident bytes stay within the budget (plus the root and the one entry the cache keeps
// over it), and every frame stays whole.
TEST(BlockLoading, ResidentHierarchiesStayWithinTheirBudget) {
  auto field = test::sharedGeneratedTerrain(513, 6);
  const TerrainEngineOptions options = withTightLodBudget();
  auto engine = TerrainEngine::create(field, options);
  ASSERT_TRUE(engine.ok());
  std::size_t onAncestor = 0;
  for (int frame = 0; frame < 60; ++frame) {
    const Camera camera = lowCamera(*field, 300.0 + 220.0 * frame);
    const TerrainFrame& result = frame % 3 == 0 ? (*engine)->updateSettled(camera) : (*engine)->update(camera);
    onAncestor += result.stats.blocksOnAncestor > 0;
    const TerrainLoadStats& loads = (*engine)->loadStats();
    EXPECT_LE(loads.residentBytes, options.lodDataBytes + 2 * (std::size_t(64) << 10)) << "frame " << frame;
    if (frame % 6 == 0) expectCoveredAndWatertight(**engine, "frame " + std::to_string(frame));
  }
  EXPECT_GT((*engine)->loadStats().evictions, 0u);
  EXPECT_GT((*engine)->loadStats().loads, 60u);
}

// A budget smaller than the cut a view wants: the blocks the last frame needed are never
// evicted for new ones, so a still camera keeps one cut (on ancestors where the budget ends)
// instead of trading blocks with the loaders frame after frame.
TEST(BlockLoading, AFullBudgetKeepsItsCutRatherThanTradingBlocks) {
  auto field = test::sharedGeneratedTerrain(513, 6);
  const TerrainEngineOptions options = withTightLodBudget();
  auto engine = TerrainEngine::create(field, options);
  ASSERT_TRUE(engine.ok());
  const Camera camera = lowCamera(*field, field->extentX() * 0.4);
  std::vector<terrain::NodeId> cut;
  std::uint64_t evictionsBefore = 0;
  for (int frame = 0; frame < 40; ++frame) {
    const TerrainFrame& result = (*engine)->update(camera);
    (*engine)->waitForLoads();
    if (frame == 20) {
      evictionsBefore = (*engine)->loadStats().evictions;
      for (const TerrainBlockDraw& block : result.blocks) cut.push_back(block.node);
    }
    if (frame > 20) {
      EXPECT_GT(result.stats.blocksOnAncestor, 0u) << "frame " << frame;  // the budget binds
      ASSERT_EQ(result.blocks.size(), cut.size()) << "frame " << frame;
      for (std::size_t i = 0; i < cut.size(); ++i) EXPECT_EQ(result.blocks[i].node, cut[i]) << "frame " << frame;
    }
  }
  const TerrainLoadStats& loads = (*engine)->loadStats();
  EXPECT_EQ(loads.evictions, evictionsBefore);
  EXPECT_GT(loads.turnedAway, 0u);
  EXPECT_LE(loads.residentBytes, options.lodDataBytes + 2 * (std::size_t(64) << 10));
  expectCoveredAndWatertight(**engine, "last frame");
}

// One memory budget: the heightfield and quadtree first, the rest split between block
// hierarchies and the LOD cache, and each part kept within its share while flying.
TEST(BlockLoading, OneMemoryBudgetIsSplitExactlyAndKept) {
  auto field = hills(1025);
  TerrainEngineOptions options;
  options.memoryBudgetBytes = std::size_t(13) << 20;  // 4 MB of heights, 4.5 MB each for blocks
  auto engine = TerrainEngine::create(field, options);
  ASSERT_TRUE(engine.ok()) << engine.error().message;
  const TerrainMemory start = (*engine)->memory();
  EXPECT_EQ(start.sourceBytes, field->heights.capacity() * sizeof(float));
  EXPECT_GT(start.quadtreeBytes, 0u);
  EXPECT_EQ(start.sourceBytes + start.quadtreeBytes + start.lodDataBudgetBytes + start.cacheBudgetBytes,
            options.memoryBudgetBytes);
  EXPECT_LE(start.lodDataBudgetBytes, start.cacheBudgetBytes);
  EXPECT_GE(start.lodDataBudgetBytes + 1, start.cacheBudgetBytes);
  std::size_t peak = 0;
  for (int frame = 0; frame < 60; ++frame) {
    const Camera camera = lowCamera(*field, 300.0 + 220.0 * frame);
    if (frame % 3 == 0) {
      (void)(*engine)->updateSettled(camera);
    } else {
      (void)(*engine)->update(camera);
    }
    const TerrainMemory held = (*engine)->memory();
    // A hierarchy may land in the frame that evicts down to the budget (one block's worth);
    // the LOD cache goes over only for meshes the frame is drawing, never here.
    EXPECT_LE(held.lodDataBytes, held.lodDataBudgetBytes + 2 * (std::size_t(64) << 10)) << "frame " << frame;
    EXPECT_LE(held.cacheBytes, held.cacheBudgetBytes) << "frame " << frame;
    peak = std::max(peak, held.totalBytes());
    if (frame % 6 == 0) expectCoveredAndWatertight(**engine, "frame " + std::to_string(frame));
  }
  EXPECT_GT((*engine)->loadStats().evictions, 0u) << "the budget must bind for this test to mean anything";
  EXPECT_LE(peak, options.memoryBudgetBytes + 2 * (std::size_t(64) << 10));
}

TEST(BlockLoading, AMemoryBudgetTooSmallForTheHeightfieldIsRefused) {
  auto field = test::sharedGeneratedTerrain(513, 6);
  TerrainEngineOptions options;
  options.memoryBudgetBytes = field->heights.size() * sizeof(float) + kLeastBlockMemoryBytes / 2;
  auto engine = TerrainEngine::create(field, options);
  ASSERT_FALSE(engine.ok());
  EXPECT_EQ(engine.error().kind, ErrorKind::InvalidArgument);
  EXPECT_NE(engine.error().message.find("memory budget"), std::string::npos) << engine.error().message;
}

TEST(BlockLoading, OnlyASettledFrameWaitsForTheLoadersAndEachWaitIsCounted) {
  auto field = test::sharedGeneratedTerrain(513, 6);
  auto engine = TerrainEngine::create(field);
  ASSERT_TRUE(engine.ok());
  std::uint64_t loadsAsked = 0;
  for (int frame = 0; frame < 30; ++frame)
    loadsAsked += (*engine)->update(lowCamera(*field, 300.0 + 220.0 * frame)).stats.loadsRequested;
  ASSERT_GT(loadsAsked, 0u) << "the frames must have had something to wait for";
  EXPECT_EQ((*engine)->loadStats().frameWaits, 0u);
  // A settled first frame of a new engine, which holds none of the blocks it needs yet: it
  // waits, and draws every block at its selected level.
  auto fresh = TerrainEngine::create(field);
  ASSERT_TRUE(fresh.ok());
  const TerrainFrame& settled = (*fresh)->updateSettled(lowCamera(*field, 300.0));
  EXPECT_EQ(settled.stats.blocksOnAncestor, 0u);
  EXPECT_GT((*fresh)->loadStats().frameWaits, 0u);
}

}  // namespace
}  // namespace polder
