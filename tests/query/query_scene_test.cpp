// The heightfield query scene on analytic surfaces: heights, ray hits, normals, the
// triangulation convention, line of sight, footprint, batches and threads.
#include <polder/query/query_scene.hpp>

#include <cmath>
#include <limits>
#include <random>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "query_test_fields.hpp"

namespace polder::query {
namespace {

using test::conventionHeight;
using test::makeField;

std::unique_ptr<QueryScene> build(const terrain::Heightfield& field, const QueryOptions& options = {}) {
  auto scene = QueryScene::create(field, options);
  EXPECT_TRUE(scene.ok()) << (scene.ok() ? "" : scene.error().message);
  return scene.ok() ? std::move(scene).value() : nullptr;
}

void expectNearVec(const glm::dvec3& actual, const glm::dvec3& expected, double tolerance) {
  EXPECT_NEAR(actual.x, expected.x, tolerance);
  EXPECT_NEAR(actual.y, expected.y, tolerance);
  EXPECT_NEAR(actual.z, expected.z, tolerance);
}

TEST(QueryScene, HorizontalPlaneHeightHitAndNormal) {
  const auto field = makeField(17, 13, 2.0, 3.0, [](double, double) { return 5.0; });
  const auto scene = build(field);
  ASSERT_TRUE(scene);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> ux(0.0, field.extentX()), uy(0.0, field.extentY());
  for (int i = 0; i < 200; ++i) EXPECT_EQ(scene->height(ux(rng), uy(rng)), 5.0);
  EXPECT_EQ(scene->height(0.0, 0.0), 5.0);
  EXPECT_EQ(scene->height(field.extentX(), field.extentY()), 5.0);

  const auto down = scene->raycast({10.0, 10.0, 100.0}, {0.0, 0.0, -1.0});
  ASSERT_TRUE(down);
  expectNearVec(down->point, {10.0, 10.0, 5.0}, 1e-12);
  expectNearVec(down->normal, {0.0, 0.0, 1.0}, 1e-12);
  EXPECT_NEAR(down->distance, 95.0, 1e-12);

  // Direction (1, 2, -2) / 3 falls 20 m after 30 m, landing at (14, 26).
  const auto oblique = scene->raycast({4.0, 6.0, 25.0}, {1.0, 2.0, -2.0});
  ASSERT_TRUE(oblique);
  expectNearVec(oblique->point, {14.0, 26.0, 5.0}, 1e-12);
  EXPECT_NEAR(oblique->distance, 30.0, 1e-12);
}

TEST(QueryScene, TiltedPlaneIsExactEverywhere) {
  // Coefficients and spacing chosen so that every sample is exactly representable.
  constexpr double a = 0.25, b = -0.5, c = 40.0;
  const auto plane = [&](double x, double y) { return a * x + b * y + c; };
  const auto field = makeField(21, 21, 2.0, 2.0, plane);
  const auto scene = build(field);
  ASSERT_TRUE(scene);
  const glm::dvec3 normal = glm::normalize(glm::dvec3(-a, -b, 1.0));

  std::mt19937 rng(2);
  std::uniform_real_distribution<double> ux(0.0, field.extentX()), uy(0.0, field.extentY());
  std::uniform_real_distribution<double> tilt(-0.6, 0.6);
  for (int i = 0; i < 300; ++i) {
    const double x = ux(rng), y = uy(rng);
    ASSERT_TRUE(scene->height(x, y));
    EXPECT_NEAR(*scene->height(x, y), plane(x, y), 1e-12);

    // A ray aimed at (x, y) on the plane from 30 m above it along a random slant.
    const glm::dvec3 target(x, y, plane(x, y));
    const glm::dvec3 direction = glm::normalize(glm::dvec3(tilt(rng), tilt(rng), -1.0));
    const glm::dvec3 origin = target - direction * 30.0;
    const auto hit = scene->raycast(origin, direction);
    ASSERT_TRUE(hit);
    expectNearVec(hit->point, target, 1e-9);
    expectNearVec(hit->normal, normal, 1e-12);
    EXPECT_NEAR(hit->distance, 30.0, 1e-9);
  }
}

TEST(QueryScene, SinusoidMatchesSamplesAndPiecewiseLinearInterpolation) {
  const auto field = makeField(33, 29, 1.5, 1.25, test::sinusoid);
  const auto scene = build(field);
  ASSERT_TRUE(scene);
  for (int y = 0; y < field.height; ++y) {
    for (int x = 0; x < field.width; ++x) {
      const glm::dvec3 p = field.worldPosition(x, y);
      ASSERT_TRUE(scene->height(p.x, p.y));
      EXPECT_EQ(*scene->height(p.x, p.y), p.z) << x << "," << y;
      // Rays exactly on the east and north borders may miss (Embree's edge rule).
      if (x == field.width - 1 || y == field.height - 1) continue;
      const auto hit = scene->raycast(p + glm::dvec3(0.0, 0.0, 50.0), {0.0, 0.0, -1.0});
      ASSERT_TRUE(hit) << x << "," << y;
      EXPECT_NEAR(hit->point.z, p.z, 1e-9) << x << "," << y;
    }
  }
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> ux(0.0, field.extentX()), uy(0.0, field.extentY());
  for (int i = 0; i < 1000; ++i) {
    const double x = ux(rng), y = uy(rng);
    const double expected = conventionHeight(field, x, y);
    EXPECT_NEAR(*scene->height(x, y), expected, 1e-9);
    const auto hit = scene->raycast({x, y, 100.0}, {0.0, 0.0, -1.0});
    ASSERT_TRUE(hit);
    EXPECT_NEAR(hit->point.z, expected, 1e-9);
    EXPECT_GT(hit->normal.z, 0.0);
  }
}

// A saddle cell: the diagonal (1,0)-(0,1) joins the two high corners, so the convention
// puts the cell's middle at height 1; the other diagonal would put it at 0.
terrain::Heightfield saddle() {
  terrain::Heightfield field(2, 2);
  field.at(0, 0) = 0.0f;
  field.at(1, 0) = 1.0f;
  field.at(0, 1) = 1.0f;
  field.at(1, 1) = 0.0f;
  return field;
}

TEST(QueryScene, SaddleCellFollowsTheDiagonalConvention) {
  const auto field = saddle();
  const auto scene = build(field);
  ASSERT_TRUE(scene);
  EXPECT_NEAR(*scene->height(0.5, 0.5), 1.0, 1e-12);
  EXPECT_NEAR(*scene->height(0.25, 0.25), 0.5, 1e-12);
  EXPECT_NEAR(*scene->height(0.75, 0.75), 0.5, 1e-12);
  EXPECT_NEAR(*scene->height(0.7, 0.1), 0.8, 1e-12);

  // Embree's own split, unrefined: its grid quads must be cut along the same diagonal.
  QueryOptions raw;
  raw.refineHits = false;
  const auto rawScene = build(field, raw);
  ASSERT_TRUE(rawScene);
  for (const glm::dvec2 p : {glm::dvec2(0.5, 0.5), glm::dvec2(0.25, 0.25), glm::dvec2(0.75, 0.75), glm::dvec2(0.7, 0.1),
                             glm::dvec2(0.1, 0.7), glm::dvec2(0.9, 0.6)}) {
    const auto hit = rawScene->raycast({p.x, p.y, 10.0}, {0.0, 0.0, -1.0});
    ASSERT_TRUE(hit);
    EXPECT_NEAR(hit->point.z, conventionHeight(field, p.x, p.y), 1e-5) << p.x << "," << p.y;
  }
  // The lower-left triangle (0,0), (1,0), (0,1) rises towards +x and +y.
  const auto hit = rawScene->raycast({0.2, 0.2, 10.0}, {0.0, 0.0, -1.0});
  ASSERT_TRUE(hit);
  expectNearVec(hit->normal, glm::normalize(glm::dvec3(-1.0, -1.0, 1.0)), 1e-6);
}

TEST(QueryScene, EmbreeGridSplitMatchesConventionOnRandomField) {
  std::mt19937 noise(4);
  std::uniform_real_distribution<double> h(-10.0, 10.0);
  const auto field = makeField(40, 30, 1.0, 1.0, [&](double, double) { return h(noise); });
  QueryOptions raw;
  raw.refineHits = false;
  raw.blockCells = 16;
  const auto scene = build(field, raw);
  ASSERT_TRUE(scene);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> ux(0.0, field.extentX()), uy(0.0, field.extentY());
  for (int i = 0; i < 2000; ++i) {
    const double x = ux(rng), y = uy(rng);
    const auto hit = scene->raycast({x, y, 50.0}, {0.0, 0.0, -1.0});
    ASSERT_TRUE(hit);
    EXPECT_NEAR(hit->point.z, conventionHeight(field, x, y), 1e-4) << x << "," << y;
  }
}

TEST(QueryScene, RaycastMissesAndDistances) {
  const auto field = makeField(11, 11, 1.0, 1.0, [](double, double) { return 0.0; });
  const auto scene = build(field);
  ASSERT_TRUE(scene);
  EXPECT_FALSE(scene->raycast({5.0, 5.0, 1.0}, {0.0, 0.0, 1.0}));         // pointing up
  EXPECT_FALSE(scene->raycast({5.0, 5.0, 1.0}, {1.0, 0.0, 0.0}));         // parallel above
  EXPECT_FALSE(scene->raycast({-5.0, 5.0, 1.0}, {0.0, 0.0, -1.0}));       // outside the footprint
  EXPECT_FALSE(scene->raycast({5.0, 5.0, 1.0}, {0.0, 0.0, 0.0}));         // no direction
  EXPECT_FALSE(scene->raycast({5.0, 5.0, 10.0}, {0.0, 0.0, -1.0}, 9.5));  // too short
  const auto hit = scene->raycast({5.0, 5.0, 10.0}, {0.0, 0.0, -3.0}, 10.5);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->distance, 10.0, 1e-12);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(scene->raycast({nan, 5.0, 10.0}, {0.0, 0.0, -1.0}));
  // From below, the hit normal faces the ray.
  const auto below = scene->raycast({3.0, 4.0, -2.0}, {0.0, 0.0, 1.0});
  ASSERT_TRUE(below);
  EXPECT_NEAR(below->normal.z, -1.0, 1e-12);
  // minDistance skips the near part of the ray.
  EXPECT_FALSE(scene->raycast(QueryRay{{5.0, 5.0, 10.0}, {0.0, 0.0, -1.0}, 10.5, 20.0}));
}

// Points far beyond any terrain, where single precision overflows Embree's ray checks, see
// nothing: no hit, no line of sight, in single rays and packets alike.
TEST(QueryScene, RaysFromFarBeyondTheTerrainSeeNothing) {
  const auto field = makeField(11, 11, 1.0, 1.0, [](double, double) { return 0.0; });
  const auto scene = build(field);
  ASSERT_TRUE(scene);
  std::vector<QueryRay> rays;
  for (const double far : {1e16, 1e18, -2e18, 1e30, -1e300}) {
    EXPECT_FALSE(scene->raycast({5.0, 5.0, far}, {0.0, 0.0, far > 0 ? -1.0 : 1.0})) << far;
    EXPECT_FALSE(scene->raycast({far, 5.0, 1.0}, {-1.0, 0.0, 0.0})) << far;
    EXPECT_FALSE(scene->lineOfSight({5.0, 5.0, far}, {5.0, 5.0, 1.0})) << far;
    rays.push_back(QueryRay{{5.0, 5.0, far}, {0.0, 0.0, -1.0}, 0.0, 1e300});
    rays.push_back(QueryRay{{5.0, 5.0, 10.0}, {0.0, 0.0, -1.0}, 0.0, 1e300});  // a near ray in the same packet
  }
  // Huge but finite segments from a near origin are fine, and still hit.
  const auto longRay = scene->raycast(QueryRay{{5.0, 5.0, 10.0}, {0.0, 0.0, -1e30}, 0.0, 1e300});
  ASSERT_TRUE(longRay);
  EXPECT_NEAR(longRay->distance, 10.0, 1e-9);
  std::vector<std::optional<RayHit>> hits(rays.size());
  scene->raycastMany(rays, hits);
  for (std::size_t i = 0; i < rays.size(); ++i) EXPECT_EQ(hits[i].has_value(), i % 2 == 1) << i;
}

TEST(QueryScene, LineOfSightOverRidgeAndValley) {
  // A ridge 40 m high along x = 50.
  const auto ridge =
      makeField(101, 21, 1.0, 1.0, [](double x, double) { return std::max(0.0, 40.0 - 2.0 * std::abs(x - 50.0)); });
  const auto ridgeScene = build(ridge);
  ASSERT_TRUE(ridgeScene);
  EXPECT_FALSE(ridgeScene->lineOfSight({10.0, 10.0, 5.0}, {90.0, 10.0, 5.0}));
  EXPECT_FALSE(ridgeScene->lineOfSight({90.0, 10.0, 5.0}, {10.0, 10.0, 5.0}));
  EXPECT_TRUE(ridgeScene->lineOfSight({10.0, 10.0, 45.0}, {90.0, 10.0, 45.0}));
  EXPECT_TRUE(ridgeScene->lineOfSight({10.0, 10.0, 5.0}, {30.0, 12.0, 3.0}));  // same side
  // Points on the surface itself do not hide each other on flat ground.
  EXPECT_TRUE(ridgeScene->lineOfSight({2.0, 3.0, 0.0}, {20.0, 15.0, 0.0}));

  // A valley between two 40 m slopes: the summits see each other across it.
  const auto valley =
      makeField(101, 21, 1.0, 1.0, [](double x, double) { return std::min(40.0, 2.0 * std::abs(x - 50.0)); });
  const auto valleyScene = build(valley);
  ASSERT_TRUE(valleyScene);
  EXPECT_TRUE(valleyScene->lineOfSight({20.0, 10.0, 41.0}, {80.0, 10.0, 41.0}));
  EXPECT_TRUE(valleyScene->lineOfSight({20.0, 10.0, 40.0}, {80.0, 10.0, 40.0}));   // on the summits
  EXPECT_FALSE(valleyScene->lineOfSight({20.0, 10.0, 39.0}, {80.0, 10.0, 41.0}));  // starts inside the slope
  EXPECT_TRUE(valleyScene->lineOfSight({50.0, 10.0, 1.0}, {50.0, 10.0, 1.0}));     // a point
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(valleyScene->lineOfSight({nan, 0.0, 0.0}, {50.0, 10.0, 1.0}));
}

TEST(QueryScene, OutsideTheFootprintIsNothing) {
  const auto field = makeField(9, 7, 2.0, 3.0, test::sinusoid);
  const auto scene = build(field);
  ASSERT_TRUE(scene);
  EXPECT_FALSE(scene->height(-1e-9, 5.0));
  EXPECT_FALSE(scene->height(5.0, -1e-9));
  EXPECT_FALSE(scene->height(field.extentX() + 1e-9, 5.0));
  EXPECT_FALSE(scene->height(5.0, field.extentY() + 1e-9));
  EXPECT_FALSE(scene->height(std::numeric_limits<double>::quiet_NaN(), 5.0));
  EXPECT_TRUE(scene->height(field.extentX(), 0.0));
  EXPECT_FALSE(scene->raycast({field.extentX() + 1.0, 5.0, 100.0}, {0.0, 0.0, -1.0}));
  EXPECT_EQ(scene->boundsMin().x, 0.0);
  EXPECT_EQ(scene->boundsMax().y, field.extentY());
}

TEST(QueryScene, NoDataSamplesLeaveHoles) {
  auto field = makeField(9, 9, 1.0, 1.0, [](double, double) { return 2.0; });
  field.at(4, 4) = std::numeric_limits<float>::quiet_NaN();
  const auto scene = build(field);
  ASSERT_TRUE(scene);
  EXPECT_FALSE(scene->height(4.0, 4.0));
  EXPECT_FALSE(scene->height(3.6, 4.2));
  EXPECT_FALSE(scene->raycast({4.1, 4.1, 10.0}, {0.0, 0.0, -1.0}));
  EXPECT_EQ(scene->height(1.0, 1.0), 2.0);
  EXPECT_TRUE(scene->raycast({1.5, 7.5, 10.0}, {0.0, 0.0, -1.0}));
}

TEST(QueryScene, BlocksJoinWithoutGaps) {
  // 8-cell blocks that do not divide the field: rays along block seams and through
  // shared corners must all hit, with the same answers as a single-block scene.
  const auto field = makeField(37, 29, 1.0, 1.0, test::sinusoid);
  QueryOptions small;
  small.blockCells = 8;
  const auto blocked = build(field, small);
  const auto whole = build(field);
  ASSERT_TRUE(blocked && whole);
  for (double y = 0.0; y < field.extentY(); y += 0.5) {
    for (double x = 0.0; x < field.extentX(); x += 0.5) {
      const auto a = blocked->raycast({x, y, 60.0}, {0.0, 0.0, -1.0});
      const auto b = whole->raycast({x, y, 60.0}, {0.0, 0.0, -1.0});
      ASSERT_TRUE(a && b) << x << "," << y;
      EXPECT_NEAR(a->point.z, conventionHeight(field, x, y), 1e-9);
      EXPECT_NEAR(a->point.z, b->point.z, 1e-9);
    }
  }
  // Slanted rays from every side onto points of the seam x = 8 (corners included).
  for (int i = 0; i <= 200; ++i) {
    const double y = 4.0 + 0.08 * i;
    const glm::dvec3 target(8.0, y, conventionHeight(field, 8.0, y));
    // Steep enough (slopes here reach 7) that nothing earlier lies in the way.
    const glm::dvec3 direction(0.1 * std::cos(i * 0.0314), 0.1 * std::sin(i * 0.0314), -1.0);
    const auto hit = blocked->raycast(target - 2.0 * direction, direction);
    ASSERT_TRUE(hit) << i;
    EXPECT_NEAR(glm::length(hit->point - target), 0.0, 1e-9) << i;
  }
}

TEST(QueryScene, BatchMatchesSingleRays) {
  const auto field = makeField(65, 65, 2.0, 2.0, test::sinusoid);
  const auto scene = build(field);
  ASSERT_TRUE(scene);
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> ux(-10.0, field.extentX() + 10.0), slant(-1.0, 1.0), dist(5.0, 400.0);
  std::vector<QueryRay> rays;
  for (int i = 0; i < 1001; ++i) {
    rays.push_back(
        QueryRay{{ux(rng), ux(rng), 60.0}, {slant(rng), slant(rng), -0.3 - std::abs(slant(rng))}, 0.0, dist(rng)});
  }
  rays[7].direction = glm::dvec3(0.0);  // invalid: no direction
  rays[8].direction.z = 1.0;            // up: misses
  std::vector<std::optional<RayHit>> hits(rays.size(), RayHit{});
  scene->raycastMany(rays, hits);
  int hitCount = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const auto single = scene->raycast(rays[i]);
    ASSERT_EQ(single.has_value(), hits[i].has_value()) << i;
    if (!single) continue;
    ++hitCount;
    expectNearVec(hits[i]->point, single->point, 1e-9);
    expectNearVec(hits[i]->normal, single->normal, 1e-9);
  }
  EXPECT_FALSE(hits[7]);
  EXPECT_FALSE(hits[8]);
  // The coherence hint changes the traversal, not the answers.
  std::vector<std::optional<RayHit>> coherent(rays.size());
  scene->raycastMany(rays, coherent, RayCoherence::Coherent);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    ASSERT_EQ(coherent[i].has_value(), hits[i].has_value()) << i;
    if (coherent[i]) {
      expectNearVec(coherent[i]->point, hits[i]->point, 1e-9);
    }
  }
  EXPECT_GT(hitCount, 300);
}

