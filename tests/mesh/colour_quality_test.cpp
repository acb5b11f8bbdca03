// Attribute-aware simplification keeps colour borders: at 10% of the triangles, the colour
// error (measured on the surfaces, polder::query::measureSurfaceDeviation) is at most half
// of what the same builder gives with colours ignored.
#include <gtest/gtest.h>

#include <cmath>

#include "mesh_test_shapes.hpp"
#include "polder/mesh/cluster_builder.hpp"
#include "polder/mesh/collapse_builder.hpp"
#include "polder/mesh/level_selection.hpp"
#include "polder/mesh/mesh_extraction.hpp"
#include "polder/query/surface_deviation.hpp"

namespace polder::mesh {
namespace {

// A bumpy grid painted red inside a circle and blue outside: a curved colour border.
TriangleMesh paintedGrid() {
  TriangleMesh grid = test::bumpyGrid(60, 0.05f);
  for (const glm::vec3& p : grid.positions) {
    const bool inside = (p.x - 0.45f) * (p.x - 0.45f) + (p.y - 0.55f) * (p.y - 0.55f) < 0.09f;
    grid.colours.push_back(inside ? glm::vec4(0.9f, 0.1f, 0.1f, 1.0f) : glm::vec4(0.1f, 0.2f, 0.9f, 1.0f));
  }
  return grid;
}

double colourErrorAtTenPercent(const TriangleMesh& mesh, const Result<SimplificationSteps>& steps) {
  EXPECT_TRUE(steps.ok());
  auto pm = ProgressiveMesh::assemble(mesh, singleRegion(), *steps);
  EXPECT_TRUE(pm.ok());
  ProgressiveMeshInstance instance(*pm);
  std::uint32_t level[1];
  levelsForTriangleBudget(*pm, mesh.triangleCount() / 10, level);
  instance.setLevel(0, level[0]);
  const TriangleMesh simplified = extractMesh(instance);
  EXPECT_LE(simplified.triangleCount(), mesh.triangleCount() / 10);
  EXPECT_GE(simplified.triangleCount(), mesh.triangleCount() / 12);
  query::SurfaceDeviationOptions options;
  options.samplesPerSurface = 50000;
  auto deviation = query::measureSurfaceDeviation(mesh, simplified, options);
  EXPECT_TRUE(deviation.ok());
  return deviation->colourRms;
}

TEST(ColourQuality, CollapseHalvesTheColourErrorOfTheColourBlindSequence) {
  const TriangleMesh mesh = paintedGrid();
  CollapseOptions blind;
  blind.colourWeight = 0.0;
  const double aware = colourErrorAtTenPercent(mesh, buildCollapseSteps(mesh, singleRegion()));
  const double ignored = colourErrorAtTenPercent(mesh, buildCollapseSteps(mesh, singleRegion(), blind));
  EXPECT_LE(aware, 0.5 * ignored) << "aware " << aware << ", blind " << ignored;
}

TEST(ColourQuality, ClusterHalvesTheColourErrorOfTheColourBlindSequence) {
  const TriangleMesh mesh = paintedGrid();
  ClusterOptions blind;
  blind.colourWeight = 0.0;
  const double aware = colourErrorAtTenPercent(mesh, buildClusterSteps(mesh, singleRegion()));
  const double ignored = colourErrorAtTenPercent(mesh, buildClusterSteps(mesh, singleRegion(), blind));
  EXPECT_LE(aware, 0.5 * ignored) << "aware " << aware << ", blind " << ignored;
}

}  // namespace
}  // namespace polder::mesh
