#include <polder/flight_recorder.hpp>

#include <chrono>
#include <memory>
#include <optional>
#include <vector>

#include <gtest/gtest.h>

#include "allocation_counter.hpp"
#include "generated_terrain.hpp"

namespace polder {
namespace {

Camera smallLens() {
  Camera lens;
  lens.widthPx = 320;
  lens.heightPx = 240;
  lens.nearM = 1.0;
  lens.farM = 1e6;
  return lens;
}

// Two seconds across the terrain, looking ahead and down.
CameraPath crossing() {
  auto path = CameraPath::fromPoses(
      {CameraPose{0.0, {1000.0, 500.0, 2500.0}, 20.0, -30.0}, CameraPose{2.0, {6000.0, 4000.0, 2000.0}, 60.0, -25.0}});
  EXPECT_TRUE(path.ok());
  return *path;
}

// A recorder over a generated terrain, along `crossing`.
class FlightRecorderTest : public ::testing::Test {
 protected:
  std::unique_ptr<TerrainEngine> engine = makeEngine();
  const CameraPath path = crossing();
  FlightRecorder recorder{*engine, path, smallLens()};

 private:
  static std::unique_ptr<TerrainEngine> makeEngine() {
    // Every frame at its selected level, so that what the hooks see does not hang on when
    // background loads arrive.
    TerrainEngineOptions options;
    options.loading = BlockLoading::Immediate;
    auto created =
        TerrainEngine::create(std::make_shared<terrain::Heightfield>(test::generatedTerrain(257, 11)), options);
    EXPECT_TRUE(created.ok());
    return std::move(*created);
  }
};

TEST_F(FlightRecorderTest, RecordsEveryFrameAsTheEngineReportedIt) {
  std::vector<TerrainFrameStats> seen;
  std::vector<Camera> cameras;
  FlightHooks hooks;
  hooks.draw = [&](const TerrainFrame& frame, const Camera& camera) {
    seen.push_back(frame.stats);
    cameras.push_back(camera);
    return std::size_t(100 * seen.size());
  };
  hooks.countCracks = [](TerrainEngine&, const Camera&) { return FramePixelCracks{3, 1}; };
  FlightOptions options;
  options.frames = 45;
  options.checkEvery = 0;
  auto record = recorder.fly(options, hooks);
  ASSERT_TRUE(record.ok()) << record.error().message;

  ASSERT_EQ(record->frames, 45);
  ASSERT_EQ(seen.size(), 45u);
  for (const std::vector<double>* series :
       {&record->selectMs, &record->lodMs, &record->dikesMs, &record->piecesMs, &record->totalMs, &record->triangles,
        &record->dikeTriangles, &record->visibleBlocks, &record->culledBlocks, &record->renderMs, &record->uploadBytes})
    EXPECT_EQ(series->size(), 45u);
  std::uint64_t lookups = 0, hits = 0, rebuilds = 0, created = 0, retired = 0;
  double bytes = 0.0;
  for (std::size_t i = 0; i < seen.size(); ++i) {
    const TerrainFrameStats& stats = seen[i];
    EXPECT_EQ(record->selectMs[i], stats.selectMs);
    EXPECT_EQ(record->lodMs[i], stats.lodMs);
    EXPECT_EQ(record->totalMs[i], stats.totalMs);
    EXPECT_EQ(record->triangles[i], double(stats.triangles()));
    EXPECT_EQ(record->dikeTriangles[i], double(stats.dikeTriangles));
    EXPECT_EQ(record->visibleBlocks[i], double(stats.visibleBlocks));
    EXPECT_EQ(record->culledBlocks[i], double(stats.culledBlocks));
    EXPECT_EQ(record->uploadBytes[i], double(100 * (i + 1)));
    EXPECT_GE(record->renderMs[i], 0.0);
    lookups += stats.cacheLookups, hits += stats.cacheHits, rebuilds += stats.cacheRebuilds;
    created += stats.piecesCreated, retired += stats.piecesRetired;
    bytes += double(stats.pieceBytesProduced);
    // 60 frames per second of flight.
    const Camera expected = path.at(double(i) / 60.0).placed(smallLens());
    EXPECT_NEAR(cameras[i].position.x, expected.position.x, 1e-9);
    EXPECT_NEAR(cameras[i].yawDeg, expected.yawDeg, 1e-9);
    EXPECT_EQ(cameras[i].widthPx, 320);
  }
  EXPECT_EQ(record->cacheLookups, lookups);
  EXPECT_EQ(record->cacheHits, hits);
  EXPECT_EQ(record->cacheRebuilds, rebuilds);
  EXPECT_EQ(record->piecesCreated, created);
  EXPECT_EQ(record->piecesRetired, retired);
  EXPECT_EQ(record->pieceBytes, bytes);
  EXPECT_GT(record->cacheHits, 0u);  // the cache served the moving camera too
  EXPECT_EQ(record->cracks.enclosedBackgroundPx, 3u * 45u);
  EXPECT_EQ(record->cracks.crackPx, 45u);
  EXPECT_EQ(record->framesChecked, 0);
  EXPECT_EQ(record->framesMeasured, 0);
}

TEST_F(FlightRecorderTest, ChecksAndMeasuresEveryNthFrame) {
  std::vector<int> measuredAt;
  int frame = -1;
  FlightHooks hooks;
  hooks.draw = [&](const TerrainFrame&, const Camera&) {
    ++frame;
    return std::size_t(0);
  };
  hooks.measureError = [&](TerrainEngine&, const Camera&) -> std::optional<FrameScreenError> {
    measuredAt.push_back(frame);
    if (frame == 4) return std::nullopt;  // could not measure this one: checked, not measured
    return FrameScreenError{0.25 * (frame + 1), 0.1 * (frame + 1), std::size_t(frame)};
  };
  std::vector<int> afterCheckAt;
  hooks.afterCheck = [&](int frameIndex) { afterCheckAt.push_back(frameIndex); };
  FlightOptions options;
  options.frames = 10;
  options.checkEvery = 4;
  auto record = recorder.fly(options, hooks);
  ASSERT_TRUE(record.ok());
  EXPECT_EQ(measuredAt, (std::vector<int>{0, 4, 8}));
  EXPECT_EQ(afterCheckAt, (std::vector<int>{0, 4, 8}));
  EXPECT_EQ(record->holePixels, 8u) << "hole pixels add up over the measured frames";
  EXPECT_EQ(record->framesChecked, 3);
  EXPECT_EQ(record->framesMeasured, 2);
  EXPECT_DOUBLE_EQ(record->errorMaxPx, 0.25 * 9);
  EXPECT_DOUBLE_EQ(record->errorP99Px, 0.1 * 9);
  EXPECT_EQ(record->openEdges, 0u);
  EXPECT_EQ(record->tJunctions, 0u);
  EXPECT_EQ(frame, 9);

  options.checkEvery = 0;  // never
  measuredAt.clear();
  afterCheckAt.clear();
  auto unchecked = recorder.fly(options, hooks);
  ASSERT_TRUE(unchecked.ok());
  EXPECT_TRUE(measuredAt.empty());
  EXPECT_TRUE(afterCheckAt.empty());
  EXPECT_EQ(unchecked->framesChecked, 0);
}

TEST_F(FlightRecorderTest, RefusesFlightsWithoutFrames) {
  FlightOptions options;
  options.frames = 0;
  EXPECT_EQ(recorder.fly(options).error().kind, ErrorKind::InvalidArgument);
  options.frames = 5;
  options.checkEvery = -1;
  EXPECT_EQ(recorder.fly(options).error().kind, ErrorKind::InvalidArgument);
}

TEST_F(FlightRecorderTest, FliesWithoutTheCacheAndRestoresIt) {
  FlightOptions options;
  options.frames = 30;
  options.checkEvery = 10;
  options.withoutCache = true;
  auto uncached = recorder.fly(options);
  ASSERT_TRUE(uncached.ok());
  EXPECT_GT(uncached->cacheLookups, 0u);
  EXPECT_EQ(uncached->cacheHits, 0u);  // every block rebuilt every frame
  EXPECT_EQ(uncached->framesChecked, 3);
  EXPECT_EQ(uncached->openEdges + uncached->tJunctions, 0u);
  EXPECT_TRUE(engine->options().cacheEnabled);

  options.withoutCache = false;
  auto cached = recorder.fly(options);
  ASSERT_TRUE(cached.ok());
  EXPECT_GT(cached->cacheHits, 0u);
  const CacheComparison comparison = compareCache(*cached, *uncached);
  EXPECT_LT(comparison.lodMsSavedFraction, 1.0);
  EXPECT_GT(comparison.trianglesRatio, 0.5);  // the cache keeps tau, it does not drop detail
  EXPECT_LT(comparison.trianglesRatio, 2.0);
}

TEST_F(FlightRecorderTest, SteadyFramesAllocateNothing) {
  auto still = CameraPath::fromPoses({CameraPose{0.0, {2000.0, -500.0, 2500.0}, 20.0, -30.0}});
  ASSERT_TRUE(still.ok());
  FlightRecorder stillRecorder(*engine, *still, smallLens());
  std::size_t atFrame5 = 0, atLastFrame = 0;
  int frame = 0;
  FlightHooks hooks;
  hooks.draw = [](const TerrainFrame&, const Camera&) { return std::size_t(0); };
  hooks.progress = [&](float) {
    ++frame;
    if (frame == 5) atFrame5 = test::allocationCount();
    if (frame == 60) atLastFrame = test::allocationCount();
  };
  FlightOptions options;
  options.frames = 60;
  options.checkEvery = 0;
  ASSERT_TRUE(stillRecorder.fly(options, hooks).ok());
  EXPECT_EQ(atLastFrame - atFrame5, 0u);
}

// With background loading a fresh engine has only the root's hierarchy: its first frame is
// drawn partly from ancestors and its error is kept apart, unless the flight settles first.
TEST(FlightRecorderLoadingTest, KeepsFramesOnAncestorsApartUnlessSettled) {
  auto created = TerrainEngine::create(std::make_shared<terrain::Heightfield>(test::generatedTerrain(257, 11)));
  ASSERT_TRUE(created.ok());
  const CameraPath path = crossing();
  FlightRecorder recorder(**created, path, smallLens());
  FlightHooks hooks;
  hooks.measureError = [](TerrainEngine&, const Camera&) { return std::optional(FrameScreenError{3.0, 2.0}); };
  FlightOptions options;
  options.frames = 1;
  options.checkEvery = 1;

  auto unsettled = recorder.fly(options, hooks);
  ASSERT_TRUE(unsettled.ok());
  EXPECT_EQ(unsettled->framesOnAncestor, 1);
  EXPECT_EQ(unsettled->framesMeasuredOnAncestor, 1);
  EXPECT_EQ(unsettled->framesMeasured, 0);
  EXPECT_DOUBLE_EQ(unsettled->errorOnAncestorMaxPx, 3.0);
  EXPECT_EQ(unsettled->openEdges + unsettled->tJunctions, 0u);  // coarser, never open

  options.settleFirstFrame = true;
  auto settled = recorder.fly(options, hooks);
  ASSERT_TRUE(settled.ok());
  EXPECT_EQ(settled->framesOnAncestor, 0);
  EXPECT_EQ(settled->framesMeasured, 1);
  EXPECT_DOUBLE_EQ(settled->errorMaxPx, 3.0);
}

TEST(FlightRecorderLoadingTest, PacedFramesStartAtTheFlightsRate) {
  auto created = TerrainEngine::create(std::make_shared<terrain::Heightfield>(test::generatedTerrain(129, 3)));
  ASSERT_TRUE(created.ok());
  const CameraPath path = crossing();
  FlightRecorder recorder(**created, path, smallLens());
  FlightOptions options;
  options.frames = 7;
  options.checkEvery = 0;
  options.paced = true;
  const auto start = std::chrono::steady_clock::now();
  ASSERT_TRUE(recorder.fly(options).ok());
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_GE(seconds, 6.0 / kFlightFramesPerSecond);  // frame 6 starts 6/60 s in
}

}  // namespace
}  // namespace polder
