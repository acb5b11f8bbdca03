// The watertightness checker (watertight.hpp) on hand-made meshes: it passes a correct grid
// triangulation and finds each kind of defect (a removed triangle, a T-junction, an overlap,
// a flipped or degenerate triangle, a vertex outside the DEM), including defects the edge
// counts alone would let through (sampling).
#include <polder/terrain/watertight.hpp>

#include <gtest/gtest.h>

namespace polder::terrain {
namespace {

// The full-resolution triangulation of a width x height grid (two triangles per cell).
TriangleSoup gridSoup(int width, int height) {
  TriangleSoup soup;
  for (int y = 0; y + 1 < height; ++y) {
    for (int x = 0; x + 1 < width; ++x) {
      soup.addTriangle({x, y}, {x + 1, y}, {x, y + 1});
      soup.addTriangle({x + 1, y + 1}, {x, y + 1}, {x + 1, y});
    }
  }
  return soup;
}

TEST(Watertight, AcceptsAGridTriangulationAndABlockMesh) {
  const WatertightReport r = checkWatertight(gridSoup(9, 6), 9, 6, WatertightOptions{500, 3});
  EXPECT_TRUE(r.watertight());
  EXPECT_TRUE(r.coversExactly);
  EXPECT_EQ(r.triangles, 2u * 8 * 5);
  EXPECT_EQ(r.doubledArea, r.expectedDoubledArea);
  EXPECT_GT(r.samplesTested, 400u);

  // A block mesh of stride 2 at an offset, converted to global coordinates.
  BlockMesh mesh;
  mesh.footprint = BlockFootprint{0, 0, 1, 2};
  mesh.cellsX = mesh.cellsY = 2;
  mesh.vertices = {{0, 0}, {2, 0}, {0, 2}, {2, 2}};
  mesh.indices = {0, 1, 2, 3, 2, 1};
  TriangleSoup soup;
  soup.addBlock(mesh);
  EXPECT_TRUE(checkWatertight(soup, 5, 5).watertight());
  EXPECT_FALSE(checkWatertight(soup, 6, 5).watertight());  // does not reach the east border
}

TEST(Watertight, FindsARemovedTriangle) {
  TriangleSoup soup = gridSoup(7, 7);
  // Remove an inner triangle: three open edges, area short.
  soup.indices.erase(soup.indices.begin() + 3 * 20, soup.indices.begin() + 3 * 21);
  const WatertightReport r = checkWatertight(soup, 7, 7, WatertightOptions{2000, 5});
  EXPECT_FALSE(r.watertight());
  EXPECT_FALSE(r.coversExactly);
  EXPECT_EQ(r.openEdges, 3u);
  EXPECT_EQ(r.doubledArea, r.expectedDoubledArea - 1);
  EXPECT_GT(r.samplesUncovered, 0u);

  // A triangle on the border: a border stretch left uncovered.
  TriangleSoup border = gridSoup(7, 7);
  border.indices.erase(border.indices.begin(), border.indices.begin() + 3);
  EXPECT_GT(checkWatertight(border, 7, 7).borderErrors, 0u);
}

TEST(Watertight, FindsATJunction) {
  // The 3 x 3 DEM's square [0,2]^2 cut along its diagonal: one half is one triangle, the other
  // is split at (1, 1), which then lies inside the first half's edge (0,0)-(2,2).
  TriangleSoup soup;
  soup.addTriangle({0, 0}, {2, 2}, {0, 2});  // north-west half, edge (0,0)-(2,2)
  soup.addTriangle({0, 0}, {2, 0}, {1, 1});  // south-east half, split at the edge's midpoint
  soup.addTriangle({2, 0}, {2, 2}, {1, 1});
  const WatertightReport r = checkWatertight(soup, 3, 3);
  EXPECT_FALSE(r.watertight());
  EXPECT_EQ(r.tJunctions, 1u);
  EXPECT_GT(r.openEdges, 0u);
  EXPECT_EQ(r.doubledArea, r.expectedDoubledArea);  // the area alone would not tell
}

TEST(Watertight, FindsAnOverlap) {
  TriangleSoup soup = gridSoup(6, 6);
  // Move one vertex of a triangle over its neighbour: still counter-clockwise, same count.
  TriangleSoup moved = soup;
  moved.points[3 * 12 + 1].x += 1;
  const WatertightReport r = checkWatertight(moved, 6, 6, WatertightOptions{4000, 9});
  EXPECT_FALSE(r.watertight());
  EXPECT_GT(r.samplesOverlapped, 0u);

  // An extra copy of an inner triangle: over-shared edges and too much area.
  TriangleSoup doubled = soup;
  doubled.addTriangle({2, 2}, {3, 2}, {2, 3});
  const WatertightReport d = checkWatertight(doubled, 6, 6, WatertightOptions{4000, 9});
  EXPECT_FALSE(d.watertight());
  EXPECT_EQ(d.overSharedEdges, 3u);
  EXPECT_GT(d.doubledArea, d.expectedDoubledArea);
}

TEST(Watertight, FindsADoubleCoverOfOppositeWinding) {
  // Two complete triangulations of the same square, the second clockwise: every edge is used
  // twice in each direction.
  TriangleSoup soup = gridSoup(4, 4);
  TriangleSoup second = gridSoup(4, 4);
  for (std::size_t t = 0; t < second.indices.size(); t += 3) std::swap(second.indices[t + 1], second.indices[t + 2]);
  const auto base = std::uint32_t(soup.points.size());
  soup.points.insert(soup.points.end(), second.points.begin(), second.points.end());
  for (std::uint32_t i : second.indices) soup.indices.push_back(base + i);
  const WatertightReport r = checkWatertight(soup, 4, 4, WatertightOptions{1000, 2});
  EXPECT_FALSE(r.watertight());
  EXPECT_GT(r.wrongWinding, 0u);
  EXPECT_GT(r.overSharedEdges, 0u);
}

TEST(Watertight, FindsDegenerateFlippedAndOutsideTriangles) {
  TriangleSoup soup = gridSoup(5, 5);
  TriangleSoup degenerate = soup;
  degenerate.addTriangle({0, 0}, {1, 1}, {2, 2});
  EXPECT_EQ(checkWatertight(degenerate, 5, 5).degenerate, 1u);

  TriangleSoup flipped = soup;
  std::swap(flipped.indices[3 * 7 + 1], flipped.indices[3 * 7 + 2]);
  const WatertightReport f = checkWatertight(flipped, 5, 5);
  EXPECT_EQ(f.wrongWinding, 1u);
  EXPECT_GT(f.flippedEdges, 0u);
  EXPECT_FALSE(f.watertight());

  EXPECT_GT(checkWatertight(soup, 4, 5).outsidePoints, 0u);
}

}  // namespace
}  // namespace polder::terrain
