// The uniform-error mesh (uniform_mesh.hpp): every triangle, blocks and dikes, within the
// bound when measured again here, watertight (watertight.hpp), fewer triangles for a looser
// bound, coarser nodes where the terrain allows, bad options refused.
#include <polder/terrain/uniform_mesh.hpp>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include <polder/terrain/generator.hpp>
#include <polder/terrain/heightfield_crop.hpp>
#include <polder/terrain/watertight.hpp>

namespace polder::terrain {
namespace {

// A generated terrain cropped to a size that is no multiple of any block pitch, so edge
// blocks are clipped.
Heightfield generated(int size, int width, int height, std::uint64_t seed, double spacingM) {
  GeneratorOptions options;
  options.size = size;
  options.seed = seed;
  options.spacingM = spacingM;
  auto field = generateTerrain(options);
  EXPECT_TRUE(field.ok());
  auto crop = cropHeightfield(*field, 0, 0, width, height);
  EXPECT_TRUE(crop.ok());
  return *crop;
}

// The largest error of every triangle, measured again from the soup alone.
float measuredMaxError(const Heightfield& field, const UniformMesh& mesh) {
  return soupMaxError(field, uniformMeshSoup(mesh));
}

void expectWatertight(const Heightfield& field, const UniformMesh& mesh, const char* what) {
  WatertightOptions options;
  options.samplePoints = 2000;
  const WatertightReport report = checkWatertight(uniformMeshSoup(mesh), field.width, field.height, options);
  EXPECT_EQ(report.openEdges, 0u) << what;
  EXPECT_EQ(report.tJunctions, 0u) << what;
  EXPECT_TRUE(report.watertight()) << what;
  EXPECT_EQ(report.triangles, mesh.triangleCount()) << what;
}

TEST(UniformMesh, EveryTriangleIsWithinTheBoundAndTheMeshIsWatertight) {
  const Heightfield field = generated(257, 201, 170, 3, 30.0);
  std::size_t coarseNodes = 0, splits = 0;
  for (const int k : {3, 5}) {
    for (const double bound : {0.5, 2.0, 8.0, 40.0}) {
      UniformMeshOptions options;
      options.maxErrorM = bound;
      options.blockK = k;
      auto mesh = buildUniformMesh(field, options);
      ASSERT_TRUE(mesh.ok()) << mesh.error().message;
      const std::string what = "k " + std::to_string(k) + ", bound " + std::to_string(bound);
      EXPECT_LE(mesh->maxErrorM(), bound) << what;
      const float measured = measuredMaxError(field, *mesh);
      EXPECT_LE(measured, bound) << what;
      EXPECT_EQ(measured, mesh->maxErrorM()) << what << ": the reported error is the measured one";
      EXPECT_GT(mesh->stats.dikeTriangles, 0u) << what;
      expectWatertight(field, *mesh, what.c_str());
      coarseNodes += mesh->nodes.size() - mesh->stats.nodesPerLevel[0];
      splits += mesh->stats.splitNodes;
    }
  }
  // Both ways of the cut were taken: coarser nodes kept, and coarse nodes split for their dikes.
  EXPECT_GT(coarseNodes, 0u);
  EXPECT_GT(splits, 0u);
}

TEST(UniformMesh, RoughTerrainPinsDikesAndATinyBoundStillHolds) {
  // Per-sample noise on a slope: blocks drop side vertices their dikes need.
  Heightfield field(90, 75, 10.0, 10.0);
  std::uint64_t state = 12345;
  for (std::size_t i = 0; i < field.heights.size(); ++i) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    field.heights[i] = float(0.5 * double(i % 90)) + float(state >> 40) * (5.0f / float(1 << 24));
  }
  for (const double bound : {0.001, 1.0, 2.5}) {
    UniformMeshOptions options;
    options.maxErrorM = bound;
    options.blockK = 4;
    auto mesh = buildUniformMesh(field, options);
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    EXPECT_LE(measuredMaxError(field, *mesh), bound);
    expectWatertight(field, *mesh, "noise");
    if (bound == 0.001) {
      // The full-resolution surface's 2 (w-1)(h-1) triangles, but for cells whose cut
      // costs nothing.
      EXPECT_GT(double(mesh->triangleCount()), 0.95 * 2 * 89 * 74);
    } else {
      EXPECT_GT(mesh->stats.pinnedNodes, 0u) << bound;
      EXPECT_GT(mesh->stats.rounds, 1u) << bound;
    }
  }
}

TEST(UniformMesh, AnySizeAndBlockSizeWorks) {
  std::uint64_t state = 99;
  for (const auto& [width, height] : {std::pair{2, 2}, std::pair{2, 9}, std::pair{3, 3}, std::pair{5, 40},
                                      std::pair{34, 34}, std::pair{35, 67}, std::pair{130, 19}}) {
    Heightfield field(width, height, 7.0, 11.0);
    for (std::size_t i = 0; i < field.heights.size(); ++i) {
      state = state * 6364136223846793005ull + 1442695040888963407ull;
      field.heights[i] = float(0.2 * double(i % std::size_t(width))) + float(state >> 40) * (3.0f / float(1 << 24));
    }
    for (const int k : {1, 3, 5}) {
      for (const double bound : {0.01, 1.0}) {
        UniformMeshOptions options;
        options.maxErrorM = bound;
        options.blockK = k;
        auto mesh = buildUniformMesh(field, options);
        const std::string what = std::to_string(width) + " x " + std::to_string(height) + ", k " + std::to_string(k) +
                                 ", bound " + std::to_string(bound);
        ASSERT_TRUE(mesh.ok()) << what << ": " << mesh.error().message;
        EXPECT_LE(measuredMaxError(field, *mesh), bound) << what;
        expectWatertight(field, *mesh, what.c_str());
      }
    }
  }
}

TEST(UniformMesh, TrianglesFallAsTheBoundGrows) {
  const Heightfield field = generated(257, 257, 257, 11, 30.0);
  std::size_t previous = std::numeric_limits<std::size_t>::max();
  for (const double bound : {0.25, 1.0, 4.0, 16.0, 64.0}) {
    UniformMeshOptions options;
    options.maxErrorM = bound;
    auto mesh = buildUniformMesh(field, options);
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    EXPECT_LT(mesh->triangleCount(), previous) << "bound " << bound;
    previous = mesh->triangleCount();
  }
}

TEST(UniformMesh, SmoothTerrainTakesCoarserNodesAndFewerTriangles) {
  // A tilted plane with one bump: away from the bump every node is exact at any stride.
  Heightfield field(300, 260, 5.0, 5.0);
  for (int y = 0; y < field.height; ++y)
    for (int x = 0; x < field.width; ++x) {
      const double r2 = (x - 60.0) * (x - 60.0) + (y - 70.0) * (y - 70.0);
      field.at(x, y) = float(0.3 * x + 0.1 * y + 40.0 * std::exp(-r2 / 200.0));
    }
  UniformMeshOptions options;
  options.maxErrorM = 0.5;
  options.coarserLevels = false;
  auto finest = buildUniformMesh(field, options);
  options.coarserLevels = true;
  auto coarser = buildUniformMesh(field, options);
  ASSERT_TRUE(finest.ok() && coarser.ok());
  EXPECT_EQ(finest->stats.nodesPerLevel[0], finest->nodes.size());
  EXPECT_LT(coarser->stats.nodesPerLevel[0], coarser->nodes.size()) << "some node above level 0";
  EXPECT_LT(coarser->triangleCount(), finest->triangleCount());
  EXPECT_LE(measuredMaxError(field, *coarser), 0.5f);
  expectWatertight(field, *coarser, "coarser levels");
}

TEST(UniformMesh, TheWorldMeshHasEveryTriangleCounterClockwiseOnTheSamples) {
  const Heightfield field = generated(129, 129, 100, 5, 20.0);
  UniformMeshOptions options;
  options.maxErrorM = 3.0;
  auto mesh = buildUniformMesh(field, options);
  ASSERT_TRUE(mesh.ok());
  const mesh::TriangleMesh world = uniformMeshTriangles(field, *mesh);
  EXPECT_EQ(world.triangleCount(), mesh->triangleCount());
  EXPECT_EQ(world.normals.size(), world.positions.size());
  EXPECT_TRUE(mesh::validateMesh(world, "uniform mesh").ok());
  for (std::size_t t = 0; t < world.triangleCount(); ++t) {
    const glm::dvec3 a(world.positions[world.indices[3 * t]]), b(world.positions[world.indices[3 * t + 1]]),
        c(world.positions[world.indices[3 * t + 2]]);
    ASSERT_GT((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x), 0.0) << "triangle " << t;
  }
  for (const glm::vec3& p : world.positions) {
    const int x = int(std::lround(p.x / field.spacingX)), y = int(std::lround(p.y / field.spacingY));
    ASSERT_EQ(p.z, field.at(x, y));
  }
}

TEST(UniformMesh, RefusesBadOptionsAndNonFiniteHeights) {
  const Heightfield field = generated(65, 65, 65, 2, 10.0);
  for (const double bound : {0.0, -1.0, std::nan(""), std::numeric_limits<double>::infinity(), 1e-9, 1e12}) {
    UniformMeshOptions options;
    options.maxErrorM = bound;
    auto mesh = buildUniformMesh(field, options);
    ASSERT_FALSE(mesh.ok()) << bound;
    EXPECT_EQ(mesh.error().kind, ErrorKind::InvalidArgument) << bound;
  }
  for (const int k : {0, 8, -3}) {
    UniformMeshOptions options;
    options.blockK = k;
    auto mesh = buildUniformMesh(field, options);
    ASSERT_FALSE(mesh.ok()) << k;
    EXPECT_EQ(mesh.error().kind, ErrorKind::InvalidArgument) << k;
  }
  Heightfield holes = field;
  holes.at(10, 10) = std::numeric_limits<float>::quiet_NaN();
  auto mesh = buildUniformMesh(holes, UniformMeshOptions{});
  ASSERT_FALSE(mesh.ok());
  EXPECT_EQ(mesh.error().kind, ErrorKind::InvalidData);
  EXPECT_FALSE(buildUniformMesh(Heightfield(1, 5), UniformMeshOptions{}).ok());
}

TEST(UniformMesh, ReportsProgressUpToOne) {
  const Heightfield field = generated(129, 129, 129, 9, 20.0);
  std::vector<float> reports;
  UniformMeshOptions options;
  options.maxErrorM = 2.0;
  options.progress = [&](float f) { reports.push_back(f); };
  ASSERT_TRUE(buildUniformMesh(field, options).ok());
  ASSERT_FALSE(reports.empty());
  EXPECT_EQ(reports.back(), 1.0f);
  for (std::size_t i = 1; i < reports.size(); ++i) EXPECT_GE(reports[i], reports[i - 1]);
}

}  // namespace
}  // namespace polder::terrain
