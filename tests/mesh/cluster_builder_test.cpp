// Builder `cluster` (Chuang 2001, part A): floating-cell vertex
// clustering into a progressive mesh that keeps sharp features and colour borders.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <span>
#include <utility>

#include "mesh_test_shapes.hpp"
#include "mesh_test_topology.hpp"
#include "polder/closest_point_triangle.hpp"
#include "polder/mesh/cluster_builder.hpp"
#include "polder/mesh/progressive_mesh.hpp"
#include "polder/mesh/progressive_mesh_instance.hpp"

namespace polder::mesh {
namespace {

using test::openEdgeCount;
using test::triangleNormal;

SimplificationSteps clusterSteps(const TriangleMesh& mesh, const RegionPartition& partition,
                                 const ClusterOptions& options = {}) {
  auto steps = buildClusterSteps(mesh, partition, options);
  EXPECT_TRUE(steps.ok()) << (steps.ok() ? "" : steps.error().message);
  return steps.ok() ? std::move(steps).value() : SimplificationSteps{};
}

ProgressiveMesh buildProgressive(const TriangleMesh& mesh, const RegionPartition& partition,
                                 const ClusterOptions& options = {}) {
  const SimplificationSteps steps = clusterSteps(mesh, partition, options);
  auto progressive = ProgressiveMesh::assemble(mesh, partition, steps);
  EXPECT_TRUE(progressive.ok()) << (progressive.ok() ? "" : progressive.error().message);
  return std::move(progressive).value();
}

double distanceToTriangles(const glm::dvec3& q, const std::vector<glm::vec3>& p, std::span<const std::uint32_t> idx) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t t = 0; t < idx.size(); t += 3) {
    const glm::dvec3 a(p[idx[t]]), b(p[idx[t + 1]]), c(p[idx[t + 2]]);
    best = std::min(best, glm::length(q - closestPointOnTriangle(q, a, b, c).point));
  }
  return best;
}

// A sheet folded along x = 0.5: the planes z = |x - 0.5| meet at a right angle, crease
// on grid edges (n even).
TriangleMesh foldedSheet(std::uint32_t n) {
  TriangleMesh sheet = test::bumpyGrid(n, 0.0f);
  for (glm::vec3& p : sheet.positions) p.z = std::abs(p.x - 0.5f);
  return sheet;
}

// The surface of the unit cube, each face an n x n grid, vertices shared along edges.
TriangleMesh subdividedBox(std::uint32_t n) {
  TriangleMesh box;
  std::map<std::array<std::uint32_t, 3>, std::uint32_t> vertexAt;
  auto vertex = [&](std::array<std::uint32_t, 3> lattice) {
    auto [it, inserted] = vertexAt.try_emplace(lattice, static_cast<std::uint32_t>(box.positions.size()));
    if (inserted)
      box.positions.emplace_back(float(lattice[0]) / float(n), float(lattice[1]) / float(n),
                                 float(lattice[2]) / float(n));
    return it->second;
  };
  for (int axis = 0; axis < 3; ++axis)
    for (std::uint32_t side = 0; side < 2; ++side) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      for (std::uint32_t j = 0; j < n; ++j)
        for (std::uint32_t i = 0; i < n; ++i) {
          auto at = [&](std::uint32_t di, std::uint32_t dj) {
            std::array<std::uint32_t, 3> l{};
            l[axis] = side * n;
            l[u] = i + di;
            l[v] = j + dj;
            return vertex(l);
          };
          const std::uint32_t a = at(0, 0), b = at(1, 0), c = at(0, 1), d = at(1, 1);
          // Counter-clockwise seen from outside: u x v points along +axis.
          if (side == 1)
            box.indices.insert(box.indices.end(), {a, b, d, a, d, c});
          else
            box.indices.insert(box.indices.end(), {a, d, b, a, c, d});
        }
    }
  return box;
}

