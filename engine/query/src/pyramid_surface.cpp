#include <polder/query/pyramid_surface.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "grid_triangulation.hpp"
#include "ray_triangle.hpp"

namespace polder::query {

namespace {

// Barycentric slack for rays through shared edges (ray_triangle.hpp).
constexpr double kEdgeTolerance = 1e-9;

// The ray's parameter interval inside the box, clipped to [t0, t1]; empty when first > second.
std::pair<double, double> slabs(const glm::dvec3& origin, const glm::dvec3& direction, const glm::dvec3& low,
                                const glm::dvec3& high, double t0, double t1) {
  for (int axis = 0; axis < 3; ++axis) {
    if (direction[axis] == 0.0) {
      if (origin[axis] < low[axis] || origin[axis] > high[axis]) return {1.0, 0.0};
      continue;
    }
    const double inverse = 1.0 / direction[axis];
    double near = (low[axis] - origin[axis]) * inverse, far = (high[axis] - origin[axis]) * inverse;
    if (near > far) std::swap(near, far);
    t0 = std::max(t0, near);
    t1 = std::min(t1, far);
    if (t0 > t1) break;
  }
  return {t0, t1};
}

}  // namespace

PyramidSurface::PyramidSurface(std::shared_ptr<const terrain::Pyramid> pyramid, std::size_t tileBytes)
    : m_pyramid(std::move(pyramid)), m_tiles(tileBytes) {}

std::string PyramidSurface::firstFailure() const {
  std::lock_guard lock(m_mutex);
  return m_firstFailure;
}

PyramidSurface::Tile PyramidSurface::levelZeroTile(int bx, int by) const {
  const terrain::NodeId node{0, std::uint32_t(bx), std::uint32_t(by)};
  const std::uint64_t key = terrain::nodeKey(node);
  {
    std::lock_guard lock(m_mutex);
    if (const Tile* held = m_tiles.find(key)) return *held;
  }
  // Read outside the lock: two threads may read the same tile once each, which is harmless.
  terrain::PyramidTile tile;
  if (Status read = m_pyramid->readTile(node, tile); !read) {
    std::lock_guard lock(m_mutex);
    if (m_failures++ == 0) m_firstFailure = read.error().message;
    return nullptr;
  }
  auto shared = std::make_shared<const terrain::Heightfield>(std::move(tile.samples));
  const std::size_t bytes = shared->heights.size() * sizeof(float) + sizeof(terrain::Heightfield);
  std::lock_guard lock(m_mutex);
  return m_tiles.insert(key, shared, bytes);
}

std::optional<double> PyramidSurface::height(double x, double y) const {
  const terrain::PyramidHeader& header = m_pyramid->header();
  const double sx = x / header.spacingX, sy = y / header.spacingY;
  if (!(sx >= 0.0 && sy >= 0.0 && sx <= header.width - 1 && sy <= header.height - 1)) return std::nullopt;
  const detail::GridTriangle under = detail::gridTriangleAt(header.width, header.height, sx, sy);
  // One level-0 footprint holds the whole cell.
  const int cx = std::clamp(int(std::floor(sx)), 0, header.width - 2);
  const int cy = std::clamp(int(std::floor(sy)), 0, header.height - 2);
  const int pitch = m_pyramid->layout().pitch();
  const int bx = cx / pitch, by = cy / pitch;
  const Tile tile = levelZeroTile(bx, by);
  if (!tile) return std::nullopt;
  double h = 0.0;
  for (int corner = 0; corner < 3; ++corner) {
    const float sample = tile->at(under.samples[corner].x - bx * pitch, under.samples[corner].y - by * pitch);
    if (!std::isfinite(sample)) return std::nullopt;
    h += under.weights[corner] * double(sample);
  }
  return h;
}

bool PyramidSurface::meets(const QueryRay& ray) const {
  const double length = glm::length(ray.direction);
  if (!(length > 0.0) || !std::isfinite(length)) return false;
  const double tMin = ray.minDistance / length, tMax = ray.maxDistance / length;
  const terrain::BlockLayout& layout = m_pyramid->layout();
  const terrain::PyramidHeader& header = m_pyramid->header();
  // Depth first, the nearer child first is not needed: any hit answers.
  std::vector<terrain::NodeId> stack{layout.root()};
  while (!stack.empty()) {
    const terrain::NodeId node = stack.back();
    stack.pop_back();
    const terrain::SampleRect area = layout.footprint(node);
    const terrain::PyramidNode& info = m_pyramid->node(node);
    const glm::dvec3 low(area.x0 * header.spacingX, area.y0 * header.spacingY, double(info.minHeight));
    const glm::dvec3 high(area.x1 * header.spacingX, area.y1 * header.spacingY, double(info.maxHeight));
    const auto [t0, t1] = slabs(ray.origin, ray.direction, low, high, tMin, tMax);
    if (t0 > t1) continue;
    if (node.level == 0) {
      if (meetsCells(node, ray, t0, t1)) return true;
      continue;
    }
    for (int quadrant = 0; quadrant < 4; ++quadrant) {
      const terrain::NodeId child = node.child(quadrant);
      if (layout.exists(child)) stack.push_back(child);
    }
  }
  return false;
}

// The cells of a level-0 node under the part [t0, t1] of the ray.
bool PyramidSurface::meetsCells(const terrain::NodeId& node, const QueryRay& ray, double t0, double t1) const {
  const terrain::PyramidHeader& header = m_pyramid->header();
  const terrain::SampleRect area = m_pyramid->layout().footprint(node);
  const Tile tile = levelZeroTile(int(node.bx), int(node.by));
  if (!tile) return false;
  const glm::dvec3 a = ray.origin + t0 * ray.direction, b = ray.origin + t1 * ray.direction;
  const auto cellRange = [](double u0, double u1, int first, int last) {
    const int from = std::clamp(int(std::floor(std::min(u0, u1))), first, last - 1);
    const int to = std::clamp(int(std::floor(std::max(u0, u1))), first, last - 1);
    return std::pair{from, to};
  };
  const auto [cx0, cx1] = cellRange(a.x / header.spacingX, b.x / header.spacingX, area.x0, area.x1);
  const auto [cy0, cy1] = cellRange(a.y / header.spacingY, b.y / header.spacingY, area.y0, area.y1);
  const auto point = [&](const glm::ivec2& sample) {
    return glm::dvec3(sample.x * header.spacingX, sample.y * header.spacingY,
                      double(tile->at(sample.x - area.x0, sample.y - area.y0)));
  };
  for (int cy = cy0; cy <= cy1; ++cy)
    for (int cx = cx0; cx <= cx1; ++cx)
      for (const detail::TriangleSamples& triangle : detail::cellTriangles(cx, cy)) {
        const glm::dvec3 p0 = point(triangle[0]), p1 = point(triangle[1]), p2 = point(triangle[2]);
        if (!std::isfinite(p0.z) || !std::isfinite(p1.z) || !std::isfinite(p2.z)) continue;
        const auto hit = detail::intersectTriangle(ray.origin, ray.direction, p0, p1, p2, kEdgeTolerance);
        if (hit && hit->t >= t0 && hit->t <= t1) return true;
      }
  return false;
}

}  // namespace polder::query
