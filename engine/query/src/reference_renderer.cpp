#include <polder/query/reference_renderer.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

#include <polder/terrain/normals.hpp>
#include <polder/thread_pool.hpp>

#include "grid_triangulation.hpp"

namespace polder::query {

namespace {

// Rows share the ray buffers of a task; a few per task keep the tasks many and cheap.
constexpr std::size_t kRowsPerTask = 4;

std::uint8_t toByte(float value) { return std::uint8_t(std::lround(std::clamp(value, 0.0f, 1.0f) * 255.0f)); }

void writePixel(RgbaImage& image, int x, int y, const glm::vec3& colour, std::uint8_t alpha) {
  std::uint8_t* pixel = image.at(x, y);
  pixel[0] = toByte(colour.r);
  pixel[1] = toByte(colour.g);
  pixel[2] = toByte(colour.b);
  pixel[3] = alpha;
}

// The normal GL would interpolate at a hit: the hit triangle's vertex normals weighted by
// the hit's barycentric coordinates.
glm::vec3 interpolatedNormal(const terrain::Heightfield& field, const glm::dvec3& point) {
  const detail::GridTriangle tri =
      detail::gridTriangleAt(field.width, field.height, point.x / field.spacingX, point.y / field.spacingY);
  glm::dvec3 normal(0.0);
  for (std::size_t i = 0; i < 3; ++i) {
    normal += tri.weights[i] * glm::dvec3(terrain::sampleNormal(field, tri.samples[i].x, tri.samples[i].y));
  }
  return glm::vec3(normal);
}

void renderRows(const QueryScene& scene, const terrain::Heightfield& field, const Camera& camera,
                const TerrainStyle& style, int rowBegin, int rowEnd, RgbaImage& image) {
  const glm::dvec3 forward = camera.forward();
  std::vector<QueryRay> rays(std::size_t(camera.widthPx));
  std::vector<std::optional<RayHit>> hits(rays.size());
  for (int y = rowBegin; y < rowEnd; ++y) {
    for (int x = 0; x < camera.widthPx; ++x) {
      const glm::dvec3 direction = camera.pixelRay(x + 0.5, y + 0.5);
      // GL clips at eye depth, distance along forward: a ray's metres to the near and far
      // planes grow as it leans away from the view axis.
      const double depthPerMetre = glm::dot(direction, forward);
      rays[std::size_t(x)] =
          QueryRay{camera.position, direction, camera.nearM / depthPerMetre, camera.farM / depthPerMetre};
    }
    scene.raycastMany(rays, hits, RayCoherence::Coherent);
    for (int x = 0; x < camera.widthPx; ++x) {
      const std::optional<RayHit>& hit = hits[std::size_t(x)];
      if (!hit) {
        writePixel(image, x, y, style.skyColour, 0);
        continue;
      }
      glm::vec3 normal = interpolatedNormal(field, hit->point);
      // Next to no-data samples the vertex normals are undefined: use the face's.
      if (!std::isfinite(normal.x + normal.y + normal.z)) normal = glm::vec3(hit->normal);
      writePixel(image, x, y, shadeTerrain(style, normal, float(hit->point.z), float(hit->distance)), 255);
    }
  }
}

}  // namespace

RgbaImage renderReference(const QueryScene& scene, const terrain::Heightfield& field, const Camera& camera,
                          const TerrainStyle& style, int threads) {
  RgbaImage image(std::max(camera.widthPx, 0), std::max(camera.heightPx, 0));
  if (image.width == 0 || image.height == 0 || field.width < 2 || field.height < 2) return image;

  core::ThreadPool(threads).forRanges(std::size_t(image.height), kRowsPerTask, [&](std::size_t begin, std::size_t end) {
    renderRows(scene, field, camera, style, int(begin), int(end), image);
  });
  return image;
}

}  // namespace polder::query