TEST(ClusterBuilder, GathersSeveralVerticesPerStepDownToAFewTriangles) {
  const TriangleMesh sphere = test::bumpySphere(24, 32);
  const SimplificationSteps steps = clusterSteps(sphere, singleRegion());
  ASSERT_GT(steps.size(), 0u);
  for (std::size_t s = 0; s < steps.size(); ++s) {
    ASSERT_GE(steps.removedBy(s).size(), 1u) << "step " << s << " gathers nothing";
    ASSERT_TRUE(std::isfinite(steps.error[s]) && steps.error[s] >= 0.0f) << "step " << s;
  }
  // The paper reports 4 to 20 triangles clustered per level: several vertices per step
  // (about 2 on this small sphere, 3 on finer meshes).
  const double verticesPerStep = double(steps.removed.size()) / double(steps.size());
  EXPECT_GT(verticesPerStep, 1.6);

  auto assembled = ProgressiveMesh::assemble(sphere, singleRegion(), steps);
  ASSERT_TRUE(assembled.ok()) << assembled.error().message;
  const RegionSequence& seq = assembled->region(0);
  EXPECT_EQ(seq.trianglesAt(seq.levelCount()), sphere.triangleCount());
  EXPECT_LE(seq.trianglesAt(0), 16u) << "a closed sphere should shrink to a handful of triangles";
  for (std::uint32_t level = 0; level < seq.levelCount(); ++level) {
    EXPECT_LE(seq.trianglesAt(level), seq.trianglesAt(level + 1));
    EXPECT_LT(seq.verticesAt(level), seq.verticesAt(level + 1));
    EXPECT_GE(seq.errorAt(level), seq.errorAt(level + 1));
  }
  EXPECT_EQ(seq.errorAt(seq.levelCount()), 0.0f);
  EXPECT_GT(seq.errorAt(0), 0.0f);
}

TEST(ClusterBuilder, GridCornersStayToTheBase) {
  const TriangleMesh grid = test::bumpyGrid(20);
  const ProgressiveMesh pm = buildProgressive(grid, singleRegion());
  const auto& p = pm.vertices().positions;
  // Corners never join: the four grid corners are in the base mesh.
  int cornersKept = 0;
  for (std::uint32_t v = 0; v < pm.region(0).verticesAt(0); ++v) {
    const glm::vec3 q = p[v];
    cornersKept += (q.x == 0.0f || q.x == 1.0f) && (q.y == 0.0f || q.y == 1.0f);
  }
  EXPECT_EQ(cornersKept, 4);
  EXPECT_GE(pm.region(0).trianglesAt(0), 2u);
}

// Triangles of `idx` whose normal is neither plane's of the folded sheet, and the largest
// distance from the crease line to the triangles.
std::pair<int, double> creaseDamage(const std::vector<glm::vec3>& p, std::span<const std::uint32_t> idx) {
  const glm::dvec3 left = glm::normalize(glm::dvec3(1, 0, 1)), right = glm::normalize(glm::dvec3(-1, 0, 1));
  int bridging = 0;
  for (std::size_t t = 0; t < idx.size(); t += 3) {
    const glm::dvec3 n = triangleNormal(p, idx, t);
    bridging += std::max(glm::dot(n, left), glm::dot(n, right)) < 0.999 * glm::length(n);
  }
  double worst = 0.0;
  for (int i = 0; i <= 100; ++i) worst = std::max(worst, distanceToTriangles(glm::dvec3(0.5, i / 100.0, 0.0), p, idx));
  return {bridging, worst};
}

TEST(ClusterBuilder, ACreaseStaysSharpAndStraightDownToTheBase) {
  const TriangleMesh sheet = foldedSheet(40);
  const ProgressiveMesh pm = buildProgressive(sheet, singleRegion());
  const RegionSequence& seq = pm.region(0);
  ProgressiveMeshInstance instance(pm);
  const std::uint32_t target = static_cast<std::uint32_t>(sheet.triangleCount() / 10);
  const std::uint32_t tenPercent = seq.levelForTriangles(target);
  ASSERT_LE(seq.trianglesAt(tenPercent), target);
  ASSERT_GT(seq.trianglesAt(tenPercent), target / 2);
  for (std::uint32_t level : {tenPercent, seq.levelCount() / 4, 0u}) {
    instance.setLevel(0, level);
    // No triangle bridges the two planes, and the crease line lies on the surface.
    const auto [bridging, distance] = creaseDamage(pm.vertices().positions, instance.indices(0));
    EXPECT_EQ(bridging, 0) << "level " << level;
    EXPECT_LT(distance, 1e-5) << "level " << level;
  }
  // The base is the sheet itself, two rectangles meeting at the crease (area 2 * 0.5 * √2);
  // without features the quadrics hold the crease for a while, but the base loses a part.
  auto baseArea = [](const ProgressiveMesh& m) {
    ProgressiveMeshInstance base(m);
    base.setLevel(0, 0);
    const auto idx = base.indices(0);
    double area = 0.0;
    for (std::size_t t = 0; t < idx.size(); t += 3)
      area += 0.5 * glm::length(triangleNormal(m.vertices().positions, idx, t));
    return area;
  };
  EXPECT_NEAR(baseArea(pm), std::sqrt(2.0), 1e-5);
  ClusterOptions noFeatures;
  noFeatures.featureAngleDegrees = 180.0;
  EXPECT_LT(baseArea(buildProgressive(sheet, singleRegion(), noFeatures)), 0.9 * std::sqrt(2.0));
}

