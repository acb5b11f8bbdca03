// The truth read from a pyramid's level-0 tiles answers as the full resolution in memory does:
// the same heights everywhere, the same rays meeting the surface, grazing ones included; a
// corrupt tile answers nothing there and is counted, with a message naming the file.
#include <polder/query/pyramid_surface.hpp>

#include <random>

#include <gtest/gtest.h>

#include <polder/query/query_scene.hpp>

#include "generated_terrain.hpp"
#include "pyramid_file.hpp"

namespace polder::query {
namespace {

TEST(PyramidSurface, HeightsAreTheFullResolutionTriangulations) {
  const terrain::Heightfield field = test::generatedTerrain(300, 5);  // not a whole number of blocks
  test::PyramidFile file(field, "surface-heights");
  PyramidSurface tiles(file.open(), 64 * 1024);  // a few tiles at once: they come and go
  auto scene = QueryScene::create(field);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  std::mt19937 random(11);
  std::uniform_real_distribution<double> x(0.0, field.extentX()), y(0.0, field.extentY());
  double worst = 0.0;
  for (int i = 0; i < 20000; ++i) {
    const double px = x(random), py = y(random);
    const auto expected = (*scene)->height(px, py);
    const auto read = tiles.height(px, py);
    ASSERT_TRUE(expected && read) << px << ", " << py;
    worst = std::max(worst, std::abs(*expected - *read));
  }
  EXPECT_LT(worst, 1e-3);
  // The borders and the corners belong to the surface; beyond them nothing.
  EXPECT_NEAR(*tiles.height(field.extentX(), field.extentY()), field.at(field.width - 1, field.height - 1), 1e-3);
  EXPECT_NEAR(*tiles.height(0.0, field.extentY()), field.at(0, field.height - 1), 1e-3);
  EXPECT_FALSE(tiles.height(field.extentX() + 1.0, 0.0));
  EXPECT_FALSE(tiles.height(-1.0, 10.0));
  EXPECT_EQ(tiles.readFailures(), 0u);
}

TEST(PyramidSurface, RaysMeetItWhereTheyMeetTheFullResolution) {
  const terrain::Heightfield field = test::generatedTerrain(257, 8);
  test::PyramidFile file(field, "surface-rays");
  PyramidSurface tiles(file.open());
  auto scene = QueryScene::create(field);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  const auto [low, high] = field.heightRange();
  std::mt19937 random(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int hits = 0, misses = 0, disagreements = 0;
  for (int i = 0; i < 4000; ++i) {
    // From above the relief towards a point near its top: many graze ridges, many miss.
    const glm::dvec3 origin(unit(random) * field.extentX(), unit(random) * field.extentY(),
                            high + 50.0 + 500.0 * unit(random));
    const glm::dvec3 target(unit(random) * field.extentX(), unit(random) * field.extentY(),
                            low + (high - low) * (0.6 + 0.5 * unit(random)));
    const QueryRay ray{origin, target - origin, 0.0, 4.0 * glm::length(target - origin)};
    const bool exact = (*scene)->raycast(ray).has_value();
    const bool met = tiles.meets(ray);
    // A ray that touches the surface within rounding may go either way: one a centimetre
    // higher or lower at its target would.
    const auto shifted = [&](double dz) {
      const glm::dvec3 to = target + glm::dvec3(0.0, 0.0, dz);
      return (*scene)->raycast(QueryRay{origin, to - origin, 0.0, ray.maxDistance}).has_value();
    };
    const bool grazing = shifted(0.01) != shifted(-0.01);
    if (met != exact && !grazing) ++disagreements;
    (met ? hits : misses)++;
  }
  EXPECT_EQ(disagreements, 0);
  EXPECT_GT(hits, 500);
  EXPECT_GT(misses, 500);
}

TEST(PyramidSurface, ACorruptTileAnswersNothingThereAndIsCounted) {
  const terrain::Heightfield field = test::generatedTerrain(129, 2);
  test::PyramidFile file(field, "surface-corrupt");
  const terrain::NodeId victim{0, 1, 1};
  file.corruptTile(victim);
  auto pyramid = file.open();
  ASSERT_NE(pyramid, nullptr);
  PyramidSurface tiles(pyramid);
  const terrain::SampleRect area = pyramid->layout().footprint(victim);
  const double cx = (area.x0 + area.x1) * 0.5 * field.spacingX, cy = (area.y0 + area.y1) * 0.5 * field.spacingY;
  EXPECT_FALSE(tiles.height(cx, cy));
  EXPECT_TRUE(tiles.height(1.0, 1.0));  // another tile
  EXPECT_FALSE(tiles.meets(QueryRay{{cx, cy, 1e4}, {0.0, 0.0, -1.0}}));
  EXPECT_GE(tiles.readFailures(), 1u);
  EXPECT_NE(tiles.firstFailure().find(file.path().string()), std::string::npos) << tiles.firstFailure();
}

}  // namespace
}  // namespace polder::query
