// Triangle-mesh query scenes (createFromMeshes): the same surface as a mesh answers like
// the grid scene, across several meshes with their own origins.
#include <polder/query/query_scene.hpp>

#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "query_test_fields.hpp"

namespace polder::query {
namespace {

using test::makeField;
using test::meshOfField;

TEST(QueryMeshScene, SameHeightsAndHitsAsTheGridScene) {
  const auto field = makeField(33, 29, 1.5, 1.25, test::sinusoid);
  const glm::dvec3 centre(0.5 * field.extentX(), 0.5 * field.extentY(), 0.0);
  const MeshData mesh = meshOfField(field, centre);
  auto gridScene = QueryScene::create(field);
  auto meshScene = QueryScene::createFromMeshes(std::span(&mesh, 1));
  ASSERT_TRUE(gridScene.ok() && meshScene.ok());

  std::mt19937 rng(11);
  std::uniform_real_distribution<double> ux(0.0, field.extentX()), uy(0.0, field.extentY()), slant(-0.8, 0.8);
  for (int i = 0; i < 1000; ++i) {
    const double x = ux(rng), y = uy(rng);
    const auto expected = (*gridScene)->height(x, y);
    const auto actual = (*meshScene)->height(x, y);
    ASSERT_TRUE(expected && actual) << x << "," << y;
    // Mesh positions are floats relative to the centre (up to 25 m): a few micrometres.
    EXPECT_NEAR(*actual, *expected, 1e-5) << x << "," << y;

    const QueryRay ray{{x, y, 40.0}, {slant(rng), slant(rng), -1.0}};
    const auto a = (*gridScene)->raycast(ray);
    const auto b = (*meshScene)->raycast(ray);
    ASSERT_EQ(a.has_value(), b.has_value());
    if (!a) continue;
    EXPECT_NEAR(glm::length(a->point - b->point), 0.0, 1e-4);
    EXPECT_NEAR(glm::length(a->normal - b->normal), 0.0, 1e-4);
  }
  EXPECT_FALSE((*meshScene)->height(-0.1, 3.0));
  EXPECT_FALSE((*meshScene)->height(3.0, field.extentY() + 0.1));
}

TEST(QueryMeshScene, SeveralMeshesWithTheirOwnOrigins) {
  // The field's west and east halves as two meshes, each relative to its own origin.
  const auto field = makeField(21, 11, 1.0, 1.0, test::sinusoid);
  terrain::Heightfield west(11, 11), east(11, 11);
  for (int y = 0; y < 11; ++y) {
    for (int x = 0; x < 11; ++x) {
      west.at(x, y) = field.at(x, y);
      east.at(x, y) = field.at(x + 10, y);
    }
  }
  MeshData eastMesh = meshOfField(east, glm::dvec3(0.0));
  eastMesh.origin = glm::dvec3(10.0, 0.0, 0.0);  // shift the east half into place
  const std::vector<MeshData> meshes = {meshOfField(west, glm::dvec3(2.0, 3.0, 4.0)), MeshData{}, eastMesh};
  auto scene = QueryScene::createFromMeshes(meshes);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  for (double x = 0.0; x <= 20.0; x += 0.37) {
    for (double y = 0.0; y <= 10.0; y += 0.41) {
      const auto h = (*scene)->height(x, y);
      ASSERT_TRUE(h) << x << "," << y;
      EXPECT_NEAR(*h, test::conventionHeight(field, x, y), 1e-5) << x << "," << y;
    }
  }
  EXPECT_NEAR((*scene)->boundsMax().x, 20.0, 1e-6);
}

TEST(QueryMeshScene, ReportsBadMeshesAndAnswersEmptyScenes) {
  MeshData broken;
  broken.positions = {glm::vec3(0.0f), glm::vec3(1.0f, 0.0f, 0.0f), glm::vec3(0.0f, 1.0f, 0.0f)};
  broken.indices = {0, 1, 3};
  auto outOfRange = QueryScene::createFromMeshes(std::span(&broken, 1));
  ASSERT_FALSE(outOfRange.ok());
  EXPECT_EQ(outOfRange.error().kind, ErrorKind::InvalidArgument);
  broken.indices = {0, 1};
  EXPECT_EQ(QueryScene::createFromMeshes(std::span(&broken, 1)).error().kind, ErrorKind::InvalidArgument);

  auto empty = QueryScene::createFromMeshes({});
  ASSERT_TRUE(empty.ok());
  EXPECT_FALSE((*empty)->height(0.0, 0.0));
  EXPECT_FALSE((*empty)->raycast({0.0, 0.0, 1.0}, {0.0, 0.0, -1.0}));
  EXPECT_TRUE((*empty)->lineOfSight({0.0, 0.0, 1.0}, {5.0, 0.0, -1.0}));
}

TEST(QueryMeshScene, RayHitsATriangleExactly) {
  MeshData triangle;
  triangle.origin = glm::dvec3(1000.0, 2000.0, 300.0);
  triangle.positions = {glm::vec3(0.0f, 0.0f, 0.0f), glm::vec3(10.0f, 0.0f, 0.0f), glm::vec3(0.0f, 10.0f, 10.0f)};
  triangle.indices = {0, 1, 2};
  auto scene = QueryScene::createFromMeshes(std::span(&triangle, 1));
  ASSERT_TRUE(scene.ok());
  const auto hit = (*scene)->raycast({1002.0, 2003.0, 400.0}, {0.0, 0.0, -1.0});
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->point.z, 303.0, 1e-9);
  EXPECT_NEAR(hit->distance, 97.0, 1e-9);
  EXPECT_NEAR(hit->normal.y, -std::sqrt(0.5), 1e-9);
  EXPECT_NEAR(hit->normal.z, std::sqrt(0.5), 1e-9);
  EXPECT_FALSE((*scene)->raycast({1008.0, 2008.0, 400.0}, {0.0, 0.0, -1.0}));  // beyond the hypotenuse
}

}  // namespace
}  // namespace polder::query
