// The uniform-error mesh (uniform_mesh.hpp) on a real DEM: a crop of the Mt Rainier SRTM
// tile (the shared data folder), skipped when absent. Within the bound when
// measured again here, watertight, fewer triangles for a looser bound.
#include <gtest/gtest.h>

#include <polder/terrain/dem_reader.hpp>
#include <polder/terrain/heightfield_crop.hpp>
#include <polder/terrain/uniform_mesh.hpp>
#include <polder/terrain/watertight.hpp>

#include "test_support.hpp"

namespace polder::terrain {
namespace {

TEST(UniformMeshRealDem, MtRainierCropIsWithinTheBoundAndWatertight) {
  POLDER_REQUIRE_SHARED_FILE(path, "dems/mt_rainier_90m_srtm3.tif");
  const auto dem = readDem(path, {});
  ASSERT_TRUE(dem.ok()) << dem.error().message;
  // The summit's flank, glaciers and valleys; not a multiple of any block pitch.
  auto crop = cropHeightfield(dem->field, 780, 900, 230, 190);
  ASSERT_TRUE(crop.ok()) << crop.error().message;
  const Heightfield& field = *crop;
  std::size_t previous = 0;
  for (const double bound : {2.0, 10.0}) {
    UniformMeshOptions options;
    options.maxErrorM = bound;
    auto mesh = buildUniformMesh(field, options);
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    const TriangleSoup soup = uniformMeshSoup(*mesh);
    const float worst = soupMaxError(field, soup);
    EXPECT_LE(worst, bound);
    EXPECT_GT(worst, 0.5 * bound) << "a bound this tight is used, not met by accident";
    const WatertightReport report = checkWatertight(soup, field.width, field.height);
    EXPECT_EQ(report.openEdges, 0u);
    EXPECT_EQ(report.tJunctions, 0u);
    EXPECT_TRUE(report.watertight());
    if (previous != 0) {
      EXPECT_LT(mesh->triangleCount(), previous);
    }
    previous = mesh->triangleCount();
  }
}

}  // namespace
}  // namespace polder::terrain