TEST(ClusterBuilder, BoxCornersStayAndNoTriangleLeavesItsFace) {
  const TriangleMesh box = subdividedBox(12);
  const ProgressiveMesh pm = buildProgressive(box, singleRegion());
  const RegionSequence& seq = pm.region(0);
  const auto& p = pm.vertices().positions;
  ProgressiveMeshInstance instance(pm);
  for (std::uint32_t level :
       {0u, seq.levelForTriangles(static_cast<std::uint32_t>(box.triangleCount() / 10)), seq.levelCount() / 2}) {
    instance.setLevel(0, level);
    const auto idx = instance.indices(0);
    EXPECT_EQ(openEdgeCount(std::vector<std::uint32_t>(idx.begin(), idx.end())), 0u) << "level " << level;
    for (std::size_t t = 0; t < idx.size(); t += 3) {
      const glm::dvec3 n = triangleNormal(p, idx, t);
      const double largest = std::max({std::abs(n.x), std::abs(n.y), std::abs(n.z)});
      ASSERT_NEAR(largest, glm::length(n), 1e-9) << "level " << level << ": triangle " << t / 3 << " spans two faces";
    }
  }
  int corners = 0;
  for (std::uint32_t v = 0; v < seq.verticesAt(0); ++v) {
    const glm::vec3 q = p[v];
    corners += (q.x == 0.0f || q.x == 1.0f) && (q.y == 0.0f || q.y == 1.0f) && (q.z == 0.0f || q.z == 1.0f);
  }
  EXPECT_EQ(corners, 8);
}

TEST(ClusterBuilder, FeaturesOfNoiseFadeAsTheMeshCoarsens) {
  // Vertices pulled out of a smooth sphere make spikes whose edges are all sharp, small
  // knots of sharp edges: noise, not features. Taken for corners, which never join, they
  // would lock one another and the base would hold all twelve spikes and their rings.
  TriangleMesh sphere = test::bumpySphere(24, 32);
  int spikes = 0;
  for (std::uint32_t ring = 8; ring <= 16; ring += 4)  // away from the rough poles
    for (std::uint32_t segment = ring % 8; segment < 32; segment += 8, ++spikes)
      sphere.positions[1 + (ring - 1) * 32 + segment] *= 1.2f;
  ASSERT_EQ(spikes, 12);
  const ProgressiveMesh pm = buildProgressive(sphere, singleRegion());
  EXPECT_LE(pm.region(0).verticesAt(0), 6u);
  EXPECT_LE(pm.region(0).trianglesAt(0), 8u);
}

TEST(ClusterBuilder, ColoursKeepAColourBorder) {
  // A flat grid painted in two colours, red up to column 11 and blue from column 12 on.
  // With colours the two border columns only gather along themselves, so the blend
  // between the colours stays the original strip between them; blind, it widens with the
  // triangles. (The number of mixed triangles is about the same either way: both are a
  // strip of triangles along the border at the current resolution.)
  const std::uint32_t n = 24;
  TriangleMesh grid = test::bumpyGrid(n, 0.0f);
  for (const glm::vec3& p : grid.positions)
    grid.colours.push_back(p.x < 0.49f ? glm::vec4(1, 0, 0, 1) : glm::vec4(0, 0, 1, 1));
  const std::uint32_t target = static_cast<std::uint32_t>(grid.triangleCount() / 10);
  struct Mixing {
    int triangles = 0, mixed = 0, mixedOffTheBorder = 0;
    double mixedArea = 0.0;
  };
  auto mixing = [&](const ClusterOptions& options) {
    const ProgressiveMesh pm = buildProgressive(grid, singleRegion(), options);
    ProgressiveMeshInstance instance(pm);
    instance.setLevel(0, pm.region(0).levelForTriangles(target));
    Mixing m;
    const auto idx = instance.indices(0);
    const auto& c = pm.vertices().colours;
    const auto& p = pm.vertices().positions;
    auto onBorder = [&](std::uint32_t v) { return p[v].x == 11.0f / n || p[v].x == 12.0f / n; };
    for (std::size_t t = 0; t < idx.size(); t += 3) {
      ++m.triangles;
      if (c[idx[t]] == c[idx[t + 1]] && c[idx[t]] == c[idx[t + 2]]) continue;
      ++m.mixed;
      m.mixedOffTheBorder += !(onBorder(idx[t]) && onBorder(idx[t + 1]) && onBorder(idx[t + 2]));
      m.mixedArea += 0.5 * glm::length(triangleNormal(p, idx, t));
    }
    return m;
  };
  ClusterOptions blind;
  blind.colourWeight = 0.0;
  const Mixing with = mixing({}), without = mixing(blind);
  EXPECT_LE(with.triangles, int(target));
  EXPECT_GT(with.triangles, int(target / 2));
  EXPECT_GT(without.triangles, int(target / 2));
  EXPECT_GT(with.mixed, 0);
  EXPECT_EQ(with.mixedOffTheBorder, 0);
  EXPECT_NEAR(with.mixedArea, 1.0 / n, 1e-5) << "the strip between the border columns, no more";
  EXPECT_GT(without.mixedOffTheBorder, 0);
  EXPECT_LT(2.0 * with.mixedArea, without.mixedArea) << "with colours " << with.mixed << " mixed of " << with.triangles
                                                     << ", blind " << without.mixed << " of " << without.triangles;
}

