// Large extents: 256 x 256 samples 9783.94 m apart span 2,500 km, where a float resolves
// 0.125 m. Heights and hits must stay within 1 m (they are exact after the double
// refinement; the unrefined float path is checked against the same bound).
#include <polder/query/query_scene.hpp>

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "query_test_fields.hpp"

namespace polder::query {
namespace {

constexpr double kSpacing = 9783.94;

terrain::Heightfield largeField() {
  return test::makeField(256, 256, kSpacing, kSpacing, [](double x, double y) {
    return 3000.0 + 2500.0 * std::sin(x * 3.1e-6) * std::cos(y * 2.3e-6) + 400.0 * std::sin(x * 1.7e-5 + y * 1.1e-5);
  });
}

TEST(QueryPrecision, LargeExtentHeightsAtGridPoints) {
  const auto field = largeField();
  auto scene = QueryScene::create(field);
  ASSERT_TRUE(scene.ok());
  EXPECT_LE((*scene)->floatResolution(), 0.13);
  for (int y = 0; y < field.height; y += 5) {
    for (int x = 0; x < field.width; x += 3) {
      const glm::dvec3 p = field.worldPosition(x, y);
      const auto h = (*scene)->height(p.x, p.y);
      ASSERT_TRUE(h);
      EXPECT_NEAR(*h, p.z, 1e-6);
    }
  }
}

TEST(QueryPrecision, LargeExtentRayHits) {
  const auto field = largeField();
  QueryOptions raw;
  raw.refineHits = false;
  auto refined = QueryScene::create(field);
  auto unrefined = QueryScene::create(field, raw);
  ASSERT_TRUE(refined.ok() && unrefined.ok());
  std::mt19937 rng(21);
  std::uniform_int_distribution<int> sample(1, 254);  // inside: the high borders are open to rays
  std::uniform_real_distribution<double> slant(-0.3, 0.3);
  double worstRaw = 0.0;
  for (int i = 0; i < 500; ++i) {
    const glm::dvec3 target = field.worldPosition(sample(rng), sample(rng));
    // Vertical rays onto grid points.
    const glm::dvec3 top = target + glm::dvec3(0.0, 0.0, 20000.0);
    const auto a = (*refined)->raycast(top, {0.0, 0.0, -1.0});
    const auto b = (*unrefined)->raycast(top, {0.0, 0.0, -1.0});
    ASSERT_TRUE(a && b);
    EXPECT_NEAR(a->point.z, target.z, 1e-6);
    EXPECT_NEAR(b->point.z, target.z, 1.0);
    worstRaw = std::max(worstRaw, std::abs(b->point.z - target.z));

    // Slanted rays aimed at grid points from 20 km away (the surface is gentle, so nothing
    // stands in the way).
    const glm::dvec3 direction = glm::normalize(glm::dvec3(slant(rng), slant(rng), -1.0));
    const glm::dvec3 origin = target - 20000.0 * direction;
    const auto c = (*refined)->raycast(origin, direction);
    const auto d = (*unrefined)->raycast(origin, direction);
    ASSERT_TRUE(c && d);
    EXPECT_NEAR(glm::length(c->point - target), 0.0, 1e-6);
    EXPECT_NEAR(glm::length(d->point - target), 0.0, 1.0);
    EXPECT_NEAR(c->distance, 20000.0, 1e-6);
  }
  RecordProperty("worst_unrefined_vertical_error_m", std::to_string(worstRaw));
}

TEST(QueryPrecision, FarFromTheWorldOriginMeshes) {
  // A mesh 10,000 km from the world origin, given relative to its own origin.
  const auto field = test::makeField(17, 17, 10.0, 10.0, test::sinusoid);
  const MeshData mesh = test::meshOfField(field, glm::dvec3(80.0, 80.0, 0.0));
  MeshData far = mesh;
  far.origin += glm::dvec3(1.0e7, -1.0e7, 0.0);
  auto scene = QueryScene::createFromMeshes(std::span(&far, 1));
  ASSERT_TRUE(scene.ok());
  for (int y = 0; y < 16; y += 2) {  // not the open north and east borders
    for (int x = 0; x < 16; x += 3) {
      const glm::dvec3 p = field.worldPosition(x, y) + glm::dvec3(1.0e7, -1.0e7, 0.0);
      const auto h = (*scene)->height(p.x, p.y);
      ASSERT_TRUE(h);
      EXPECT_NEAR(*h, p.z, 1e-4);
    }
  }
}

}  // namespace
}  // namespace polder::query
