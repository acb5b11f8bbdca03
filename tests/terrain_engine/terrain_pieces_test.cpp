// The frame's pieces and their lifetimes (polder/terrain_frame.hpp): a host that follows
// created, changed and retired holds exactly the frame's pieces; a version changes exactly
// when the geometry does; a still camera changes nothing; the pieces' vertices lie on the
// sample grid and together cover the DEM without cracks.
#include <polder/terrain_engine.hpp>

#include <cmath>
#include <map>
#include <random>
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include <polder/terrain/watertight.hpp>

#include "generated_terrain.hpp"

namespace polder {
namespace {

// A piece's geometry as a host would have copied it.
struct HeldPiece {
  std::uint64_t version = 0;
  GridAnchor anchor;
  std::vector<GridMeshVertex> vertices;
  std::vector<std::uint32_t> indices;

  bool sameGeometry(const GridMeshView& mesh) const {
    if (!(mesh.anchor == anchor) || mesh.vertices.size() != vertices.size() || mesh.indices.size() != indices.size())
      return false;
    for (std::size_t i = 0; i < vertices.size(); ++i) {
      const GridMeshVertex& a = vertices[i];
      const GridMeshVertex& b = mesh.vertices[i];
      if (a.x != b.x || a.y != b.y || a.z != b.z || a.nx != b.nx || a.ny != b.ny || a.nz != b.nz) return false;
    }
    return std::equal(indices.begin(), indices.end(), mesh.indices.begin());
  }
};

HeldPiece hold(const TerrainPiece& piece) {
  return HeldPiece{piece.version,
                   piece.mesh.anchor,
                   {piece.mesh.vertices.begin(), piece.mesh.vertices.end()},
                   {piece.mesh.indices.begin(), piece.mesh.indices.end()}};
}

// A flight that turns and climbs, so blocks refine, coarsen, leave and enter the view.
Camera flightCamera(int frame, const terrain::Heightfield& field) {
  Camera camera;
  camera.widthPx = 320;
  camera.heightPx = 240;
  const double t = frame / 60.0;
  camera.position = {field.extentX() * (0.5 + 0.35 * std::cos(0.9 * t)),
                     field.extentY() * (0.5 + 0.35 * std::sin(0.9 * t)), 2200.0 + 900.0 * std::sin(0.5 * t)};
  camera.yawDeg = 40.0 * t;
  camera.pitchDeg = -25.0;
  return camera;
}

void followFlight(TerrainEngineOptions options) {
  auto field = test::sharedGeneratedTerrain(300, 4);
  auto engine = TerrainEngine::create(field, options);
  ASSERT_TRUE(engine.ok()) << engine.error().message;
  std::map<std::uint64_t, HeldPiece> held;
  std::set<std::uint64_t> versionsSeen;
  std::size_t created = 0, changed = 0, retired = 0, unchanged = 0;
  for (int frame = 0; frame < 240; ++frame) {
    const TerrainFrame& result = (*engine)->update(flightCamera(frame, *field));
    // Loads arrive at the next frame whatever the machine's load, so the flight is the same
    // on every run.
    (*engine)->waitForLoads();
    for (const TerrainPieceKey key : result.retired) {
      ASSERT_EQ(held.erase(key.value), 1u) << "frame " << frame << ": retired a piece the host never had";
      ++retired;
    }
    std::set<std::uint32_t> touched;
    for (const std::uint32_t index : result.created) {
      const TerrainPiece& piece = result.pieces[index];
      ASSERT_FALSE(held.count(piece.key.value)) << "frame " << frame << ": created a piece the host holds";
      held[piece.key.value] = hold(piece);
      touched.insert(index);
      ++created;
    }
    for (const std::uint32_t index : result.changed) {
      const TerrainPiece& piece = result.pieces[index];
      auto it = held.find(piece.key.value);
      ASSERT_NE(it, held.end()) << "frame " << frame << ": changed a piece the host does not hold";
      EXPECT_NE(it->second.version, piece.version);
      EXPECT_FALSE(it->second.sameGeometry(piece.mesh)) << "frame " << frame << ": a new version of the same geometry";
      it->second = hold(piece);
      touched.insert(index);
      ++changed;
    }
    ASSERT_EQ(held.size(), result.pieces.size()) << "frame " << frame;
    for (std::uint32_t i = 0; i < result.pieces.size(); ++i) {
      const TerrainPiece& piece = result.pieces[i];
      auto it = held.find(piece.key.value);
      ASSERT_NE(it, held.end()) << "frame " << frame << ": a piece the host was never told of";
      if (touched.count(i)) {
        EXPECT_TRUE(versionsSeen.insert(piece.version).second) << "versions are never reused";
        continue;
      }
      // Not reported: same version, same geometry, byte for byte.
      EXPECT_EQ(it->second.version, piece.version) << "frame " << frame;
      EXPECT_TRUE(it->second.sameGeometry(piece.mesh)) << "frame " << frame << ": geometry changed under one version";
      ++unchanged;
    }
  }
  // The flight exercises every case.
  EXPECT_GT(created, 100u);
  EXPECT_GT(changed, 10u);
  EXPECT_GT(retired, 10u);
  EXPECT_GT(unchanged, created + changed);
}

TEST(TerrainPieces, AHostFollowingTheListsHoldsExactlyTheFramesPieces) { followFlight({}); }

TEST(TerrainPieces, AHostFollowingTheListsHoldsExactlyTheFramesPiecesInBudgetMode) {
  TerrainEngineOptions options;
  options.mode = LodMode::TriangleBudget;
  options.budgetTriangles = 30000;
  options.loading = BlockLoading::Immediate;  // the pixel-error flight above loads in the background
  followFlight(options);
}

TEST(TerrainPieces, AStillCameraChangesNothing) {
  auto field = test::sharedGeneratedTerrain(257, 6);
  auto engine = TerrainEngine::create(field, {});
  ASSERT_TRUE(engine.ok());
  const Camera camera = flightCamera(30, *field);
  const TerrainFrame& start = (*engine)->update(camera);
  EXPECT_EQ(start.created.size(), start.pieces.size());
  // The first frames from a new viewpoint may still split nodes whose dikes were too coarse.
  (void)(*engine)->updateSettled(camera);
  for (int settle = 0; settle < 3; ++settle) (void)(*engine)->update(camera);
  const TerrainFrame& first = (*engine)->update(camera);
  std::vector<std::uint64_t> versions;
  std::vector<const GridMeshVertex*> data;
  for (const TerrainPiece& piece : first.pieces)
    versions.push_back(piece.version), data.push_back(piece.mesh.vertices.data());
  for (int frame = 0; frame < 5; ++frame) {
    const TerrainFrame& again = (*engine)->update(camera);
    EXPECT_TRUE(again.created.empty());
    EXPECT_TRUE(again.changed.empty());
    EXPECT_TRUE(again.retired.empty());
    EXPECT_EQ(again.stats.pieceBytesProduced, 0u);
    EXPECT_FALSE(again.stats.dikesStitched) << "nothing changed: the dikes stand";
    EXPECT_TRUE((*engine)->checkWatertight().watertight());
    ASSERT_EQ(again.pieces.size(), versions.size());
    for (std::size_t i = 0; i < versions.size(); ++i) {
      EXPECT_EQ(again.pieces[i].version, versions[i]);
      EXPECT_EQ(again.pieces[i].mesh.vertices.data(), data[i]) << "the data stays where the host found it";
    }
  }
}

// Seen from straight above, every block is visible, so the pieces are the whole frame: on the
// integer sample grid they cover the DEM with no open edge, and their vertices are samples.
TEST(TerrainPieces, PiecesLieOnTheSampleGridAndCoverTheDemWatertight) {
  auto field = test::sharedGeneratedTerrain(300, 8);
  for (const LodMode mode : {LodMode::PixelError, LodMode::TriangleBudget}) {
    TerrainEngineOptions options;
    options.mode = mode;
    options.budgetTriangles = 20000;
    options.tauPx = 3.0;
    auto engine = TerrainEngine::create(field, options);
    ASSERT_TRUE(engine.ok());
    Camera camera;
    camera.widthPx = 400;
    camera.heightPx = 400;
    camera.fovYDeg = 90.0;
    camera.position = {0.5 * field->extentX(), 0.5 * field->extentY(), 12000.0};
    camera.pitchDeg = -90.0;
    const TerrainFrame& frame = (*engine)->update(camera);
    ASSERT_EQ(frame.stats.culledBlocks, 0u);
    terrain::TriangleSoup soup;
    std::size_t triangles = 0;
    for (const TerrainPiece& piece : frame.pieces) {
      triangles += piece.mesh.triangleCount();
      for (std::size_t t = 0; t < piece.mesh.indices.size(); t += 3) {
        terrain::GridPoint corners[3];
        for (int c = 0; c < 3; ++c) {
          const GridMeshVertex& v = piece.mesh.vertices[piece.mesh.indices[t + std::size_t(c)]];
          ASSERT_EQ(v.x, std::floor(v.x));
          ASSERT_EQ(v.y, std::floor(v.y));
          const int x = int(piece.mesh.anchor.x) + int(v.x), y = int(piece.mesh.anchor.y) + int(v.y);
          ASSERT_EQ(v.z, field->at(x, y)) << "heights are the samples' own";
          corners[c] = terrain::GridPoint{x, y};
        }
        soup.addTriangle(corners[0], corners[1], corners[2]);
      }
    }
    EXPECT_EQ(triangles, frame.stats.triangles());
    const terrain::WatertightReport report = terrain::checkWatertight(soup, field->width, field->height);
    EXPECT_TRUE(report.watertight()) << report.openEdges << " open edges, " << report.tJunctions << " T-junctions, "
                                     << report.samplesUncovered << " uncovered, " << report.samplesOverlapped
                                     << " overlapped";
  }
}

}  // namespace
}  // namespace polder
