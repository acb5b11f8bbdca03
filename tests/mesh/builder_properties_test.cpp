// What every builder's sequence must give, checked for `collapse` and `cluster` alike:
// closed levels over original, active vertices; no step flips a triangle; a level is the
// same whatever path led to it; regions at independent levels add no open edges; the
// input's vertex numbering and triangle order do not change the steps.
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <numeric>
#include <random>
#include <string>

#include "mesh_test_shapes.hpp"
#include "mesh_test_topology.hpp"
#include "polder/mesh/cluster_builder.hpp"
#include "polder/mesh/collapse_builder.hpp"
#include "polder/mesh/mesh_extraction.hpp"
#include "polder/mesh/progressive_mesh.hpp"
#include "polder/mesh/progressive_mesh_instance.hpp"

namespace polder::mesh {
namespace {

using test::drawnIndices;
using test::edgeUse;
using test::foldedPairCount;
using test::openEdgeCount;
using test::triangleNormal;

// Whether q lies on the outline of the unit square that test::bumpyGrid spans.
bool onUnitSquareOutline(const glm::vec3& q) { return q.x == 0.0f || q.y == 0.0f || q.x == 1.0f || q.y == 1.0f; }

struct Builder {
  std::string name;
  std::function<Result<SimplificationSteps>(const TriangleMesh&, const RegionPartition&)> build;
};

class BuilderProperties : public ::testing::TestWithParam<Builder> {
 protected:
  ProgressiveMesh progressive(const TriangleMesh& mesh, const RegionPartition& partition) const {
    auto steps = GetParam().build(mesh, partition);
    EXPECT_TRUE(steps.ok()) << (steps.ok() ? "" : steps.error().message);
    for (std::size_t s = 0; steps.ok() && s < steps->size(); ++s)
      for (std::uint32_t v : steps->removedBy(s))
        EXPECT_EQ(partition.regionOf(v), partition.regionOf(steps->representative[s])) << "step " << s;
    auto assembled = ProgressiveMesh::assemble(mesh, partition, *steps);
    EXPECT_TRUE(assembled.ok()) << (assembled.ok() ? "" : assembled.error().message);
    return std::move(assembled).value();
  }
};

TEST_P(BuilderProperties, EveryLevelIsClosedAndUsesActiveOriginalVertices) {
  const TriangleMesh sphere = test::bumpySphere(20, 26);
  const ProgressiveMesh pm = progressive(sphere, singleRegion());
  ProgressiveMeshInstance instance(pm);
  const RegionSequence& seq = pm.region(0);
  EXPECT_LE(seq.trianglesAt(0), 16u) << "a sphere's base mesh should be a handful of triangles";
  for (std::uint32_t level = seq.levelCount() + 1; level-- > 0;) {
    instance.setLevel(0, level);
    instance.resolveBorders();
    const auto indices = drawnIndices(instance);
    ASSERT_EQ(indices.size(), 3 * std::size_t(seq.trianglesAt(level)));
    // Every edge keeps exactly two triangles: no holes, and no step pinches the surface.
    for (const auto& [edge, count] : edgeUse(indices)) ASSERT_EQ(count, 2) << "level " << level;
    for (std::uint32_t v : indices) {
      ASSERT_LT(v, seq.verticesAt(level)) << "level " << level << " uses a vertex outside its active prefix";
      ASSERT_EQ(pm.vertices().positions[v], sphere.positions[pm.originalVertex()[v]]);
    }
    if (level < seq.levelCount()) {
      ASSERT_LE(seq.trianglesAt(level), seq.trianglesAt(level + 1));
      ASSERT_GE(seq.errorAt(level), seq.errorAt(level + 1));
    }
  }
}

TEST_P(BuilderProperties, NoStepFlipsATriangle) {
  // The bicone's two apexes of valence 300 take the builders' path for fans too large to scan.
  for (const TriangleMesh& mesh : {test::bumpySphere(16, 20), test::bumpyGrid(24, 0.3f), test::bumpySphere(2, 300)}) {
    const ProgressiveMesh pm = progressive(mesh, singleRegion());
    const RegionSequence& seq = pm.region(0);
    ProgressiveMeshInstance instance(pm);
    const auto& p = pm.vertices().positions;
    for (std::uint32_t level = seq.levelCount(); level > 0; --level) {
      const std::vector<std::uint32_t> before(instance.indices(0).begin(), instance.indices(0).end());
      instance.setLevel(0, level - 1);
      const auto after = instance.indices(0);
      for (std::size_t t = 0; t < after.size(); t += 3) {
        if (std::equal(after.begin() + t, after.begin() + t + 3, before.begin() + t)) continue;
        ASSERT_GT(glm::dot(triangleNormal(p, before, t), triangleNormal(p, after, t)), 0.0)
            << "step to level " << level - 1 << " flips triangle " << t / 3;
      }
    }
  }
}

// Two apexes of valence 300 (one ring between the poles): every level stays closed on the
// builders' path for fans too large to scan (NoStepFlipsATriangle walks it too).
TEST_P(BuilderProperties, HighValenceApexesKeepEveryLevelClosed) {
  const TriangleMesh bicone = test::bumpySphere(2, 300);
  const ProgressiveMesh pm = progressive(bicone, singleRegion());
  const RegionSequence& seq = pm.region(0);
  EXPECT_LE(seq.trianglesAt(0), 16u);
  ProgressiveMeshInstance instance(pm);
  for (std::uint32_t level = seq.levelCount(); level > 0; --level) {
    instance.setLevel(0, level - 1);
    for (const auto& [edge, count] : edgeUse(drawnIndices(instance))) ASSERT_EQ(count, 2) << "level " << level - 1;
  }
}

TEST_P(BuilderProperties, SameLevelSameTrianglesWhateverThePath) {
  const TriangleMesh sphere = test::bumpySphere(14, 18);
  const RegionPartition partition = automaticPartition(sphere.positions, 4);
  const ProgressiveMesh pm = progressive(sphere, partition);
  std::mt19937 random(7);
  ProgressiveMeshInstance walker(pm);
  for (int move = 0; move < 60; ++move) {
    ProgressiveMeshInstance fresh(pm);
    for (std::uint32_t r = 0; r < pm.regionCount(); ++r) {
      const std::uint32_t level = std::uniform_int_distribution<std::uint32_t>(0, pm.region(r).levelCount())(random);
      walker.setLevel(r, level);
      fresh.setLevel(r, level);
    }
    walker.resolveBorders();
    fresh.resolveBorders();
    ASSERT_EQ(drawnIndices(walker), drawnIndices(fresh)) << "move " << move;
  }
}

TEST_P(BuilderProperties, RegionsAtIndependentLevelsAddNoOpenEdges) {
  const TriangleMesh sphere = test::bumpySphere(24, 30);
  const RegionPartition partition = automaticPartition(sphere.positions, 12);
  ASSERT_GE(partition.regionCount, 12u);
  const ProgressiveMesh pm = progressive(sphere, partition);
  ASSERT_EQ(pm.regionCount(), partition.regionCount);
  std::size_t borderCorners = 0;
  for (std::uint32_t r = 0; r < pm.regionCount(); ++r) borderCorners += pm.region(r).foreignCorners().size();
  ASSERT_GT(borderCorners, 0u) << "regions must share border triangles";
  std::mt19937 random(11);
  ProgressiveMeshInstance instance(pm);
  for (int trial = 0; trial < 80; ++trial) {
    for (std::uint32_t r = 0; r < pm.regionCount(); ++r)
      instance.setLevel(r, std::uniform_int_distribution<std::uint32_t>(0, pm.region(r).levelCount())(random));
    instance.resolveBorders();
    const auto indices = drawnIndices(instance);
    ASSERT_EQ(openEdgeCount(test::withoutDegenerate(indices)), 0u) << "trial " << trial;
    // No fin: a neighbour's step that folds two border triangles back to back leaves
    // them flattened (drawn as nothing: a wrongly flattened one would open edges above).
    ASSERT_EQ(foldedPairCount(indices), 0u) << "trial " << trial;
  }
}

// A region one edge wide inside another: its border triangles lie back to back on its
// edges, and once the surrounding region has joined the far corners (it did so while the
// strip was coarser) they would coincide. Every pair of levels: no fin, no open edge, and
// the same triangles at a pair of levels whatever the path.
TEST_P(BuilderProperties, ARegionOneEdgeWideNeverFolds) {
  const std::uint32_t n = 12;
  const TriangleMesh grid = test::bumpyGrid(n, 0.02f);
  RegionPartition partition{2, std::vector<std::uint32_t>(grid.vertexCount(), 1)};
  for (std::uint32_t i = 0; i < 4; ++i) partition.vertexRegion[(n / 2) * (n + 1) + n / 2 - 2 + i] = 0;
  const ProgressiveMesh pm = progressive(grid, partition);
  const auto& p = pm.vertices().positions;
  auto onOutline = [&](std::uint32_t v) { return onUnitSquareOutline(p[v]); };
  ProgressiveMeshInstance instance(pm), fresh(pm);
  std::size_t flattened = 0;
  // Region 1 steps through its levels and, at each, the strip through all of its own: the
  // strip's own moves alone can fold a pair too.
  for (std::uint32_t around = 0; around <= pm.region(1).levelCount(); ++around)
    for (std::uint32_t strip = 0; strip <= pm.region(0).levelCount(); ++strip) {
      instance.setLevel(1, around);
      instance.setLevel(0, strip);
      instance.resolveBorders();
      const auto indices = drawnIndices(instance);
      ASSERT_EQ(foldedPairCount(indices), 0u) << "levels " << strip << ", " << around;
      for (const auto& [edge, count] : edgeUse(test::withoutDegenerate(indices)))
        ASSERT_TRUE(count == 2 || (count == 1 && onOutline(edge.first) && onOutline(edge.second)))
            << "levels " << strip << ", " << around << ": edge used " << count << " times";
      for (std::size_t t = 0; t < indices.size(); t += 3) flattened += test::isDegenerate(indices, t);
      fresh.setLevel(0, strip);  // the other way round: the strip first, and every time
      fresh.setLevel(1, around);
      fresh.resolveBorders();
      ASSERT_EQ(drawnIndices(fresh), indices) << "levels " << strip << ", " << around;
    }
  EXPECT_GT(flattened, 0u) << "the strip should have folded somewhere: the test lost its case";
}

TEST_P(BuilderProperties, OpenBoundaryStaysOnTheOriginalOutline) {
  const TriangleMesh grid = test::bumpyGrid(20);
  const ProgressiveMesh pm = progressive(grid, singleRegion());
  ProgressiveMeshInstance instance(pm);
  const auto& p = pm.vertices().positions;
  for (std::uint32_t level : {0u, 5u, 40u, pm.region(0).levelCount() / 2}) {
    instance.setLevel(0, level);
    for (const auto& [edge, count] : edgeUse(drawnIndices(instance))) {
      ASSERT_LE(count, 2);
      if (count == 1) {
        EXPECT_TRUE(onUnitSquareOutline(p[edge.first]) && onUnitSquareOutline(p[edge.second])) << "level " << level;
      }
    }
  }
  // The surface never vanishes whole: the base keeps at least one triangle.
  EXPECT_GE(pm.region(0).trianglesAt(0), 1u);
}

TEST_P(BuilderProperties, StepsDoNotDependOnTheInputsNumbering) {
  // The same coloured surface (with a texture seam) cut into regions, with its vertices
  // renumbered, its triangles reordered and their corners turned: the same steps, renamed,
  // with the same errors.
  TriangleMesh sphere = test::seamedSphere(24, 28);  // large enough for the cluster builder's rounds
  for (const glm::vec3& p : sphere.positions)
    sphere.colours.emplace_back(p.x > 0.3f ? 1.0f : 0.2f, 0.5f + 0.4f * p.z, 0.3f, 1.0f);
  const RegionPartition partition = automaticPartition(sphere.positions, 4);
  ASSERT_GE(partition.regionCount, 4u);
  std::mt19937 random(5);
  std::vector<std::uint32_t> newId(sphere.vertexCount());
  std::iota(newId.begin(), newId.end(), 0u);
  std::shuffle(newId.begin(), newId.end(), random);
  TriangleMesh shuffled;
  shuffled.positions.resize(sphere.vertexCount());
  shuffled.colours.resize(sphere.vertexCount());
  shuffled.uvs.resize(sphere.vertexCount());
  RegionPartition shuffledPartition{partition.regionCount, std::vector<std::uint32_t>(sphere.vertexCount())};
  for (std::uint32_t v = 0; v < sphere.vertexCount(); ++v) {
    shuffled.positions[newId[v]] = sphere.positions[v];
    shuffled.colours[newId[v]] = sphere.colours[v];
    shuffled.uvs[newId[v]] = sphere.uvs[v];
    shuffledPartition.vertexRegion[newId[v]] = partition.vertexRegion[v];
  }
  std::vector<std::uint32_t> triangleOrder(sphere.triangleCount());
  std::iota(triangleOrder.begin(), triangleOrder.end(), 0u);
  std::shuffle(triangleOrder.begin(), triangleOrder.end(), random);
  for (std::uint32_t t : triangleOrder) {
    const int turn = int(t % 3);
    for (int k = 0; k < 3; ++k) shuffled.indices.push_back(newId[sphere.indices[3 * t + (k + turn) % 3]]);
  }
  const auto original = GetParam().build(sphere, partition);
  const auto renumbered = GetParam().build(shuffled, shuffledPartition);
  ASSERT_TRUE(original.ok() && renumbered.ok());
  ASSERT_GT(original->size(), sphere.vertexCount() / 8);
  ASSERT_EQ(original->size(), renumbered->size());
  for (std::size_t s = 0; s < original->size(); ++s) {
    ASSERT_EQ(newId[original->representative[s]], renumbered->representative[s]) << "step " << s;
    ASSERT_EQ(original->error[s], renumbered->error[s]) << "step " << s;
    const auto a = original->removedBy(s), b = renumbered->removedBy(s);
    const auto aOnto = original->ontoBy(s), bOnto = renumbered->ontoBy(s);
    ASSERT_EQ(a.size(), b.size()) << "step " << s;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> renamed, other;
    for (std::size_t i = 0; i < a.size(); ++i) renamed.emplace_back(newId[a[i]], newId[aOnto[i]]);
    for (std::size_t i = 0; i < b.size(); ++i) other.emplace_back(b[i], bOnto[i]);
    std::sort(renamed.begin(), renamed.end());
    std::sort(other.begin(), other.end());
    ASSERT_EQ(renamed, other) << "step " << s;
  }
}

// A texture seam splits the surface's vertices in two along a line; whatever levels the
// regions take, the two sides still meet (the surface, welded by position, stays closed),
// with no sliver left between them, and every corner keeps its own side's UVs. The
// builders move the seam's twins together, so the seam coarsens too; twins that regions
// given per vertex put apart never move.
TEST_P(BuilderProperties, TextureSeamNeverOpens) {
  const std::uint32_t rings = 24, segments = 28;  // large enough for the cluster builder's rounds
  const TriangleMesh sphere = test::seamedSphere(rings, segments);
  const std::uint32_t seamVertices = 2 * (rings - 1);
  auto onSeam = [](const glm::vec3& p) { return p.y == 0.0f && p.x > 0.0f; };
  RegionPartition twinsApart{2, std::vector<std::uint32_t>(sphere.vertexCount(), 0)};
  for (auto v = static_cast<std::uint32_t>(sphere.vertexCount()) - seamVertices / 2; v < sphere.vertexCount(); ++v)
    twinsApart.vertexRegion[v] = 1;  // the seam's west copies, added last
  {
    const auto steps = GetParam().build(sphere, twinsApart);
    ASSERT_TRUE(steps.ok());
    EXPECT_GT(steps->removed.size(), sphere.vertexCount() / 2) << "the rest still simplifies";
    for (std::uint32_t v : steps->removed) ASSERT_FALSE(onSeam(sphere.positions[v])) << "a twin moved without its twin";
  }
  for (std::uint32_t regions : {1u, 6u, 2u}) {
    const RegionPartition partition = regions == 1   ? singleRegion()
                                      : regions == 2 ? twinsApart
                                                     : automaticPartition(sphere.positions, regions);
    const ProgressiveMesh pm = progressive(sphere, partition);
    const auto& positions = pm.vertices().positions;
    std::mt19937 random(regions);
    ProgressiveMeshInstance instance(pm);
    for (int trial = 0; trial < 40; ++trial) {
      for (std::uint32_t r = 0; r < pm.regionCount(); ++r) {
        const std::uint32_t levels = pm.region(r).levelCount();
        instance.setLevel(r, trial == 0 ? 0 : std::uniform_int_distribution<std::uint32_t>(0, levels)(random));
      }
      instance.resolveBorders();
      const auto drawn = drawnIndices(instance);
      const auto welded = indicesWeldedByPosition(drawn, positions);
      ASSERT_EQ(openEdgeCount(test::withoutDegenerate(welded)), 0u) << regions << " regions, trial " << trial;
      ASSERT_EQ(foldedPairCount(drawn), 0u) << regions << " regions, trial " << trial;
      for (std::size_t t = 0; t < welded.size(); t += 3)
        ASSERT_TRUE(test::isDegenerate(drawn, t) || !test::isDegenerate(welded, t))
            << regions << " regions, trial " << trial << ": a sliver between the seam's sides";
    }
    for (std::uint32_t v = 0; v < pm.vertices().vertexCount(); ++v)
      ASSERT_EQ(pm.vertices().uvs[v], sphere.uvs[pm.originalVertex()[v]]);
    if (regions > 1) continue;
    // Seam vertices left at the base level.
    instance.setLevel(0, 0);
    std::uint32_t seamLeft = 0;
    for (std::uint32_t v = 0; v < pm.region(0).verticesAt(0); ++v) seamLeft += onSeam(positions[v]);
    EXPECT_LT(seamLeft, seamVertices / 3) << "the seam should coarsen";
  }
}

void PrintTo(const Builder& builder, std::ostream* out) { *out << builder.name; }

// Two closed surfaces touching at one vertex (a pinch), and a sphere with one triangle
// wound against the others: the vertices whose fan is not one consistently wound disk
// keep their place; the rest of the surface still simplifies.
TEST_P(BuilderProperties, APinchOrAFlippedTriangleKeepsItsVertices) {
  // The upper sphere's south pole (its last vertex, at z = -1) is the lower one's north pole.
  TriangleMesh pinched = test::bumpySphere(12, 16);
  const auto upperCount = static_cast<std::uint32_t>(pinched.vertexCount());
  const std::uint32_t pinch = upperCount - 1;
  TriangleMesh lower = test::bumpySphere(12, 16);
  for (glm::vec3& p : lower.positions) p.z -= 2.0f;
  pinched.positions.insert(pinched.positions.end(), lower.positions.begin() + 1, lower.positions.end());
  for (std::uint32_t i : lower.indices) pinched.indices.push_back(i == 0 ? pinch : upperCount + i - 1);
  {
    auto steps = GetParam().build(pinched, singleRegion());
    ASSERT_TRUE(steps.ok());
    EXPECT_GT(steps->removed.size(), pinched.vertexCount() / 2) << "the rest still simplifies";
    EXPECT_EQ(std::count(steps->removed.begin(), steps->removed.end(), pinch), 0) << "the pinch moved";
  }

  TriangleMesh flipped = test::bumpySphere(12, 16);
  const std::size_t t = flipped.triangleCount() / 2;
  std::swap(flipped.indices[3 * t + 1], flipped.indices[3 * t + 2]);
  auto steps = GetParam().build(flipped, singleRegion());
  ASSERT_TRUE(steps.ok());
  EXPECT_GT(steps->removed.size(), flipped.vertexCount() / 2);
  for (int k = 0; k < 3; ++k)
    EXPECT_EQ(std::count(steps->removed.begin(), steps->removed.end(), flipped.indices[3 * t + k]), 0)
        << "a corner of the flipped triangle moved";
}

INSTANTIATE_TEST_SUITE_P(
    Builders, BuilderProperties,
    ::testing::Values(
        Builder{"collapse", [](const TriangleMesh& m, const RegionPartition& p) { return buildCollapseSteps(m, p); }},
        Builder{"cluster", [](const TriangleMesh& m, const RegionPartition& p) { return buildClusterSteps(m, p); }}),
    [](const ::testing::TestParamInfo<Builder>& info) { return info.param.name; });

}  // namespace
}  // namespace polder::mesh
