// Surface deviation on meshes whose distances are known in closed form, and against brute
// force where they are not.
#include <polder/query/surface_deviation.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include <polder/closest_point_triangle.hpp>

namespace polder::query {
namespace {

using mesh::TriangleMesh;

// The unit square [0, 1]^2 at height z, as two triangles.
TriangleMesh unitSquare(float z) {
  TriangleMesh mesh;
  mesh.positions = {{0, 0, z}, {1, 0, z}, {1, 1, z}, {0, 1, z}};
  mesh.indices = {0, 1, 2, 0, 2, 3};
  return mesh;
}

// The corner tetrahedron (0,0,0), (1,0,0), (0,1,0), apex, faces facing out.
TriangleMesh tetrahedron(glm::vec3 apex) {
  TriangleMesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, apex};
  mesh.indices = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
  return mesh;
}

// A latitude-longitude sphere: rings x segments quads, poles shared.
TriangleMesh sphere(int rings, int segments, float radius) {
  TriangleMesh mesh;
  const double pi = std::numbers::pi;
  mesh.positions.push_back({0, 0, radius});
  for (int r = 1; r < rings; ++r) {
    const double theta = pi * r / rings;
    for (int s = 0; s < segments; ++s) {
      const double phi = 2.0 * pi * s / segments;
      mesh.positions.push_back(
          glm::vec3(glm::dvec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)) *
                    double(radius)));
    }
  }
  mesh.positions.push_back({0, 0, -radius});
  const auto ring = [&](int r, int s) { return std::uint32_t(1 + (r - 1) * segments + (s % segments)); };
  const std::uint32_t south = std::uint32_t(mesh.positions.size() - 1);
  for (int s = 0; s < segments; ++s) {
    mesh.indices.insert(mesh.indices.end(), {0, ring(1, s), ring(1, s + 1)});
    for (int r = 1; r + 1 < rings; ++r) {
      mesh.indices.insert(mesh.indices.end(), {ring(r, s), ring(r + 1, s), ring(r + 1, s + 1)});
      mesh.indices.insert(mesh.indices.end(), {ring(r, s), ring(r + 1, s + 1), ring(r, s + 1)});
    }
    mesh.indices.insert(mesh.indices.end(), {ring(rings - 1, s), south, ring(rings - 1, s + 1)});
  }
  return mesh;
}

SurfaceDeviation measure(const TriangleMesh& original, const TriangleMesh& simplified,
                         SurfaceDeviationOptions options = {}) {
  auto result = measureSurfaceDeviation(original, simplified, options);
  EXPECT_TRUE(result.ok()) << (result.ok() ? "" : result.error().message);
  return result.ok() ? *result : SurfaceDeviation{};
}

TEST(SurfaceDeviation, IdenticalMeshesDoNotDeviate) {
  const TriangleMesh ball = sphere(24, 48, 3.0f);
  const SurfaceDeviation d = measure(ball, ball, {.samplesPerSurface = 20000});
  EXPECT_NEAR(d.hausdorff, 0.0, 1e-12);
  EXPECT_NEAR(d.rms, 0.0, 1e-12);
  EXPECT_TRUE(std::isnan(d.colourRms));  // no colours
  EXPECT_EQ(d.samples, 2 * (20000 + ball.positions.size()));
}

TEST(SurfaceDeviation, PlaneOffsetAlongItsNormal) {
  const double offset = 0.25, diagonal = std::sqrt(2.0);
  const SurfaceDeviation d = measure(unitSquare(0.0f), unitSquare(float(offset)), {.samplesPerSurface = 5000});
  EXPECT_NEAR(d.hausdorff, offset / diagonal, 1e-6);
  EXPECT_NEAR(d.rms, offset / diagonal, 1e-6);
}

TEST(SurfaceDeviation, ApexPushedOutIsSeenFromTheSimplifiedSurface) {
  // The original sits inside the moved one. Its farthest point from the original is the
  // new apex (0,0,2), 1 from the old apex; the original's points are at most 0.2 from the
  // moved surface (the centre of its slanted face), so the maximum comes from the
  // simplified side, and exactly, since vertices are samples.
  const TriangleMesh original = tetrahedron({0, 0, 1}), moved = tetrahedron({0, 0, 2});
  const SurfaceDeviation forward = measure(original, moved);
  EXPECT_NEAR(forward.hausdorff, 1.0 / std::sqrt(3.0), 1e-9);

  // Swapped roles: the same distance over the other diagonal, about the same RMS.
  const SurfaceDeviation backward = measure(moved, original);
  EXPECT_NEAR(backward.hausdorff, 1.0 / std::sqrt(6.0), 1e-9);
  EXPECT_NEAR(forward.rms * std::sqrt(3.0), backward.rms * std::sqrt(6.0), 0.02 * forward.rms * std::sqrt(3.0));
}

