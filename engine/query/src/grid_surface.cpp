#include "grid_surface.hpp"

#include <algorithm>
#include <cmath>

#include "grid_triangulation.hpp"
#include "ray_triangle.hpp"

namespace polder::query::detail {

namespace {
// Barycentric slack when re-intersecting in double: far below any float effect, enough
// that a ray through a shared edge or vertex is not lost to double rounding.
constexpr double kEdgeTolerance = 1e-9;
}  // namespace

GridSurface::GridSurface(const terrain::Heightfield& field, const glm::dvec3& sceneOrigin)
    : m_width(field.width), m_height(field.height), m_spacingX(field.spacingX), m_spacingY(field.spacingY) {
  m_vertices.resize(vertexCount() * 3 + 1, 0.0f);
  float* out = m_vertices.data();
  for (int y = 0; y < m_height; ++y) {
    const float vy = float(y * m_spacingY - sceneOrigin.y);
    for (int x = 0; x < m_width; ++x) {
      *out++ = float(x * m_spacingX - sceneOrigin.x);
      *out++ = vy;
      *out++ = field.at(x, y);
    }
  }
}

std::optional<double> GridSurface::heightAt(double x, double y) const {
  const double sx = x / m_spacingX;
  const double sy = y / m_spacingY;
  // Written so that NaN coordinates fail too.
  if (!(sx >= 0.0 && sx <= m_width - 1 && sy >= 0.0 && sy <= m_height - 1)) return std::nullopt;
  const GridTriangle tri = gridTriangleAt(m_width, m_height, sx, sy);
  double z = 0.0;
  for (int i = 0; i < 3; ++i)
    z += tri.weights[std::size_t(i)] * sample(tri.samples[std::size_t(i)].x, tri.samples[std::size_t(i)].y).z;
  if (!std::isfinite(z)) return std::nullopt;
  return z;
}

std::optional<SurfaceHit> GridSurface::intersectCells(const glm::dvec3& origin, const glm::dvec3& direction,
                                                      double tMin, double tMax, int cx0, int cy0, int cx1,
                                                      int cy1) const {
  std::optional<SurfaceHit> best;
  for (int cy = std::max(cy0, 0); cy <= std::min(cy1, m_height - 2); ++cy) {
    for (int cx = std::max(cx0, 0); cx <= std::min(cx1, m_width - 2); ++cx) {
      for (const TriangleSamples& tri : cellTriangles(cx, cy)) {
        const glm::dvec3 p0 = sample(tri[0].x, tri[0].y);
        const glm::dvec3 p1 = sample(tri[1].x, tri[1].y);
        const glm::dvec3 p2 = sample(tri[2].x, tri[2].y);
        const auto hit = intersectTriangle(origin, direction, p0, p1, p2, kEdgeTolerance);
        if (!hit || !(hit->t >= tMin && hit->t <= tMax) || (best && hit->t >= best->t)) continue;
        best = SurfaceHit{hit->t, glm::normalize(glm::cross(p1 - p0, p2 - p0))};
      }
    }
  }
  return best;
}

std::optional<SurfaceHit> GridSurface::intersectNear(const glm::dvec3& origin, const glm::dvec3& direction, double tMin,
                                                     double tMax, int cx, int cy) const {
  if (auto hit = intersectCells(origin, direction, tMin, tMax, cx, cy, cx, cy)) return hit;
  return intersectCells(origin, direction, tMin, tMax, cx - 1, cy - 1, cx + 1, cy + 1);
}

}  // namespace polder::query::detail
