#include <polder/query/screen_error.hpp>

#include <cmath>

#include <gtest/gtest.h>

#include "query_test_fields.hpp"

namespace polder::query {
namespace {

terrain::Heightfield hills() {
  terrain::Heightfield field(129, 129, 20.0, 20.0);
  for (int y = 0; y < field.height; ++y)
    for (int x = 0; x < field.width; ++x)
      field.at(x, y) =
          float(300.0 + 120.0 * std::sin(x * 0.11) * std::cos(y * 0.07) + 40.0 * std::sin(x * 0.37 + y * 0.23));
  return field;
}

// The heightfield's own triangulation as meshes, lifted by `liftM`.
std::vector<MeshData> surfaceMeshes(const terrain::Heightfield& field, float liftM) {
  MeshData mesh;
  for (int y = 0; y < field.height; ++y)
    for (int x = 0; x < field.width; ++x)
      mesh.positions.push_back(glm::vec3(float(x * field.spacingX), float(y * field.spacingY), field.at(x, y) + liftM));
  auto id = [&](int x, int y) { return std::uint32_t(y * field.width + x); };
  for (int y = 0; y + 1 < field.height; ++y)
    for (int x = 0; x + 1 < field.width; ++x) {
      mesh.indices.insert(mesh.indices.end(), {id(x, y), id(x + 1, y), id(x, y + 1)});
      mesh.indices.insert(mesh.indices.end(), {id(x + 1, y + 1), id(x, y + 1), id(x + 1, y)});
    }
  return {mesh};
}

Camera obliqueCamera() {
  Camera camera;
  camera.widthPx = 200;
  camera.heightPx = 150;
  camera.fovYDeg = 50.0;
  camera.position = {1280.0, -900.0, 1400.0};
  camera.yawDeg = 0.0;
  camera.pitchDeg = -35.0;
  camera.nearM = 1.0;
  camera.farM = 1e5;
  return camera;
}

TEST(ScreenError, TheFullResolutionSurfaceMeasuresZero) {
  const auto field = hills();
  auto truth = QueryScene::create(field);
  auto same = QueryScene::createFromMeshes(surfaceMeshes(field, 0.0f));
  ASSERT_TRUE(truth.ok() && same.ok());
  const ScreenError error = measureScreenError(**same, **truth, obliqueCamera());
  EXPECT_GT(error.pixelsMeasured, 10000u);
  EXPECT_LT(error.maxPx, 0.01);
}

TEST(ScreenError, AVerticalOffsetMeasuresItsProjectedLength) {
  const auto field = hills();
  auto truth = QueryScene::create(field);
  const float lift = 5.0f;
  auto lifted = QueryScene::createFromMeshes(surfaceMeshes(field, lift));
  ASSERT_TRUE(truth.ok() && lifted.ok());
  const Camera camera = obliqueCamera();
  const ScreenError error = measureScreenError(**lifted, **truth, camera, {.pixelStride = 2});
  // A vertical offset e at distance d covers at most K e / d pixels; the nearest visible
  // surface bounds the maximum, and every measured pixel sees some offset.
  const double nearest = 1400.0 - 500.0;  // the camera is at least this far above the terrain
  EXPECT_LE(error.maxPx, camera.projectionConstant() * lift / nearest + 1e-6);
  EXPECT_GT(error.meanPx, 0.2);
  EXPECT_LE(error.p99Px, error.maxPx);
}

}  // namespace
}  // namespace polder::query
