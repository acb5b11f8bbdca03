// Region partitions (ASLOD regions): every vertex in exactly one dense region id, and costs
// that follow the vertices whatever the number of regions or grid cells asked for.
#include <gtest/gtest.h>

#include <set>

#include <polder/mesh/region_partition.hpp>

#include "mesh_test_shapes.hpp"

namespace polder::mesh {
namespace {

// Dense ids: every id below regionCount holds a vertex.
void expectDense(const RegionPartition& partition, std::size_t vertexCount) {
  ASSERT_TRUE(validatePartition(partition, vertexCount, "partition").ok());
  const std::set<std::uint32_t> used(partition.vertexRegion.begin(), partition.vertexRegion.end());
  EXPECT_EQ(used.size(), partition.regionCount);
}

TEST(RegionPartition, GridRegionsFollowCellOrderAndDropEmptyCells) {
  // Eight vertices on a line along x, cut in four: two per cell, ids in x order.
  std::vector<glm::vec3> positions;
  for (int i = 0; i < 8; ++i) positions.push_back({float(i), 0.0f, 0.0f});
  const RegionPartition four = gridPartition(positions, {4, 1, 1});
  ASSERT_EQ(four.regionCount, 4u);
  for (std::uint32_t v = 0; v < 8; ++v) EXPECT_EQ(four.regionOf(v), v / 2) << v;
  // Sixteen cells for eight vertices: no more regions than vertices, none empty.
  const RegionPartition sixteen = gridPartition(positions, {16, 1, 1});
  EXPECT_EQ(sixteen.regionCount, 8u);
  expectDense(sixteen, positions.size());
}

// Grids and counts far beyond the mesh (a million cells per axis, a billion regions) neither
// allocate per cell nor loop: the answer has at most one region per vertex.
TEST(RegionPartition, AbsurdCountsCostNoMoreThanTheVertices) {
  const TriangleMesh sphere = test::bumpySphere(10, 12);
  const std::size_t vertices = sphere.positions.size();
  const RegionPartition grid = gridPartition(sphere.positions, {1000000, 1000000, 1000000});
  EXPECT_LE(grid.regionCount, vertices);
  expectDense(grid, vertices);
  for (const std::uint32_t count : {std::uint32_t(vertices), 3000u, 1000000000u}) {
    const RegionPartition automatic = automaticPartition(sphere.positions, count);
    EXPECT_LE(automatic.regionCount, vertices) << count;
    EXPECT_GT(automatic.regionCount, vertices / 4) << count;  // refined, not given up
    expectDense(automatic, vertices);
  }
  EXPECT_EQ(automaticPartition({}, 50).regionCount, 1u);
  EXPECT_EQ(automaticPartition(std::vector<glm::vec3>(3, glm::vec3(1.0f)), 50).regionCount, 1u);
}

}  // namespace
}  // namespace polder::mesh