TEST(QueryScene, ConcurrentQueriesMatchSerialOnes) {
  const auto field = makeField(129, 129, 1.0, 1.0, test::sinusoid);
  const auto scene = build(field);
  ASSERT_TRUE(scene);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> ux(0.0, field.extentX()), slant(-1.0, 1.0);
  std::vector<QueryRay> rays;
  for (int i = 0; i < 2000; ++i) rays.push_back(QueryRay{{ux(rng), ux(rng), 40.0}, {slant(rng), slant(rng), -1.0}});

  struct Answers {
    std::vector<std::optional<double>> heights;
    std::vector<std::optional<RayHit>> hits, batch;
    std::vector<bool> visible;
  };
  const auto answer = [&] {
    Answers out;
    out.batch.resize(rays.size());
    scene->raycastMany(rays, out.batch);
    for (const QueryRay& ray : rays) {
      out.heights.push_back(scene->height(ray.origin.x, ray.origin.y));
      out.hits.push_back(scene->raycast(ray));
      out.visible.push_back(scene->lineOfSight(ray.origin, ray.origin + 60.0 * ray.direction));
    }
    return out;
  };
  const Answers serial = answer();
  std::vector<Answers> parallel(4);
  std::vector<std::thread> threads;
  for (Answers& out : parallel) threads.emplace_back([&] { out = answer(); });
  for (std::thread& thread : threads) thread.join();
  for (const Answers& out : parallel) {
    EXPECT_EQ(out.heights, serial.heights);
    EXPECT_EQ(out.visible, serial.visible);
    for (std::size_t i = 0; i < rays.size(); ++i) {
      ASSERT_EQ(out.hits[i].has_value(), serial.hits[i].has_value());
      ASSERT_EQ(out.batch[i].has_value(), serial.batch[i].has_value());
      if (out.hits[i]) {
        EXPECT_EQ(out.hits[i]->point, serial.hits[i]->point);
      }
      if (out.batch[i]) {
        EXPECT_EQ(out.batch[i]->point, serial.batch[i]->point);
      }
    }
  }
}

