// closestPointOnTriangle against brute force and against the exact optimality condition:
// q is the closest point of a convex set to p exactly when (p - q) . (x - q) <= 0 for every
// x in the set, so it suffices to check the three vertices.
#include <polder/closest_point_triangle.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

namespace polder {
namespace {

constexpr double kTolerance = 1e-10;

// The seven Voronoi regions a result can lie in, read from which weights are zero.
enum Region { kVertexA, kVertexB, kVertexC, kEdgeAB, kEdgeBC, kEdgeCA, kFace, kRegionCount };

Region regionOf(const glm::dvec3& w) {
  const bool a = w.x > 0.0, b = w.y > 0.0, c = w.z > 0.0;
  if (a && b && c) return kFace;
  if (a && b) return kEdgeAB;
  if (b && c) return kEdgeBC;
  if (c && a) return kEdgeCA;
  if (a) return kVertexA;
  return b ? kVertexB : kVertexC;
}

// The closest of a dense barycentric grid of points on the triangle.
double bruteForceDistance(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c,
                          int steps) {
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= steps; ++i) {
    for (int j = 0; i + j <= steps; ++j) {
      const double v = double(i) / steps, w = double(j) / steps;
      best = std::min(best, glm::length(p - ((1.0 - v - w) * a + v * b + w * c)));
    }
  }
  return best;
}

// Checks the result is on the triangle, consistent with its weights and optimal.
void expectExact(const TrianglePoint& r, const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
                 const glm::dvec3& c) {
  EXPECT_GE(r.weights.x, 0.0);
  EXPECT_GE(r.weights.y, 0.0);
  EXPECT_GE(r.weights.z, 0.0);
  EXPECT_NEAR(r.weights.x + r.weights.y + r.weights.z, 1.0, 1e-12);
  const glm::dvec3 combined = r.weights.x * a + r.weights.y * b + r.weights.z * c;
  EXPECT_NEAR(glm::length(combined - r.point), 0.0, 1e-12);
  for (const glm::dvec3& x : {a, b, c}) EXPECT_LE(glm::dot(p - r.point, x - r.point), kTolerance);
}

TEST(ClosestPointOnTriangle, KnownAnswersInEveryRegion) {
  const glm::dvec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  struct Case {
    glm::dvec3 p, expected;
    Region region;
  };
  const Case cases[] = {
      {{-1, -1, 1}, {0, 0, 0}, kVertexA},    {{2, -0.5, 3}, {1, 0, 0}, kVertexB},
      {{-0.5, 2, -1}, {0, 1, 0}, kVertexC},  {{0.5, -1, 2}, {0.5, 0, 0}, kEdgeAB},
      {{1, 1, -4}, {0.5, 0.5, 0}, kEdgeBC},  {{-1, 0.25, 0}, {0, 0.25, 0}, kEdgeCA},
      {{0.2, 0.3, 5}, {0.2, 0.3, 0}, kFace}, {{0.2, 0.3, 0}, {0.2, 0.3, 0}, kFace},
  };
  for (const Case& test : cases) {
    const TrianglePoint r = closestPointOnTriangle(test.p, a, b, c);
    EXPECT_NEAR(glm::length(r.point - test.expected), 0.0, 1e-15) << test.p.x << "," << test.p.y << "," << test.p.z;
    EXPECT_EQ(regionOf(r.weights), test.region) << test.p.x << "," << test.p.y << "," << test.p.z;
    expectExact(r, test.p, a, b, c);
  }
}

TEST(ClosestPointOnTriangle, MatchesBruteForceOnRandomInputsInAllRegions) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> corner(-1.0, 1.0), query(-2.5, 2.5);
  const auto randomPoint = [&](auto& distribution) {
    return glm::dvec3(distribution(rng), distribution(rng), distribution(rng));
  };
  constexpr int kSteps = 60;
  std::array<int, kRegionCount> hits{};
  for (int trial = 0; trial < 6000; ++trial) {
    const glm::dvec3 a = randomPoint(corner), b = randomPoint(corner), c = randomPoint(corner);
    // Points near the plane land in the face region more often than uniform ones would.
    glm::dvec3 p = randomPoint(query);
    if (trial % 3 == 0) p = (a + b + c) / 3.0 + 0.3 * (p - (a + b + c) / 3.0);
    const TrianglePoint r = closestPointOnTriangle(p, a, b, c);
    expectExact(r, p, a, b, c);
    const double distance = glm::length(p - r.point);
    const double brute = bruteForceDistance(p, a, b, c, kSteps);
    // The grid's nearest point is at most one grid cell (its longest edge) from r.point.
    const double cell = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)}) / kSteps;
    EXPECT_LE(distance, brute + 1e-12);
    EXPECT_GE(distance, brute - cell);
    ++hits[regionOf(r.weights)];
    if (HasFailure()) FAIL() << "trial " << trial;
  }
  for (int region = 0; region < kRegionCount; ++region) EXPECT_GE(hits[region], 100) << "region " << region;
}

TEST(ClosestPointOnTriangle, DegenerateTrianglesAreTheirEdges) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  const glm::dvec3 x(0.1, -0.2, 0.3), y(1.1, 0.8, -0.7);
  const std::array<std::array<glm::dvec3, 3>, 5> triangles = {{
      {x, x, x},                  // one point
      {x, y, y},                  // two coincident corners
      {x, 0.5 * (x + y), y},      // collinear, middle corner between
      {0.5 * (x + y), x, y},      // collinear, middle corner first
      {x, y, x + 3.0 * (y - x)},  // collinear, corner beyond
  }};
  for (const auto& t : triangles) {
    for (int i = 0; i < 500; ++i) {
      const glm::dvec3 p(u(rng), u(rng), u(rng));
      const TrianglePoint r = closestPointOnTriangle(p, t[0], t[1], t[2]);
      ASSERT_TRUE(std::isfinite(r.point.x) && std::isfinite(r.point.y) && std::isfinite(r.point.z));
      expectExact(r, p, t[0], t[1], t[2]);
      EXPECT_LE(glm::length(p - r.point), bruteForceDistance(p, t[0], t[1], t[2], 200) + 1e-12);
    }
  }
}

TEST(ClosestPointOnTriangle, ThinTrianglesStayExact) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (double height : {1e-3, 1e-6, 1e-9, 1e-12}) {
    const glm::dvec3 a(0, 0, 0), b(1, 0, 0), c(0.4, height, 0);
    for (int i = 0; i < 2000; ++i) {
      const glm::dvec3 p(0.5 + u(rng), u(rng), u(rng));
      const TrianglePoint r = closestPointOnTriangle(p, a, b, c);
      expectExact(r, p, a, b, c);
      EXPECT_LE(glm::length(p - r.point), bruteForceDistance(p, a, b, c, 100) + 1e-12);
    }
  }
}

}  // namespace
}  // namespace polder
