// The dike check as a property: over rough DEMs in error mode, no drawn dike triangle is
// over tau on screen, by brute force. Each dike triangle is a plane through three samples;
// the test walks a quarter-cell lattice over it, takes the true surface below each point
// (the heightfield's own triangulation), projects both points with an
// independent pinhole model and compares the pixel distance with tau. The lattice can only
// miss error, so any excess it finds is real. White noise at the sample scale is what
// pins cannot cure, so the node-split path must run.
#include <polder/terrain_engine.hpp>

#include <algorithm>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "heightfield_surface.hpp"
#include "pinhole_camera.hpp"

namespace polder {
namespace {

// The largest on-screen distance between a drawn dike point and the surface below it.
double worstDikePixelError(const terrain::Heightfield& field, const TerrainDikes& dikes, const Camera& camera) {
  double worst = 0.0;
  auto measure = [&](double sx, double sy, double drawnHeight) {
    const glm::dvec3 drawn(sx * field.spacingX, sy * field.spacingY, drawnHeight);
    const glm::dvec3 truth(drawn.x, drawn.y, test::conventionHeight(field, drawn.x, drawn.y));
    const test::PinholePixel a = test::pinholePixel(camera, drawn), b = test::pinholePixel(camera, truth);
    if (a.onScreen && b.onScreen) worst = std::max(worst, glm::length(a.pixel - b.pixel));
  };
  for (std::size_t t = 0; t + 2 < dikes.indices.size(); t += 3) {
    glm::dvec3 corner[3];
    for (int k = 0; k < 3; ++k) {
      const terrain::DikeVertex v = dikes.vertices[dikes.indices[t + std::size_t(k)]];
      corner[k] = {double(v.x), double(v.y), double(field.at(v.x, v.y))};
    }
    const double longest =
        std::max({glm::length(glm::dvec2(corner[1] - corner[0])), glm::length(glm::dvec2(corner[2] - corner[1])),
                  glm::length(glm::dvec2(corner[0] - corner[2]))});
    const int n = std::max(2, int(std::ceil(4.0 * longest)));  // a quarter of a cell apart
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        const double u = double(i) / n, v = double(j) / n;
        const glm::dvec3 p = corner[0] + u * (corner[1] - corner[0]) + v * (corner[2] - corner[0]);
        measure(p.x, p.y, p.z);
      }
  }
  return worst;
}

std::shared_ptr<terrain::Heightfield> whiteNoise(int size, std::uint32_t seed, double amplitudeM) {
  auto field = std::make_shared<terrain::Heightfield>(size, size, 10.0, 10.0);
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> noise(-amplitudeM, amplitudeM);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x)
      field->at(x, y) = float(300.0 * std::sin(x * 0.02) * std::cos(y * 0.03) + noise(random));
  return field;
}

TEST(DikeProperty, NoDrawnDikeTriangleExceedsTauOnRoughDems) {
  std::size_t splits = 0, frames = 0, dikeTriangles = 0;
  double worstOverall = 0.0;
  for (const std::uint32_t seed : {1u, 2u, 3u}) {
    const auto field = whiteNoise(257, seed, 25.0);
    TerrainEngineOptions options;
    options.tauPx = 1.0;
    options.loading = BlockLoading::Immediate;
    auto engine = TerrainEngine::create(field, options);
    ASSERT_TRUE(engine.ok()) << engine.error().message;
    std::mt19937 random(seed * 7 + 1);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (int view = 0; view < 12; ++view) {
      Camera camera;
      camera.widthPx = 320;
      camera.heightPx = 240;
      camera.fovYDeg = 40.0 + 30.0 * unit(random);
      camera.position = {field->extentX() * unit(random), field->extentY() * unit(random),
                         350.0 + 1500.0 * unit(random)};
      camera.yawDeg = 360.0 * unit(random);
      camera.pitchDeg = -10.0 - 60.0 * unit(random);
      camera.nearM = 1.0;
      camera.farM = 1e6;
      const TerrainFrame& frame = (*engine)->update(camera);
      ++frames;
      splits += frame.stats.dikeSplits;
      dikeTriangles += frame.dikes.indices.size() / 3;
      EXPECT_EQ(frame.stats.dikeTrianglesOverTau, 0u) << "seed " << seed << " view " << view;
      const double worst = worstDikePixelError(*field, frame.dikes, camera);
      EXPECT_LE(worst, options.tauPx + 1e-6) << "seed " << seed << " view " << view;
      worstOverall = std::max(worstOverall, worst);
      EXPECT_LE(worst, frame.stats.dikeErrorPx + 1e-6) << "the check's bound must hold the brute-force figure";
    }
  }
  EXPECT_GT(dikeTriangles, 1000u);
  EXPECT_GT(splits, 0u) << "no frame took the node-split path over " << frames << " frames";
  // The brute force sees the dikes' error close to tau: it measures something.
  EXPECT_GT(worstOverall, 0.25 * 1.0);
  std::printf("%zu frames, %zu dike triangles, %zu node splits, worst %.3f px\n", frames, dikeTriangles, splits,
              worstOverall);
}

}  // namespace
}  // namespace polder
