#include "pyramid_dike_bound.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

#include <polder/mix_bits.hpp>

namespace polder {

namespace {

std::uint64_t keyOf(const terrain::NodeId& node) {
  return (std::uint64_t(node.level) << 56) | (std::uint64_t(node.bx) << 28) | std::uint64_t(node.by);
}

struct Point {
  double x, y;
};

// Whether the closed triangle and the closed axis-aligned square [x0, x1] x [y0, y1] meet
// (separating axes: the square's two and the triangle's three edge normals).
bool meets(const Point (&t)[3], double x0, double y0, double x1, double y1) {
  if (std::max({t[0].x, t[1].x, t[2].x}) < x0 || std::min({t[0].x, t[1].x, t[2].x}) > x1) return false;
  if (std::max({t[0].y, t[1].y, t[2].y}) < y0 || std::min({t[0].y, t[1].y, t[2].y}) > y1) return false;
  const Point corners[4] = {{x0, y0}, {x1, y0}, {x0, y1}, {x1, y1}};
  for (int e = 0; e < 3; ++e) {
    const Point& p = t[e];
    const Point& q = t[(e + 1) % 3];
    const Point& r = t[(e + 2) % 3];
    const double nx = q.y - p.y, ny = p.x - q.x;  // a normal of edge pq
    const double side = nx * (r.x - p.x) + ny * (r.y - p.y);
    bool allOutside = true;
    for (const Point& c : corners) {
      const double d = nx * (c.x - p.x) + ny * (c.y - p.y);
      if (side > 0.0 ? d >= 0.0 : d <= 0.0) allOutside = false;
    }
    if (allOutside) return false;
  }
  return true;
}

struct Corner {
  double x, y;
  float h;
};

// The largest |plane - level triangle| over the part of `t` inside the level triangle (a, b,
// c), counter-clockwise: both are linear there, so it is largest at a corner of the clipped
// polygon. 0 when they do not overlap.
template <class Plane>
double largestDifference(const Point (&t)[3], const Plane& plane, const Corner& a, const Corner& b, const Corner& c) {
  Point polygon[9], clipped[9];
  int count = 3;
  for (int i = 0; i < 3; ++i) polygon[i] = t[i];
  const Corner* edge[3][2] = {{&a, &b}, {&b, &c}, {&c, &a}};
  for (const auto& e : edge) {
    const Corner& p = *e[0];
    const Corner& q = *e[1];
    // Inside: left of p -> q (the level triangle is counter-clockwise).
    const auto side = [&](const Point& r) { return (q.x - p.x) * (r.y - p.y) - (q.y - p.y) * (r.x - p.x); };
    int out = 0;
    for (int i = 0; i < count; ++i) {
      const Point& r = polygon[i];
      const Point& next = polygon[(i + 1) % count];
      const double sr = side(r), sn = side(next);
      if (sr >= 0.0) clipped[out++] = r;
      if ((sr > 0.0 && sn < 0.0) || (sr < 0.0 && sn > 0.0)) {
        const double f = sr / (sr - sn);
        clipped[out++] = Point{r.x + f * (next.x - r.x), r.y + f * (next.y - r.y)};
      }
    }
    count = out;
    if (count == 0) return 0.0;
    for (int i = 0; i < count; ++i) polygon[i] = clipped[i];
  }
  // The level triangle's plane.
  const double ux = b.x - a.x, uy = b.y - a.y, uz = double(b.h) - a.h;
  const double wx = c.x - a.x, wy = c.y - a.y, wz = double(c.h) - a.h;
  const double det = ux * wy - uy * wx;
  const double px = (uz * wy - uy * wz) / det, py = (ux * wz - uz * wx) / det;
  double largest = 0.0;
  for (int i = 0; i < count; ++i) {
    const double level = double(a.h) + px * (polygon[i].x - a.x) + py * (polygon[i].y - a.y);
    largest = std::max(largest, std::abs(plane(polygon[i].x, polygon[i].y) - level));
  }
  return largest;
}

}  // namespace

void PyramidDikeBound::setFrame(std::span<const terrain::SelectedNode> cut, const DikeVertexSamples& samples) {
  m_cut = cut;
  m_samples = &samples;
  m_indexed = false;
}

void PyramidDikeBound::indexCut() const {
  const std::size_t size = std::bit_ceil(std::max<std::size_t>(4 * m_cut.size(), 64));
  if (m_slots.size() < size) m_slots.resize(size);
  std::fill(m_slots.begin(), m_slots.end(), Slot{});
  const std::size_t mask = m_slots.size() - 1;
  for (std::size_t i = 0; i < m_cut.size(); ++i) {
    const std::uint64_t key = keyOf(m_cut[i].node);
    std::size_t slot = std::size_t(mixBits(key)) & mask;
    while (m_slots[slot].index != kNone) slot = (slot + 1) & mask;
    m_slots[slot] = Slot{key, std::uint32_t(i)};
  }
  m_indexed = true;
}

std::uint32_t PyramidDikeBound::cutNodeAt(int x, int y) const {
  if (!m_indexed) indexCut();
  const std::size_t mask = m_slots.size() - 1;
  for (int level = 0; level <= m_layout.rootLevel(); ++level) {
    const int span = m_layout.pitch() << level;
    const terrain::NodeId node{std::uint8_t(level), std::uint32_t(x / span), std::uint32_t(y / span)};
    if (!m_layout.exists(node)) continue;
    const std::uint64_t key = keyOf(node);
    for (std::size_t slot = std::size_t(mixBits(key)) & mask; m_slots[slot].index != kNone; slot = (slot + 1) & mask)
      if (m_slots[slot].key == key) return m_slots[slot].index;
  }
  return kNone;
}

float PyramidDikeBound::error(const terrain::DikeVertex& a, const terrain::DikeVertex& b, const terrain::DikeVertex& c,
                              const terrain::DikeTriangleRef& where) const {
  const terrain::DikeVertex v[3] = {a, b, c};
  double z[3];
  for (int i = 0; i < 3; ++i) z[i] = double(height(v[i], where.vertices[i]));
  // The plane z = p0 + px x + py y through the three vertices.
  const double ux = v[1].x - v[0].x, uy = v[1].y - v[0].y, uz = z[1] - z[0];
  const double wx = v[2].x - v[0].x, wy = v[2].y - v[0].y, wz = z[2] - z[0];
  const double det = ux * wy - uy * wx;
  const float fallback = m_pyramid.node(m_cut[where.owner].node).dikeRange;
  if (det == 0.0) return fallback;
  const double px = (uz * wy - uy * wz) / det, py = (ux * wz - uz * wx) / det;
  const auto plane = [&](double x, double y) { return z[0] + px * (x - v[0].x) + py * (y - v[0].y); };
  const Point triangle[3] = {{double(a.x), double(a.y)}, {double(b.x), double(b.y)}, {double(c.x), double(c.y)}};

  const int tx0 = std::min({a.x, b.x, c.x}), tx1 = std::max({a.x, b.x, c.x});
  const int ty0 = std::min({a.y, b.y, c.y}), ty1 = std::max({a.y, b.y, c.y});
  std::uint32_t candidates[7];
  int count = 0;
  const auto add = [&](std::uint32_t node) {
    if (node == kNone || std::find(candidates, candidates + count, node) != candidates + count) return;
    candidates[count++] = node;
  };
  for (int i = 0; i < 3; ++i) add(m_samples->vertexNodes[where.vertices[i]]);
  const int cx1 = std::max(tx0, tx1 - 1), cy1 = std::max(ty0, ty1 - 1);
  add(cutNodeAt(tx0, ty0));
  add(cutNodeAt(cx1, ty0));
  add(cutNodeAt(tx0, cy1));
  add(cutNodeAt(cx1, cy1));

  // Over the part of T in node N's footprint the full resolution lies in N's height range and
  // the plane between T's lowest and highest vertex: a bound wherever N's tile falls short.
  const double zLow = std::min({z[0], z[1], z[2]}), zHigh = std::max({z[0], z[1], z[2]});
  std::int64_t covered = 0;
  double bound = 0.0;
  for (int n = 0; n < count; ++n) {
    const terrain::NodeId& node = m_cut[candidates[n]].node;
    const terrain::SampleRect footprint = m_layout.footprint(node);
    const int fx0 = std::max(tx0, footprint.x0), fx1 = std::min(tx1, footprint.x1);
    const int fy0 = std::max(ty0, footprint.y0), fy1 = std::min(ty1, footprint.y1);
    if (fx1 <= fx0 || fy1 <= fy0) continue;
    const std::int64_t area = std::int64_t(fx1 - fx0) * std::int64_t(fy1 - fy0);
    covered += area;
    const terrain::PyramidNode& data = m_pyramid.node(node);
    const double byRange = std::max(zHigh - double(data.minHeight), double(data.maxHeight) - zLow);
    const SampleGrid& grid = m_samples->cut[candidates[n]];
    if (!grid.samples) {
      bound = std::max(bound, byRange);
      continue;
    }
    // The tile's level surface over the same part, plus the residual, where the tile covers it.
    const int s = grid.stride;
    const int rx1 = std::min(fx1, grid.x0 + (grid.samples->width - 1) * s);
    const int ry1 = std::min(fy1, grid.y0 + (grid.samples->height - 1) * s);
    if (std::int64_t(rx1 - fx0) * std::int64_t(ry1 - fy0) != area || rx1 <= fx0 || ry1 <= fy0) {
      bound = std::max(bound, byRange);
      continue;
    }
    double largest = 0.0;
    const int i0 = (fx0 - grid.x0) / s, i1 = (rx1 - grid.x0 + s - 1) / s;
    const int j0 = (fy0 - grid.y0) / s, j1 = (ry1 - grid.y0 + s - 1) / s;
    for (int j = j0; j < j1; ++j) {
      for (int i = i0; i < i1; ++i) {
        const double x0 = grid.x0 + i * s, y0 = grid.y0 + j * s;
        if (!meets(triangle, x0, y0, x0 + s, y0 + s)) continue;
        // The cell's two level triangles, cut from its south-east to its north-west corner.
        const Corner sw{x0, y0, grid.samples->at(i, j)}, se{x0 + s, y0, grid.samples->at(i + 1, j)};
        const Corner nw{x0, y0 + s, grid.samples->at(i, j + 1)}, ne{x0 + s, y0 + s, grid.samples->at(i + 1, j + 1)};
        largest = std::max(largest, largestDifference(triangle, plane, sw, se, nw));
        largest = std::max(largest, largestDifference(triangle, plane, se, ne, nw));
      }
    }
    bound = std::max(bound, std::min(largest + double(data.residual), byRange));
  }
  if (covered != std::int64_t(tx1 - tx0) * std::int64_t(ty1 - ty0)) return fallback;
  return std::min(float(bound), fallback);
}

}  // namespace polder
