// The progressive meshes' self-reported object-space error, errorAt(level), held against
// the deviation measured on the surfaces (a Metro-style symmetric Hausdorff distance,
// polder::query::measureSurfaceDeviation) at random levels, for both builders, and asks
// what level selection relies on: the estimate stays within a fixed factor of the measured
// distance, and it orders the levels as the measurement does. The collapse builder tracks
// how far each vertex's surface has moved and claims at least the measured distance
// (0.58-0.84 of its claim on this sphere); the cluster builder's figure is the largest
// root mean square plane distance of a cluster, an estimate either way (0.55-1.13).
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "mesh_test_shapes.hpp"
#include "polder/mesh/cluster_builder.hpp"
#include "polder/mesh/collapse_builder.hpp"
#include "polder/mesh/mesh_extraction.hpp"
#include "polder/mesh/progressive_mesh.hpp"
#include "polder/mesh/progressive_mesh_instance.hpp"
#include "polder/query/surface_deviation.hpp"

namespace polder::mesh {
namespace {

struct Builder {
  std::string name;
  double lowestRatio, highestRatio;  // measured Hausdorff distance over errorAt
  std::function<Result<SimplificationSteps>(const TriangleMesh&, const RegionPartition&)> build;
};

class ErrorEstimate : public ::testing::TestWithParam<Builder> {};

TEST_P(ErrorEstimate, TracksTheMeasuredHausdorffDistanceAtRandomLevels) {
  const TriangleMesh sphere = test::bumpySphere(40, 52);
  auto steps = GetParam().build(sphere, singleRegion());
  ASSERT_TRUE(steps.ok()) << steps.error().message;
  auto pm = ProgressiveMesh::assemble(sphere, singleRegion(), *steps);
  ASSERT_TRUE(pm.ok()) << pm.error().message;
  const RegionSequence& seq = pm->region(0);
  const double diagonal = boundingBoxDiagonal(sphere.positions);
  ProgressiveMeshInstance instance(*pm);
  std::mt19937 random(19);
  std::uniform_int_distribution<std::uint32_t> anyLevel(0, seq.levelCount() - 1);
  query::SurfaceDeviationOptions options;
  options.samplesPerSurface = 20000;
  std::vector<std::pair<double, double>> claimedAndMeasured;
  for (int trial = 0; trial < 12; ++trial) {
    const std::uint32_t level = anyLevel(random);
    instance.setLevel(0, level);
    instance.resolveBorders();
    const TriangleMesh simplified = extractMesh(instance);
    auto deviation = query::measureSurfaceDeviation(sphere, simplified, options);
    ASSERT_TRUE(deviation.ok()) << deviation.error().message;
    const double measured = deviation->hausdorff * diagonal;
    const double claimed = seq.errorAt(level);
    ASSERT_GT(claimed, 0.0) << "level " << level << " lacks steps yet claims no error";
    EXPECT_GE(measured / claimed, GetParam().lowestRatio) << "level " << level << " claims " << claimed;
    EXPECT_LE(measured / claimed, GetParam().highestRatio) << "level " << level << " claims " << claimed;
    claimedAndMeasured.emplace_back(claimed, measured);
  }
  // Where one level claims at least twice another's error, it also measures more.
  for (const auto& [claimedA, measuredA] : claimedAndMeasured)
    for (const auto& [claimedB, measuredB] : claimedAndMeasured)
      if (claimedA >= 2.0 * claimedB) {
        EXPECT_GT(measuredA, measuredB) << claimedA << " against " << claimedB;
      }
  // The finest level is the original: nothing claimed, nothing measured.
  instance.setLevel(0, seq.levelCount());
  instance.resolveBorders();
  auto finest = query::measureSurfaceDeviation(sphere, extractMesh(instance), options);
  ASSERT_TRUE(finest.ok());
  EXPECT_EQ(seq.errorAt(seq.levelCount()), 0.0f);
  EXPECT_LT(finest->hausdorff, 1e-6);
}

INSTANTIATE_TEST_SUITE_P(
    Builders, ErrorEstimate,
    ::testing::Values(Builder{"collapse", 0.4, 1.0,
                              [](const TriangleMesh& m, const RegionPartition& p) { return buildCollapseSteps(m, p); }},
                      Builder{"cluster", 0.4, 1.6,
                              [](const TriangleMesh& m, const RegionPartition& p) { return buildClusterSteps(m, p); }}),
    [](const ::testing::TestParamInfo<Builder>& info) { return info.param.name; });

}  // namespace
}  // namespace polder::mesh
