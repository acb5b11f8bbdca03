#include "pyramid_dike_bound.hpp"

#include <algorithm>
#include <cmath>

namespace polder {

namespace {

struct Point {
  double x, y;
};

struct Corner {
  double x, y;
  double h;
};

// The plane z = h0 + px (x - x0) + py (y - y0) through three corners; false when they are
// collinear.
struct SurfacePlane {
  Corner origin{};
  double px = 0.0, py = 0.0;

  static bool through(const Corner& a, const Corner& b, const Corner& c, SurfacePlane& out) {
    const double ux = b.x - a.x, uy = b.y - a.y, uz = b.h - a.h;
    const double wx = c.x - a.x, wy = c.y - a.y, wz = c.h - a.h;
    const double det = ux * wy - uy * wx;
    if (det == 0.0) return false;
    out = SurfacePlane{a, (uz * wy - uy * wz) / det, (ux * wz - uz * wx) / det};
    return true;
  }
  double at(double x, double y) const { return origin.h + px * (x - origin.x) + py * (y - origin.y); }
};

// The largest |plane - level triangle| over the part of `t` inside the level triangle (a, b,
// c), counter-clockwise: both are linear there, so it is largest at a corner of the clipped
// polygon. 0 when they do not overlap.
double largestDifference(const Point (&t)[3], const SurfacePlane& plane, const Corner& a, const Corner& b,
                         const Corner& c) {
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
  SurfacePlane level;
  if (!SurfacePlane::through(a, b, c, level)) return 0.0;  // never: level triangles are half cells
  double largest = 0.0;
  for (int i = 0; i < count; ++i)
    largest = std::max(largest, std::abs(plane.at(polygon[i].x, polygon[i].y) - level.at(polygon[i].x, polygon[i].y)));
  return largest;
}

}  // namespace

void PyramidDikeBound::setFrame(std::span<const terrain::SelectedNode> cut, const DikeVertexSamples& samples) {
  m_cut = cut;
  m_samples = &samples;
}

float PyramidDikeBound::error(const terrain::DikeVertex& a, const terrain::DikeVertex& b, const terrain::DikeVertex& c,
                              const terrain::DikeTriangleRef& where) const {
  const terrain::DikeVertex v[3] = {a, b, c};
  Corner corners[3];
  for (int i = 0; i < 3; ++i)
    corners[i] = Corner{double(v[i].x), double(v[i].y), double(height(v[i], where.vertices[i]))};
  const float fallback = m_pyramid.node(m_cut[where.owner].node).dikeRange;
  SurfacePlane plane;
  if (!SurfacePlane::through(corners[0], corners[1], corners[2], plane)) return fallback;
  const double z[3] = {corners[0].h, corners[1].h, corners[2].h};
  const Point triangle[3] = {{double(a.x), double(a.y)}, {double(b.x), double(b.y)}, {double(c.x), double(c.y)}};

  const int tx0 = std::min({a.x, b.x, c.x}), tx1 = std::max({a.x, b.x, c.x});
  const int ty0 = std::min({a.y, b.y, c.y}), ty1 = std::max({a.y, b.y, c.y});
  std::uint32_t candidates[7];
  int count = 0;
  const auto add = [&](std::uint32_t node) {
    if (node == CutIndex::kNone || std::find(candidates, candidates + count, node) != candidates + count) return;
    candidates[count++] = node;
  };
  for (int i = 0; i < 3; ++i) add(m_samples->stage->vertexNodes()[where.vertices[i]]);
  const int cx1 = std::max(tx0, tx1 - 1), cy1 = std::max(ty0, ty1 - 1);
  add(m_cutIndex.at(tx0, ty0));
  add(m_cutIndex.at(cx1, ty0));
  add(m_cutIndex.at(tx0, cy1));
  add(m_cutIndex.at(cx1, cy1));

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
    // Where the tile reaches over that part (it starts where the footprint does), its level
    // surface plus each cell's residual bounds it too.
    const SampleGrid& grid = m_samples->cut[candidates[n]];
    const int s = grid.stride;
    const bool tileCovers = grid.samples && grid.x0 + (grid.samples->width - 1) * s >= fx1 &&
                            grid.y0 + (grid.samples->height - 1) * s >= fy1;
    if (!tileCovers) {
      bound = std::max(bound, byRange);
      continue;
    }
    double largest = 0.0;
    const int i0 = (fx0 - grid.x0) / s, i1 = (fx1 - grid.x0 + s - 1) / s;
    const int j0 = (fy0 - grid.y0) / s, j1 = (fy1 - grid.y0 + s - 1) / s;
    for (int j = j0; j < j1; ++j) {
      for (int i = i0; i < i1; ++i) {
        const double x0 = grid.x0 + i * s, y0 = grid.y0 + j * s;
        // The cell's two level triangles, cut from its south-east to its north-west corner.
        const Corner sw{x0, y0, grid.samples->at(i, j)}, se{x0 + s, y0, grid.samples->at(i + 1, j)};
        const Corner nw{x0, y0 + s, grid.samples->at(i, j + 1)}, ne{x0 + s, y0 + s, grid.samples->at(i + 1, j + 1)};
        const double cell =
            std::max(largestDifference(triangle, plane, sw, se, nw), largestDifference(triangle, plane, se, ne, nw));
        largest = std::max(largest, cell + double(grid.residual(i, j)));
      }
    }
    bound = std::max(bound, std::min(largest, byRange));
  }
  if (covered != std::int64_t(tx1 - tx0) * std::int64_t(ty1 - ty0)) return fallback;
  return std::min(float(bound), fallback);
}

}  // namespace polder
