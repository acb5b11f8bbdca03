#include <polder/terrain/full_resolution_mesh.hpp>

#include <array>
#include <cmath>
#include <map>
#include <set>
#include <utility>

#include <gtest/gtest.h>

#include <polder/terrain/normals.hpp>

namespace polder::terrain {
namespace {

using GridKey = std::pair<int, int>;  // (x, y) sample coordinates

// A bumpy field whose heights differ from sample to sample, so a wrong vertex shows.
Heightfield bumpyField(int w, int h, double sx, double sy) {
  Heightfield field(w, h, sx, sy);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      field.at(x, y) = float(100.0 + 40.0 * std::sin(0.7 * x) * std::cos(0.45 * y) + 3.0 * x - 2.0 * y);
  return field;
}

// The sample a chunk vertex stands for, from its world position.
GridKey keyOf(const Heightfield& field, const MeshData& mesh, std::uint32_t vertex) {
  const glm::dvec3 world = mesh.origin + glm::dvec3(mesh.positions[vertex]);
  return {int(std::lround(world.x / field.spacingX)), int(std::lround(world.y / field.spacingY))};
}

std::array<GridKey, 3> triangleKeys(const Heightfield& field, const MeshData& mesh, std::size_t triangle) {
  return {keyOf(field, mesh, mesh.indices[3 * triangle]), keyOf(field, mesh, mesh.indices[3 * triangle + 1]),
          keyOf(field, mesh, mesh.indices[3 * triangle + 2])};
}

TEST(FullResolutionMesh, TriangleCountIsTwicePerCell) {
  const Heightfield field = bumpyField(13, 10, 30.0, 30.0);
  EXPECT_EQ(fullResolutionTriangleCount(field), 2u * 12u * 9u);
  std::size_t total = 0;
  for (const MeshData& mesh : buildFullResolutionMeshes(field, 4)) total += mesh.triangleCount();
  EXPECT_EQ(total, fullResolutionTriangleCount(field));

  EXPECT_EQ(fullResolutionTriangleCount(Heightfield(2, 2)), 2u);
  EXPECT_EQ(fullResolutionTriangleCount(Heightfield(1, 5)), 0u);
  EXPECT_TRUE(buildFullResolutionMeshes(Heightfield(1, 5)).empty());
  EXPECT_TRUE(buildFullResolutionMeshes(Heightfield()).empty());
}

TEST(FullResolutionMesh, ChunksAreCutFromTheSouthWestAndEdgeChunksAreSmaller) {
  const Heightfield field = bumpyField(13, 10, 30.0, 20.0);  // 12 x 9 cells
  const std::vector<MeshData> chunks = buildFullResolutionMeshes(field, 5);
  // Columns of 5, 5, 2 cells; rows of 5, 4 cells.
  ASSERT_EQ(chunks.size(), 6u);
  const int expectedCells[6][2] = {{5, 5}, {5, 5}, {2, 5}, {5, 4}, {5, 4}, {2, 4}};
  const int expectedOrigin[6][2] = {{0, 0}, {5, 0}, {10, 0}, {0, 5}, {5, 5}, {10, 5}};
  for (std::size_t c = 0; c < chunks.size(); ++c) {
    const MeshData& mesh = chunks[c];
    const int columns = expectedCells[c][0] + 1, rows = expectedCells[c][1] + 1;
    EXPECT_EQ(mesh.positions.size(), std::size_t(columns * rows)) << "chunk " << c;
    EXPECT_EQ(mesh.normals.size(), mesh.positions.size());
    EXPECT_EQ(mesh.triangleCount(), std::size_t(2 * (columns - 1) * (rows - 1)));
    const glm::dvec3 sw = field.worldPosition(expectedOrigin[c][0], expectedOrigin[c][1]);
    EXPECT_EQ(mesh.origin, sw) << "chunk " << c << ": origin is its south-west sample";
    // Never stretched: neighbouring vertices are one spacing apart.
    EXPECT_FLOAT_EQ(mesh.positions[1].x - mesh.positions[0].x, 30.0f);
    EXPECT_FLOAT_EQ(mesh.positions[std::size_t(columns)].y - mesh.positions[0].y, 20.0f);
  }
}

TEST(FullResolutionMesh, EveryTriangleIsCounterClockwiseSeenFromAbove) {
  const Heightfield field = bumpyField(17, 11, 25.0, 40.0);
  for (const MeshData& mesh : buildFullResolutionMeshes(field, 6)) {
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
      const glm::vec3 a = mesh.positions[mesh.indices[3 * t]], b = mesh.positions[mesh.indices[3 * t + 1]],
                      c = mesh.positions[mesh.indices[3 * t + 2]];
      const float crossZ = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
      ASSERT_GT(crossZ, 0.0f) << "triangle " << t;
      // And its geometric normal points up.
      EXPECT_GT(glm::cross(b - a, c - a).z, 0.0f);
    }
  }
}

TEST(FullResolutionMesh, CellsAreCutAlongTheDiagonalFromSouthEastToNorthWest) {
  // The two triangles of cell (x, y) must be {(x,y), (x+1,y), (x,y+1)} and
  // {(x+1,y+1), (x,y+1), (x+1,y)}: the diagonal joins (x+1, y) and (x, y+1).
  const Heightfield field = bumpyField(9, 7, 10.0, 10.0);
  std::multiset<std::set<GridKey>> expected, actual;
  for (int y = 0; y + 1 < field.height; ++y)
    for (int x = 0; x + 1 < field.width; ++x) {
      expected.insert(std::set<GridKey>{GridKey{x, y}, GridKey{x + 1, y}, GridKey{x, y + 1}});
      expected.insert(std::set<GridKey>{GridKey{x + 1, y + 1}, GridKey{x, y + 1}, GridKey{x + 1, y}});
    }
  for (const MeshData& mesh : buildFullResolutionMeshes(field, 3))
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
      const auto keys = triangleKeys(field, mesh, t);
      actual.insert(std::set<GridKey>{keys[0], keys[1], keys[2]});
    }
  EXPECT_EQ(actual, expected);

