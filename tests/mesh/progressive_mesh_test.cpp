// The multiresolution sequence: built by `collapse`, moved through by instances, split
// into regions that take independent levels without cracks.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>
#include <utility>

#include "mesh_test_shapes.hpp"
#include "mesh_test_topology.hpp"
#include "polder/mesh/collapse_builder.hpp"
#include "polder/mesh/progressive_mesh.hpp"
#include "polder/mesh/progressive_mesh_instance.hpp"

namespace polder::mesh {
namespace {

using test::drawnIndices;
using test::edgeUse;
using test::openEdgeCount;

ProgressiveMesh buildProgressive(const TriangleMesh& mesh, const RegionPartition& partition,
                                 const CollapseOptions& options = {}) {
  auto steps = buildCollapseSteps(mesh, partition, options);
  EXPECT_TRUE(steps.ok()) << (steps.ok() ? "" : steps.error().message);
  auto progressive = ProgressiveMesh::assemble(mesh, partition, *steps);
  EXPECT_TRUE(progressive.ok()) << (progressive.ok() ? "" : progressive.error().message);
  return std::move(progressive).value();
}

TEST(CollapseBuilder, ReachesAFewTrianglesOnAClosedSurface) {
  const TriangleMesh sphere = test::bumpySphere(24, 32);
  const ProgressiveMesh pm = buildProgressive(sphere, singleRegion());
  ASSERT_EQ(pm.regionCount(), 1u);
  const RegionSequence& seq = pm.region(0);
  EXPECT_EQ(seq.trianglesAt(seq.levelCount()), sphere.triangleCount());
  EXPECT_LE(seq.trianglesAt(0), 8u) << "the base mesh of a sphere should be near a tetrahedron";
  EXPECT_EQ(seq.levelCount(), pm.stepCount());
  // Counts and errors are monotone in the level.
  for (std::uint32_t level = 0; level < seq.levelCount(); ++level) {
    EXPECT_LE(seq.trianglesAt(level), seq.trianglesAt(level + 1));
    EXPECT_LE(seq.verticesAt(level), seq.verticesAt(level + 1));
    EXPECT_GE(seq.errorAt(level), seq.errorAt(level + 1));
  }
  EXPECT_EQ(seq.errorAt(seq.levelCount()), 0.0f);
  EXPECT_GT(seq.errorAt(0), 0.0f);
}

TEST(ProgressiveMeshInstance, CostIsProportionalToTheChange) {
  const TriangleMesh sphere = test::bumpySphere(20, 24);
  const ProgressiveMesh pm = buildProgressive(sphere, singleRegion());
  const RegionSequence& seq = pm.region(0);
  ProgressiveMeshInstance instance(pm);
  instance.setLevel(0, seq.levelCount() / 2);
  const std::uint64_t start = instance.writes();
  instance.setLevel(0, seq.levelCount() / 2 + 1);
  const std::uint64_t oneStep = instance.writes() - start;
  EXPECT_EQ(oneStep, seq.cornerChanges(seq.levelCount() - seq.levelCount() / 2 - 1).size());
  EXPECT_LE(oneStep, 16u) << "one half-edge collapse touches one vertex's fan";
  // Down and back up writes the same corners twice.
  const std::uint64_t beforeTrip = instance.writes();
  instance.setLevel(0, 10);
  const std::uint64_t down = instance.writes() - beforeTrip;
  instance.setLevel(0, seq.levelCount() / 2 + 1);
  EXPECT_EQ(instance.writes() - beforeTrip, 2 * down);
  // Staying put costs nothing.
  const std::uint64_t still = instance.writes();
  instance.setLevel(0, instance.level(0));
  instance.resolveBorders();
  EXPECT_EQ(instance.writes(), still);
}

TEST(Regions, StepsNeverJoinTwoRegionsAndBordersFollowTheNeighbour) {
  const TriangleMesh grid = test::bumpyGrid(30);
  const RegionPartition partition = gridPartition(grid.positions, {3, 3, 1});
  ASSERT_EQ(partition.regionCount, 9u);
  const ProgressiveMesh pm = buildProgressive(grid, partition);
  // Each region's vertices are a contiguous range and its steps stay inside it.
  for (std::uint32_t r = 0; r < pm.regionCount(); ++r) {
    const RegionSequence& seq = pm.region(r);
    for (std::uint32_t v = seq.vertexBegin(); v < seq.vertexEnd(); ++v) ASSERT_EQ(pm.regionOfVertex()[v], r);
    for (std::size_t step = 0; step < seq.levelCount(); ++step)
      for (const CornerChange& c : seq.cornerChanges(step)) {
        ASSERT_EQ(pm.regionOfVertex()[c.before], r);
        ASSERT_EQ(pm.regionOfVertex()[c.after], r);
      }
  }
  // Coarsening one region moves its neighbours' border triangles onto its representatives.
  ProgressiveMeshInstance instance(pm);
  const std::uint32_t centre = 4;
  instance.setLevel(centre, 0);
  instance.resolveBorders();
  const std::uint32_t centreBase = pm.region(centre).verticesAt(0);
  std::size_t centreVerticesSeen = 0;
  for (std::uint32_t r = 0; r < pm.regionCount(); ++r) {
    if (r == centre) continue;
    for (std::uint32_t v : instance.indices(r)) {
      if (pm.regionOfVertex()[v] != centre) continue;
      ++centreVerticesSeen;
      ASSERT_LT(v - pm.region(centre).vertexBegin(), centreBase) << "a border triangle uses a removed vertex";
    }
  }
  EXPECT_GT(centreVerticesSeen, 0u);
  // Open edges stay on the grid's outline whatever the mix of levels.
  std::mt19937 random(5);
  const auto& p = pm.vertices().positions;
  for (int trial = 0; trial < 40; ++trial) {
    for (std::uint32_t r = 0; r < pm.regionCount(); ++r)
      instance.setLevel(r, std::uniform_int_distribution<std::uint32_t>(0, pm.region(r).levelCount())(random));
    instance.resolveBorders();
    for (const auto& [edge, count] : edgeUse(drawnIndices(instance))) {
      ASSERT_LE(count, 2);
      if (count == 1) {
        const glm::vec3 a = p[edge.first], b = p[edge.second];
        const bool sameSide =
            (a.x == 0 && b.x == 0) || (a.y == 0 && b.y == 0) || (a.x == 1 && b.x == 1) || (a.y == 1 && b.y == 1);
        ASSERT_TRUE(sameSide) << "trial " << trial << ": an open edge inside the grid";
      }
    }
  }
}

TEST(ProgressiveMesh, RejectsStepsThatBreakTheRules) {
  const TriangleMesh grid = test::bumpyGrid(4);
  RegionPartition two = gridPartition(grid.positions, {2, 1, 1});
  SimplificationSteps steps;
  const std::uint32_t removedTwice[1] = {1};
  steps.add(0, removedTwice, 0.1f);
  steps.add(2, removedTwice, 0.2f);
  auto result = ProgressiveMesh::assemble(grid, singleRegion(), steps);
  ASSERT_FALSE(result.ok());
  EXPECT_NE(result.error().message.find("not active"), std::string::npos);

  SimplificationSteps crossing;
  const std::uint32_t farVertex[1] = {4};  // x = 1, the other region
  crossing.add(0, farVertex, 0.1f);
  result = ProgressiveMesh::assemble(grid, two, crossing);
  ASSERT_FALSE(result.ok());
  EXPECT_NE(result.error().message.find("two regions"), std::string::npos);

  // A vertex may only go onto an active vertex of its region that stays in the step.
  SimplificationSteps ontoRemoved;
  const std::uint32_t first[1] = {1}, second[2] = {2, 3}, ontoFirst[2] = {0, 1};
  ontoRemoved.add(0, first, 0.1f);
  ontoRemoved.add(0, second, ontoFirst, 0.2f);
  result = ProgressiveMesh::assemble(grid, singleRegion(), ontoRemoved);
  ASSERT_FALSE(result.ok());
  EXPECT_NE(result.error().message.find("goes onto vertex 1, which is not active"), std::string::npos)
      << result.error().message;
  SimplificationSteps ontoRemovedTogether;
  const std::uint32_t pair[2] = {2, 1}, ontoEachOther[2] = {1, 0};
  ontoRemovedTogether.add(0, pair, ontoEachOther, 0.1f);
  result = ProgressiveMesh::assemble(grid, singleRegion(), ontoRemovedTogether);
  ASSERT_FALSE(result.ok());
  EXPECT_NE(result.error().message.find("removed and takes a place"), std::string::npos) << result.error().message;
  SimplificationSteps ontoFar;
  const std::uint32_t near[1] = {1}, far[1] = {4};
  ontoFar.add(0, near, far, 0.1f);
  result = ProgressiveMesh::assemble(grid, two, ontoFar);
  ASSERT_FALSE(result.ok());
  EXPECT_NE(result.error().message.find("two regions"), std::string::npos);

  SimplificationSteps outOfRange;
  const std::uint32_t missing[1] = {999};
  outOfRange.add(0, missing, 0.1f);
  EXPECT_FALSE(ProgressiveMesh::assemble(grid, singleRegion(), outOfRange).ok());
}

}  // namespace
}  // namespace polder::mesh
