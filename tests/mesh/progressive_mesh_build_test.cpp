// buildProgressiveMesh assembles on a second thread while the builder runs: its sequence
// must equal the builder's steps assembled afterwards, for both builders and with regions,
// and a builder's error must come back as such.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <string>

#include "mesh_test_shapes.hpp"
#include "polder/mesh/cluster_builder.hpp"
#include "polder/mesh/collapse_builder.hpp"
#include "polder/mesh/progressive_mesh.hpp"
#include "polder/mesh/progressive_mesh_build.hpp"

namespace polder::mesh {
namespace {

void expectSameSequence(const ProgressiveMesh& a, const ProgressiveMesh& b) {
  ASSERT_EQ(a.stepCount(), b.stepCount());
  ASSERT_EQ(a.regionCount(), b.regionCount());
  EXPECT_EQ(a.vertices().positions, b.vertices().positions);
  EXPECT_EQ(a.vertices().indices, b.vertices().indices);
  EXPECT_TRUE(std::equal(a.originalVertex().begin(), a.originalVertex().end(), b.originalVertex().begin(),
                         b.originalVertex().end()));
  for (std::uint32_t r = 0; r < a.regionCount(); ++r) {
    const RegionSequence &x = a.region(r), &y = b.region(r);
    ASSERT_EQ(x.levelCount(), y.levelCount()) << "region " << r;
    for (std::uint32_t level = 0; level <= x.levelCount(); ++level) {
      EXPECT_EQ(x.trianglesAt(level), y.trianglesAt(level));
      EXPECT_EQ(x.verticesAt(level), y.verticesAt(level));
      EXPECT_EQ(x.errorAt(level), y.errorAt(level));
    }
    for (std::size_t step = 0; step < x.levelCount(); ++step) {
      const auto cx = x.cornerChanges(step), cy = y.cornerChanges(step);
      ASSERT_EQ(cx.size(), cy.size()) << "region " << r << " step " << step;
      for (std::size_t i = 0; i < cx.size(); ++i) {
        EXPECT_EQ(cx[i].slot, cy[i].slot);
        EXPECT_EQ(cx[i].before, cy[i].before);
        EXPECT_EQ(cx[i].after, cy[i].after);
      }
      ASSERT_EQ(x.borderChanges(step).size(), y.borderChanges(step).size());
    }
    EXPECT_TRUE(std::equal(x.borderVertices().begin(), x.borderVertices().end(), y.borderVertices().begin(),
                           y.borderVertices().end()));
  }
}

TEST(ProgressiveMeshBuild, EqualsTheStepsAssembledAfterwards) {
  const TriangleMesh sphere = test::bumpySphere(40, 60);
  for (std::uint32_t regions : {1u, 6u}) {
    SCOPED_TRACE(std::to_string(regions) + " regions");
    const RegionPartition partition = regions == 1 ? singleRegion() : automaticPartition(sphere.positions, regions);
    // minSteps: long enough to span several handed-over batches.
    auto compare = [&](const auto& options, const auto& buildSteps, std::uint32_t minSteps) {
      auto steps = buildSteps(sphere, partition, options);
      ASSERT_TRUE(steps.ok());
      auto afterwards = ProgressiveMesh::assemble(sphere, partition, *steps);
      auto pipelined = buildProgressiveMesh(sphere, partition, options);
      ASSERT_TRUE(afterwards.ok() && pipelined.ok());
      EXPECT_GT(pipelined->stepCount(), minSteps);
      expectSameSequence(*pipelined, *afterwards);
    };
    compare(
        CollapseOptions{}, [](auto&&... a) { return buildCollapseSteps(a...); }, 1000u);
    compare(
        ClusterOptions{}, [](auto&&... a) { return buildClusterSteps(a...); }, 500u);
  }
}

TEST(ProgressiveMeshBuild, StopsWhereTheBuilderIsToldTo) {
  const TriangleMesh sphere = test::bumpySphere(30, 40);
  CollapseOptions options;
  options.stopAtTriangles = 500;
  auto pipelined = buildProgressiveMesh(sphere, singleRegion(), options);
  ASSERT_TRUE(pipelined.ok());
  EXPECT_LE(pipelined->region(0).trianglesAt(0), 500u);
  EXPECT_GT(pipelined->region(0).trianglesAt(0), 480u);
}

TEST(ProgressiveMeshBuild, ReturnsTheBuildersError) {
  TriangleMesh broken = test::bumpySphere(10, 12);
  broken.positions[3].y = std::numeric_limits<float>::quiet_NaN();
  auto collapse = buildProgressiveMesh(broken, singleRegion(), CollapseOptions{});
  ASSERT_FALSE(collapse.ok());
  EXPECT_NE(collapse.error().message.find("collapse builder input"), std::string::npos) << collapse.error().message;
  auto cluster = buildProgressiveMesh(broken, singleRegion(), ClusterOptions{});
  ASSERT_FALSE(cluster.ok());
  EXPECT_NE(cluster.error().message.find("cluster builder input"), std::string::npos) << cluster.error().message;

  ClusterOptions absurd;
  absurd.cellGrowth = 0.5;
  auto refused = buildProgressiveMesh(test::bumpySphere(10, 12), singleRegion(), absurd);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().message.find("cellGrowth"), std::string::npos);
}

}  // namespace
}  // namespace polder::mesh