TEST(ClusterBuilder, StopsAtTheRequestedTriangleCount) {
  // Large enough for rounds of two workers; the higher count ends within them.
  const TriangleMesh sphere = test::bumpySphere(40, 48);
  for (std::uint32_t stop : {300u, 2500u}) {
    ClusterOptions options;
    options.stopAtTriangles = stop;
    double lastProgress = -1.0;
    int reports = 0;
    options.progress = [&](double fraction) {
      EXPECT_GE(fraction, lastProgress);
      EXPECT_LE(fraction, 1.0);
      lastProgress = fraction;
      ++reports;
    };
    const ProgressiveMesh pm = buildProgressive(sphere, singleRegion(), options);
    EXPECT_LE(pm.region(0).trianglesAt(0), stop);
    EXPECT_GT(pm.region(0).trianglesAt(0), stop - stop / 6);
    EXPECT_GT(reports, 0);
  }
}

// A large mesh is simplified by two workers at once, on parts of it that are apart: the
// steps must not depend on how the two threads' work interleaves.
TEST(ClusterBuilder, ALargeMeshGivesTheSameStepsEveryTime) {
  TriangleMesh sphere = test::bumpySphere(48, 64);
  for (const glm::vec3& p : sphere.positions) sphere.colours.emplace_back(p.x > 0.2f ? 1.0f : 0.1f, 0.5f, 0.3f, 1.0f);
  const RegionPartition partition = automaticPartition(sphere.positions, 3);
  const SimplificationSteps first = clusterSteps(sphere, partition);
  ASSERT_GT(first.removed.size(), sphere.vertexCount() * 9 / 10);
  for (int build = 0; build < 4; ++build) {
    const SimplificationSteps again = clusterSteps(sphere, partition);
    ASSERT_EQ(again.representative, first.representative) << "build " << build;
    ASSERT_EQ(again.removedBegin, first.removedBegin) << "build " << build;
    ASSERT_EQ(again.removed, first.removed) << "build " << build;
    ASSERT_EQ(again.onto, first.onto) << "build " << build;
    ASSERT_EQ(again.error, first.error) << "build " << build;
  }
}

TEST(ClusterBuilder, RejectsBadOptions) {
  const TriangleMesh grid = test::bumpyGrid(4);
  ClusterOptions noGrowth;
  noGrowth.cellGrowth = 1.0;
  EXPECT_FALSE(buildClusterSteps(grid, singleRegion(), noGrowth).ok());
  ClusterOptions negativeCell;
  negativeCell.initialCellFraction = -0.1;
  EXPECT_FALSE(buildClusterSteps(grid, singleRegion(), negativeCell).ok());
  ClusterOptions badAngle;
  badAngle.featureAngleDegrees = std::nan("");
  EXPECT_FALSE(buildClusterSteps(grid, singleRegion(), badAngle).ok());
  RegionPartition wrongSize;
  wrongSize.regionCount = 2;
  wrongSize.vertexRegion.assign(3, 0);
  EXPECT_FALSE(buildClusterSteps(grid, wrongSize).ok());
}

}  // namespace
}  // namespace polder::mesh