TEST(QueryScene, RejectsBadInputWithErrors) {
  EXPECT_EQ(QueryScene::create(terrain::Heightfield(1, 5)).error().kind, ErrorKind::InvalidArgument);
  terrain::Heightfield mismatched(4, 4);
  mismatched.heights.pop_back();
  EXPECT_EQ(QueryScene::create(mismatched).error().kind, ErrorKind::InvalidArgument);
  EXPECT_EQ(QueryScene::create(terrain::Heightfield(4, 4, 0.0, 1.0)).error().kind, ErrorKind::InvalidArgument);
  QueryOptions badBlocks;
  badBlocks.blockCells = 40000;
  EXPECT_EQ(QueryScene::create(terrain::Heightfield(4, 4), badBlocks).error().kind, ErrorKind::InvalidArgument);
}

TEST(QueryScene, DeviceErrorsBecomeErrors) {
  // Embree's memory monitor refuses the BVH past the limit; the device's error callback
  // turns that into an OutOfMemory error from create().
  QueryOptions tight;
  tight.memoryLimitBytes = 64 * 1024;
  const auto scene = QueryScene::create(makeField(129, 129, 1.0, 1.0, test::sinusoid), tight);
  ASSERT_FALSE(scene.ok());
  EXPECT_EQ(scene.error().kind, ErrorKind::OutOfMemory);
  EXPECT_NE(scene.error().message.find("Embree"), std::string::npos) << scene.error().message;

  const auto roomy = QueryScene::create(makeField(129, 129, 1.0, 1.0, test::sinusoid));
  ASSERT_TRUE(roomy.ok());
  EXPECT_GT((*roomy)->memoryBytes(), std::size_t(129 * 129 * 12));
}

}  // namespace
}  // namespace polder::query