TEST(SurfaceDeviation, ApexPulledInIsSeenFromTheOriginalSurface) {
  // The old apex (0,0,1) is 0.5 from the new one (0,0,0.5), its closest point on the
  // pulled-in tetrahedron; every point of that one lies on or inside the original.
  const SurfaceDeviation d = measure(tetrahedron({0, 0, 1}), tetrahedron({0, 0, 0.5f}));
  EXPECT_NEAR(d.hausdorff, 0.5 / std::sqrt(3.0), 1e-9);
}

TEST(SurfaceDeviation, SharedVertexTableWithTrianglesDropped) {
  // One vertex far away that no triangle uses: it is neither sampled nor in the diagonal.
  TriangleMesh original = unitSquare(0.0f);
  original.positions.push_back({5, 5, 5});
  TriangleMesh simplified = original;
  simplified.indices = {0, 1, 2};

  const std::size_t n = 200000;
  const SurfaceDeviation d = measure(original, simplified, {.samplesPerSurface = n});
  EXPECT_EQ(d.samples, 2 * n + 4 + 3);
  // Vertex (0,1) is sqrt(2)/2 from the kept triangle's diagonal; the diagonal is sqrt(2).
  EXPECT_NEAR(d.hausdorff, 0.5, 1e-9);
  // Points on the dropped half lie at distance h from its hypotenuse with E[h^2] = 1/12; half
  // the original's samples fall there, the simplified mesh's are all on the original.
  const double meanSquare = (double(n) / 24.0 + 0.5) / double(d.samples);
  EXPECT_NEAR(d.rms, std::sqrt(meanSquare / 2.0), 0.01 * std::sqrt(meanSquare / 2.0));
}

TEST(SurfaceDeviation, DegenerateTrianglesDoNotDisturb) {
  TriangleMesh square = unitSquare(0.0f);
  TriangleMesh withDegenerates = square;
  withDegenerates.positions.push_back({0.5f, 0.0f, 0.0f});  // on the square's edge
  withDegenerates.positions.push_back({0.3f, 0.6f, 0.0f});  // inside the square
  withDegenerates.indices.insert(withDegenerates.indices.end(), {0, 4, 1, 5, 5, 5, 2, 2, 3});
  const SurfaceDeviation d = measure(square, withDegenerates, {.samplesPerSurface = 5000});
  EXPECT_NEAR(d.hausdorff, 0.0, 1e-12);
  EXPECT_NEAR(d.rms, 0.0, 1e-12);

  // A simplified mesh of zero area: its points are its vertices and edges.
  TriangleMesh point = square;
  point.indices = {0, 0, 0};
  EXPECT_NEAR(measure(square, point, {.samplesPerSurface = 5000}).hausdorff, 1.0, 1e-9);  // (1,1) from (0,0)
  TriangleMesh segment = withDegenerates;
  segment.indices = {0, 4, 1};  // the edge y = 0
  EXPECT_NEAR(measure(square, segment, {.samplesPerSurface = 5000}).hausdorff, 1.0 / std::sqrt(2.0), 1e-9);
}

// Two unit squares 3 apart along x, the first with colour `first`, the second `second`.
TriangleMesh twoColouredSquares(glm::vec4 first, glm::vec4 second) {
  TriangleMesh mesh = unitSquare(0.0f);
  for (int i = 0; i < 4; ++i) mesh.positions.push_back(mesh.positions[std::size_t(i)] + glm::vec3(3, 0, 0));
  mesh.indices.insert(mesh.indices.end(), {4, 5, 6, 4, 6, 7});
  mesh.colours = {first, first, first, first, second, second, second, second};
  return mesh;
}

TEST(SurfaceDeviation, ColourAgainstItselfAndFlipped) {
  const glm::vec4 red(1, 0, 0, 1), cyan(0, 1, 1, 0.25f);
  const TriangleMesh mesh = twoColouredSquares(red, cyan);
  const SurfaceDeviation same = measure(mesh, mesh, {.samplesPerSurface = 20000});
  EXPECT_NEAR(same.colourRms, 0.0, 1e-12);

  // Every channel flipped (c -> 1 - c, alpha too, which is ignored): each RGB channel
  // differs by 1 everywhere.
  const TriangleMesh flipped = twoColouredSquares(glm::vec4(1.0f) - red, glm::vec4(1.0f) - cyan);
  const SurfaceDeviation d = measure(mesh, flipped, {.samplesPerSurface = 20000});
  EXPECT_NEAR(d.colourRms, std::sqrt(3.0), 1e-9);
  EXPECT_NEAR(d.hausdorff, 0.0, 1e-12);
}

TEST(SurfaceDeviation, ColourIsInterpolatedOnBothSides) {
  // Red = x on the original and 1 - x on the copy: the difference 2x - 1 has mean square
  // 1/3 over the square (the four corners, also samples, differ by 1).
  TriangleMesh original = unitSquare(0.0f), mirrored = unitSquare(0.0f);
  for (const glm::vec3& p : original.positions) {
    original.colours.push_back({p.x, 0.5f, 0.5f, 1.0f});
    mirrored.colours.push_back({1.0f - p.x, 0.5f, 0.5f, 1.0f});
  }
  mirrored.indices = {0, 1, 3, 1, 2, 3};  // the other diagonal: different closest triangles
  const std::size_t n = 100000;
  const SurfaceDeviation d = measure(original, mirrored, {.samplesPerSurface = n});
  const double expected = std::sqrt((double(n) / 3.0 + 4.0) / double(n + 4));
  EXPECT_NEAR(d.colourRms, expected, 0.01 * expected);

  TriangleMesh uncoloured = mirrored;
  uncoloured.colours.clear();
  EXPECT_TRUE(std::isnan(measure(original, uncoloured, {.samplesPerSurface = 100}).colourRms));
  EXPECT_TRUE(std::isnan(measure(uncoloured, original, {.samplesPerSurface = 100}).colourRms));
}