  // The smallest case, vertex by vertex and in the header's order.
  const Heightfield cell = bumpyField(2, 2, 1.0, 1.0);
  const std::vector<MeshData> one = buildFullResolutionMeshes(cell);
  ASSERT_EQ(one.size(), 1u);
  ASSERT_EQ(one[0].triangleCount(), 2u);
  EXPECT_EQ(triangleKeys(cell, one[0], 0), (std::array<GridKey, 3>{GridKey{0, 0}, GridKey{1, 0}, GridKey{0, 1}}));
  EXPECT_EQ(triangleKeys(cell, one[0], 1), (std::array<GridKey, 3>{GridKey{1, 1}, GridKey{0, 1}, GridKey{1, 0}}));
}

TEST(FullResolutionMesh, ChunksCoverTheGridWithoutGapsOrOverlaps) {
  const Heightfield field = bumpyField(23, 14, 30.0, 30.0);
  std::map<std::pair<GridKey, GridKey>, int> edgeUses;
  for (const MeshData& mesh : buildFullResolutionMeshes(field, 5)) {
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
      const auto keys = triangleKeys(field, mesh, t);
      for (int e = 0; e < 3; ++e) {
        GridKey a = keys[std::size_t(e)], b = keys[std::size_t((e + 1) % 3)];
        if (b < a) std::swap(a, b);
        ++edgeUses[{a, b}];
      }
    }
  }
  // Edges along the grid's outline belong to one triangle, every other edge to two.
  auto onOutline = [&](GridKey a, GridKey b) {
    return (a.first == b.first && (a.first == 0 || a.first == field.width - 1)) ||
           (a.second == b.second && (a.second == 0 || a.second == field.height - 1));
  };
  std::size_t outline = 0;
  for (const auto& [edge, uses] : edgeUses) {
    if (onOutline(edge.first, edge.second)) {
      EXPECT_EQ(uses, 1) << "outline edge (" << edge.first.first << "," << edge.first.second << ")-("
                         << edge.second.first << "," << edge.second.second << ")";
      ++outline;
    } else {
      EXPECT_EQ(uses, 2) << "interior edge (" << edge.first.first << "," << edge.first.second << ")-("
                         << edge.second.first << "," << edge.second.second << ")";
    }
  }
  EXPECT_EQ(outline, std::size_t(2 * (field.width - 1) + 2 * (field.height - 1)));
  // Edges: (w-1)h horizontal + w(h-1) vertical + (w-1)(h-1) diagonals.
  const std::size_t w = std::size_t(field.width), h = std::size_t(field.height);
  EXPECT_EQ(edgeUses.size(), (w - 1) * h + w * (h - 1) + (w - 1) * (h - 1));
}

