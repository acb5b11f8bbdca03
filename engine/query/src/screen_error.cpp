#include <polder/query/screen_error.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <polder/thread_pool.hpp>

namespace polder::query {

namespace {

// Rows share the ray buffers of a task; a few per task keep the tasks many and cheap.
constexpr std::size_t kRowsPerTask = 4;

// Pixel coordinates (x right, y down) of a world point, or nothing behind the eye.
std::optional<glm::dvec2> project(const glm::dmat4& viewProjection, const Camera& camera, const glm::dvec3& point) {
  const glm::dvec4 clip = viewProjection * glm::dvec4(point - camera.position, 1.0);
  if (clip.w <= 0.0) return std::nullopt;
  return glm::dvec2((clip.x / clip.w * 0.5 + 0.5) * camera.widthPx, (0.5 - clip.y / clip.w * 0.5) * camera.heightPx);
}

// A ray meets the back of a triangle in two ways: through a gap, after running under the
// mesh, or by grazing a ridge on the silhouette, where the ridge's front and back faces share
// the hit point. Just before the hit the first ray is under the mesh, the second above it.
bool cameFromUnderTheMesh(const QueryScene& lodMesh, const QueryRay& ray, const RayHit& hit) {
  const double back = std::max(1e-4 * hit.distance, 1e-3);
  const glm::dvec3 before = hit.point - glm::normalize(ray.direction) * back;
  const std::optional<double> surface = lodMesh.height(before.x, before.y);
  return surface && before.z < *surface;
}

}  // namespace

ScreenError measureScreenError(const QueryScene& lodMesh, const TrueSurface& truth, const Camera& camera,
                               const ScreenErrorOptions& options) {
  const int stride = std::max(options.pixelStride, 1);
  const int columns = (camera.widthPx + stride - 1) / stride;
  const int rows = (camera.heightPx + stride - 1) / stride;
  const glm::dmat4 viewProjection = camera.projection() * camera.viewRotation();
  // Errors per row, gathered afterwards in row order, so that no figure depends on which
  // thread measured which rows.
  std::vector<std::vector<double>> errors(static_cast<std::size_t>(std::max(rows, 0)));
  // Per sampled pixel: 1 where its ray met the LOD mesh from above, 2 from below (for the holes).
  std::vector<std::uint8_t> hitLod(std::size_t(std::max(rows, 0)) * std::size_t(std::max(columns, 0)), 0);
  auto cell = [columns](int row, int column) { return std::size_t(row) * std::size_t(columns) + std::size_t(column); };
  auto measureRows = [&](std::size_t rowBegin, std::size_t rowEnd) {
    std::vector<QueryRay> rays(static_cast<std::size_t>(columns));
    std::vector<std::optional<RayHit>> hits(static_cast<std::size_t>(columns));
    for (int row = int(rowBegin); row < int(rowEnd); ++row) {
      auto& out = errors[std::size_t(row)];
      const double py = row * stride + 0.5;
      for (int column = 0; column < columns; ++column) {
        const double px = column * stride + 0.5;
        rays[std::size_t(column)] = QueryRay{camera.position, camera.pixelRay(px, py), camera.nearM, camera.farM};
      }
      lodMesh.raycastMany(rays, hits, RayCoherence::Coherent);
      for (int column = 0; column < columns; ++column) {
        const auto& hit = hits[std::size_t(column)];
        if (!hit) continue;
        // RayHit::normal faces against the ray; terrain triangles face up.
        const bool fromAbove = hit->normal.z > 0.0 || !cameFromUnderTheMesh(lodMesh, rays[std::size_t(column)], *hit);
        hitLod[cell(row, column)] = fromAbove ? 1 : 2;
        const auto trueHeight = truth.height(hit->point.x, hit->point.y);
        if (!trueHeight) continue;
        const auto drawn = project(viewProjection, camera, hit->point);
        const auto actual = project(viewProjection, camera, {hit->point.x, hit->point.y, *trueHeight});
        if (!drawn || !actual) continue;
        out.push_back(glm::length(*drawn - *actual));
      }
    }
  };
  core::ThreadPool(options.threads).forRanges(errors.size(), kRowsPerTask, measureRows);

  ScreenError result;
  auto hitAt = [&](int row, int column) { return hitLod[cell(row, column)]; };
  for (int column = 0; column < columns; ++column) {
    // Misses between the column's first and last hit are enclosed by the mesh.
    int first = rows, last = -1;
    for (int row = 0; row < rows; ++row)
      if (hitAt(row, column)) first = std::min(first, row), last = row;
    for (int row = 0; row < rows; ++row) {
      if (hitAt(row, column) == 2) {
        ++result.holePixels;
        continue;
      }
      if (hitAt(row, column) || row < first || row > last) continue;
      const QueryRay ray{camera.position, camera.pixelRay(column * stride + 0.5, row * stride + 0.5), camera.nearM,
                         camera.farM};
      if (truth.meets(ray)) ++result.holePixels;
    }
  }

  std::vector<double> all;
  for (auto& band : errors) all.insert(all.end(), band.begin(), band.end());
  result.pixelsMeasured = all.size();
  if (all.empty()) return result;
  double sum = 0.0;
  for (double e : all) sum += e, result.maxPx = std::max(result.maxPx, e);
  result.meanPx = sum / double(all.size());
  const std::size_t rank = std::min(all.size() - 1, std::size_t(std::ceil(0.99 * double(all.size()))) - 1);
  std::nth_element(all.begin(), all.begin() + std::ptrdiff_t(rank), all.end());
  result.p99Px = all[rank];
  return result;
}

}  // namespace polder::query