// The distance from p to the closest triangle of the mesh, trying every triangle.
double bruteForceDistance(const glm::dvec3& p, const TriangleMesh& mesh) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t t = 0; t < mesh.indices.size(); t += 3) {
    const glm::dvec3 a(mesh.positions[mesh.indices[t]]), b(mesh.positions[mesh.indices[t + 1]]),
        c(mesh.positions[mesh.indices[t + 2]]);
    best = std::min(best, glm::length(p - closestPointOnTriangle(p, a, b, c).point));
  }
  return best;
}

TEST(SurfaceDeviation, EmbreeFindsTheClosestTriangle) {
  // With vertices as the only samples the whole measure can be recomputed by brute force.
  const TriangleMesh original = sphere(20, 40, 2.0f);
  TriangleMesh coarse = sphere(9, 13, 2.1f);
  for (glm::vec3& p : coarse.positions) p = glm::vec3(p.y, p.z, p.x) + glm::vec3(0.05f, -0.1f, 0.02f);

  double maxDistance = 0.0, sumSquares = 0.0;
  for (const glm::vec3& p : original.positions) {
    const double d = bruteForceDistance(glm::dvec3(p), coarse);
    maxDistance = std::max(maxDistance, d), sumSquares += d * d;
  }
  for (const glm::vec3& p : coarse.positions) {
    const double d = bruteForceDistance(glm::dvec3(p), original);
    maxDistance = std::max(maxDistance, d), sumSquares += d * d;
  }
  const std::size_t samples = original.positions.size() + coarse.positions.size();
  const double diagonal = mesh::boundingBoxDiagonal(original.positions);

  const SurfaceDeviation d = measure(original, coarse, {.samplesPerSurface = 0});
  EXPECT_EQ(d.samples, samples);
  EXPECT_NEAR(d.hausdorff, maxDistance / diagonal, 1e-12);
  EXPECT_NEAR(d.rms, std::sqrt(sumSquares / double(samples)) / diagonal, 1e-12);
}

TEST(SurfaceDeviation, SameSeedSameResultOnAnyThreadCount) {
  const TriangleMesh original = sphere(20, 40, 1.0f), coarse = sphere(8, 16, 1.0f);
  const SurfaceDeviation one = measure(original, coarse, {.samplesPerSurface = 30000, .seed = 9, .threads = 1});
  const SurfaceDeviation three = measure(original, coarse, {.samplesPerSurface = 30000, .seed = 9, .threads = 3});
  EXPECT_EQ(one.hausdorff, three.hausdorff);
  EXPECT_EQ(one.rms, three.rms);
  EXPECT_GT(one.rms, 0.0);
  const SurfaceDeviation other = measure(original, coarse, {.samplesPerSurface = 30000, .seed = 10, .threads = 1});
  EXPECT_NE(one.rms, other.rms);
  EXPECT_NEAR(one.rms, other.rms, 0.02 * one.rms);
}

TEST(SurfaceDeviation, RejectsEmptyAndMalformedMeshes) {
  const TriangleMesh square = unitSquare(0.0f);
  TriangleMesh noTriangles = square;  // positions, but no indices
  noTriangles.indices.clear();
  const TriangleMesh empty;
  const auto expectNoTriangles = [](const Result<SurfaceDeviation>& result) {
    ASSERT_FALSE(result.ok());
    EXPECT_EQ(result.error().kind, ErrorKind::InvalidArgument);
    EXPECT_NE(result.error().message.find("no triangles"), std::string::npos) << result.error().message;
  };
  expectNoTriangles(measureSurfaceDeviation(square, empty));
  expectNoTriangles(measureSurfaceDeviation(square, noTriangles));
  expectNoTriangles(measureSurfaceDeviation(empty, square));
  expectNoTriangles(measureSurfaceDeviation(noTriangles, square));

  TriangleMesh outOfRange = square;
  outOfRange.indices.back() = 7;
  EXPECT_FALSE(measureSurfaceDeviation(square, outOfRange).ok());

  TriangleMesh collapsed = square;  // every vertex at one point: no diagonal
  for (glm::vec3& p : collapsed.positions) p = glm::vec3(2.0f);
  auto noExtent = measureSurfaceDeviation(collapsed, square);
  ASSERT_FALSE(noExtent.ok());
  EXPECT_EQ(noExtent.error().kind, ErrorKind::InvalidArgument);
}

}  // namespace
}  // namespace polder::query