TEST(FullResolutionMesh, VerticesReproduceTheSamplesAndTheirNormals) {
  const Heightfield field = bumpyField(20, 12, 30.0, 17.5);
  std::map<GridKey, glm::dvec3> seen;  // world position of each sample, as the first chunk gave it
  for (const MeshData& mesh : buildFullResolutionMeshes(field, 7)) {
    for (std::uint32_t v = 0; v < mesh.positions.size(); ++v) {
      const GridKey key = keyOf(field, mesh, v);
      const glm::dvec3 world = mesh.origin + glm::dvec3(mesh.positions[v]);
      const glm::dvec3 exact = field.worldPosition(key.first, key.second);
      EXPECT_NEAR(world.x, exact.x, 1e-4);
      EXPECT_NEAR(world.y, exact.y, 1e-4);
      EXPECT_NEAR(world.z, exact.z, 1e-4);
      const glm::vec3 normal = sampleNormal(field, key.first, key.second);
      EXPECT_EQ(mesh.normals[v], normal) << "sample (" << key.first << "," << key.second << ")";
      // Samples on a chunk seam appear in each chunk at the same place.
      const auto [it, inserted] = seen.emplace(key, world);
      if (!inserted) {
        EXPECT_LT(glm::length(it->second - world), 1e-4);
      }
    }
  }
  EXPECT_EQ(seen.size(), field.sampleCount());
}

TEST(FullResolutionMesh, PositionsStayWithinACentimetreAtLargeSpacing) {
  // 9783 m between samples: 255 cells would span 2500 km, where a float's step is 25 cm.
  // Chunks shrink instead, so every vertex stays within a centimetre of its exact position.
  Heightfield field(256, 256, 9783.0, 9783.0);
  for (int y = 0; y < field.height; ++y)
    for (int x = 0; x < field.width; ++x) field.at(x, y) = float(4000.0 + 3900.0 * std::sin(0.13 * x + 0.29 * y));
  const std::vector<MeshData> chunks = buildFullResolutionMeshes(field);
  ASSERT_FALSE(chunks.empty());
  double worst = 0.0;
  std::size_t triangles = 0;
  for (const MeshData& mesh : chunks) {
    triangles += mesh.triangleCount();
    for (std::uint32_t v = 0; v < mesh.positions.size(); ++v) {
      const GridKey key = keyOf(field, mesh, v);
      worst = std::max(
          worst, glm::length(mesh.origin + glm::dvec3(mesh.positions[v]) - field.worldPosition(key.first, key.second)));
      EXPECT_LE(std::abs(mesh.positions[v].x), kMaxChunkExtentM);
      EXPECT_LE(std::abs(mesh.positions[v].y), kMaxChunkExtentM);
    }
  }
  EXPECT_LT(worst, 0.01);
  EXPECT_EQ(triangles, fullResolutionTriangleCount(field));
}

}  // namespace
}  // namespace polder::terrain
