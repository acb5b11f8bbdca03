// Errors of the dikes (dike_errors.hpp): every dike triangle's exact vertical error against the
// full-resolution surface (dikeTriangleErrors, dikeTriangleError, triangleSampleError) and the
// a-priori bound on those a node owns (dikeBoundRegion, dikeErrorBound, DikeErrorBounds). The
// dikes follow J.-H. Chuang, "Level-of-Detail Modeling Technique for Virtual Reality (I)", 2001,
// part B (dikes.hpp).
//
// Why the bound holds (dikeErrorBound; region: the owner's footprint and those of its west,
// south and south-west neighbours at its level). A node's dike lies east and north of its
// interior, inside its own footprint, so the gap next to a node's west and south sides belongs
// to its west and south neighbours.
// - A zipper triangle lies in the strip between its two interiors: in the west (south)
//   member's column (row), within the east (north) member's interior range. It is owned by the
//   coarser member: then it lies in that member's footprint, or in the strip at most one of
//   its strides wide just west (south) of it. Proved.
// - A junction triangle is owned by the coarsest node around its junction polygon. (1) A
//   junction that enters a node's dike touches that node: no zipper crosses a node's corner
//   square (zippers lie beside interiors), so the corner square lies in the junction at the
//   node's north-east corner; and between a node's side and the rest of its column or row
//   only that side's zippers stand. So the junction lies in the dikes of nodes no coarser
//   than its owner O. (2) It cannot leave O's footprint eastward or northward: there the gap
//   runs between nodes whose footprints start together, whose zipper (both have a corner at
//   the start) seals it, or under a node coarser than O, which would then be around the
//   junction. (3) Westward and southward it follows O's finer neighbours, whose footprints
//   touching O lie within half of O's neighbour footprint.
//   (1) is proved; (2) and (3) are argued, not proved: dikes_test.cpp checks that every vertex
//   of every dike triangle lies in its owner's region on random cuts and LODs, and a stress
//   run over 10^4 frames (k = 1..5, neighbours up to 7 levels apart) found junction triangles
//   reaching at most half a footprint west or south of their owner's footprint, never east or
//   north of it: the region has a factor-two margin.
#include <polder/terrain/dike_errors.hpp>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <limits>

namespace polder::terrain {
namespace {

// Rounds a non-negative value up to float, so reported errors never fall below the exact ones.
float roundUp(double x) {
  float f = float(x);
  if (double(f) < x) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  return f;
}

std::int64_t floorDiv(std::int64_t a, std::int64_t b) {  // b > 0
  const std::int64_t q = a / b;
  return (a % b != 0 && a < 0) ? q - 1 : q;
}
std::int64_t ceilDiv(std::int64_t a, std::int64_t b) {  // b > 0
  const std::int64_t q = a / b;
  return (a % b != 0 && a > 0) ? q + 1 : q;
}

// Largest |surface - plane| where the segment a-b crosses the surface's edges: vertical
// (x = i) and horizontal (y = j) grid lines, and cell diagonals (x + y = c), strictly between
// its ends. The surface there interpolates the two samples of the edge crossed.
double edgeCrossingError(const Heightfield& field, const DikeVertex& a, const DikeVertex& b, double c0, double gx,
                         double gy) {
  const double dx = double(b.x) - a.x, dy = double(b.y) - a.y;
  double err = 0.0;
  auto sampleAt = [&](int x, int y) {
    return double(field.at(std::clamp(x, 0, field.width - 1), std::clamp(y, 0, field.height - 1)));
  };
  auto check = [&](double px, double py, double surface) {
    err = std::max(err, std::fabs(surface - (c0 + gx * px + gy * py)));
  };
  // Vertical grid lines.
  for (int i = std::min(a.x, b.x) + 1; i < std::max(a.x, b.x); ++i) {
    const double t = (i - a.x) / dx, py = a.y + t * dy;
    const int j = int(std::floor(py));
    const double f = py - j;
    check(i, py, (1.0 - f) * sampleAt(i, j) + f * sampleAt(i, j + 1));
  }
  // Horizontal grid lines.
  for (int j = std::min(a.y, b.y) + 1; j < std::max(a.y, b.y); ++j) {
    const double t = (j - a.y) / dy, px = a.x + t * dx;
    const int i = int(std::floor(px));
    const double f = px - i;
    check(px, j, (1.0 - f) * sampleAt(i, j) + f * sampleAt(i + 1, j));
  }
  // Cell diagonals x + y = c: in cell (i, c - 1 - i), from sample (i + 1, c - 1 - i) to (i, c - i).
  const int sa = a.x + a.y, sb = b.x + b.y;
  if (sa != sb) {
    for (int c = std::min(sa, sb) + 1; c < std::max(sa, sb); ++c) {
      const double t = (c - sa) / double(sb - sa), px = a.x + t * dx, py = a.y + t * dy;
      const int i = int(std::floor(px));
      const double w = (i + 1) - px;  // 0 at (i + 1, c - 1 - i), 1 at (i, c - i)
      check(px, py, (1.0 - w) * sampleAt(i + 1, c - 1 - i) + w * sampleAt(i, c - i));
    }
  }
  return err;
}

// The plane z = c0 + gx x + gy y through a triangle's three samples; false when it has no area.
struct SamplePlane {
  double c0 = 0.0, gx = 0.0, gy = 0.0;
  double det = 0.0;  // twice the signed area
};

bool planeThrough(const Heightfield& field, const DikeVertex* const v[3], SamplePlane& plane) {
  double z[3];
  for (int k = 0; k < 3; ++k) {
    assert(v[k]->x >= 0 && v[k]->x < field.width && v[k]->y >= 0 && v[k]->y < field.height &&
           "dikeTriangleError: a vertex outside the field");
    z[k] = double(field.at(v[k]->x, v[k]->y));
  }
  const double e1x = v[1]->x - v[0]->x, e1y = v[1]->y - v[0]->y, e2x = v[2]->x - v[0]->x, e2y = v[2]->y - v[0]->y;
  plane.det = e1x * e2y - e1y * e2x;
  if (plane.det == 0.0) return false;
  const double dz1 = z[1] - z[0], dz2 = z[2] - z[0];
  plane.gx = (dz1 * e2y - dz2 * e1y) / plane.det;
  plane.gy = (e1x * dz2 - e2x * dz1) / plane.det;
  plane.c0 = z[0] - plane.gx * v[0]->x - plane.gy * v[0]->y;
  return true;
}

// Largest |sample - plane| over the samples in the closed triangle.
double sampleError(const Heightfield& field, const DikeVertex* const v[3], const SamplePlane& plane) {
  const double c0 = plane.c0, gx = plane.gx, gy = plane.gy;
  const int yMin = std::min({v[0]->y, v[1]->y, v[2]->y}), yMax = std::max({v[0]->y, v[1]->y, v[2]->y});
  const double sign = plane.det > 0 ? 1.0 : -1.0;  // half-planes of a clockwise triangle flip
  double err = 0.0;
  for (int y = yMin; y <= yMax; ++y) {
    // The closed triangle's row: the intersection of its three edges' half-planes
    // (A x + B >= 0 per edge, exact in integers).
    std::int64_t lo = std::numeric_limits<std::int64_t>::min(), hi = std::numeric_limits<std::int64_t>::max();
    bool empty = false;
    for (int e = 0; e < 3 && !empty; ++e) {
      const DikeVertex& p = *v[e];
      const DikeVertex& q = *v[(e + 1) % 3];
      std::int64_t ea = -(std::int64_t(q.y) - p.y);
      std::int64_t eb = (std::int64_t(q.x) - p.x) * (std::int64_t(y) - p.y) + (std::int64_t(q.y) - p.y) * p.x;
      if (sign < 0) {
        ea = -ea;
        eb = -eb;
      }
      if (ea > 0)
        lo = std::max(lo, ceilDiv(-eb, ea));
      else if (ea < 0)
        hi = std::min(hi, floorDiv(eb, -ea));
      else if (eb < 0)
        empty = true;
    }
    if (empty || lo > hi) continue;
    const int x0 = int(std::max<std::int64_t>(lo, 0)), x1 = int(std::min<std::int64_t>(hi, field.width - 1));
    const float* row = field.heights.data() + std::size_t(y) * std::size_t(field.width);
    const double base = c0 + gy * y;
    for (int x = x0; x <= x1; ++x) err = std::max(err, std::fabs(double(row[x]) - (base + gx * x)));
  }
  return err;
}

}  // namespace

float dikeTriangleError(const Heightfield& field, const DikeVertex& a, const DikeVertex& b, const DikeVertex& c) {
  const DikeVertex* const v[3] = {&a, &b, &c};
  SamplePlane plane;
  if (!planeThrough(field, v, plane)) return 0.0f;
  double err = sampleError(field, v, plane);
  // The surface is piecewise linear too, so the difference is largest at a vertex of the
  // two triangulations' overlay: a sample in the triangle (above) or a point where a
  // triangle edge crosses a cell edge (x or y integer) or a cell diagonal (x + y integer,
  // heightfield.hpp's cut from (x+1, y) to (x, y+1)).
  for (int e = 0; e < 3; ++e)
    err = std::max(err, edgeCrossingError(field, *v[e], *v[(e + 1) % 3], plane.c0, plane.gx, plane.gy));
  return roundUp(err);
}

float triangleSampleError(const Heightfield& field, const DikeVertex& a, const DikeVertex& b, const DikeVertex& c) {
  const DikeVertex* const v[3] = {&a, &b, &c};
  SamplePlane plane;
  if (!planeThrough(field, v, plane)) return 0.0f;
  return roundUp(sampleError(field, v, plane));
}

float dikeTriangleErrors(const Heightfield& field, const DikeMesh& dikes, std::vector<float>* perTriangle) {
  assert(field.heights.size() == field.sampleCount() && "dikeTriangleErrors: heights do not match width * height");
  const std::size_t count = dikes.triangleCount();
  if (perTriangle) perTriangle->resize(count);
  float worst = 0.0f;
  for (std::size_t t = 0; t < count; ++t) {
    const float e =
        dikeTriangleError(field, dikes.vertices[dikes.indices[3 * t]], dikes.vertices[dikes.indices[3 * t + 1]],
                          dikes.vertices[dikes.indices[3 * t + 2]]);
    if (perTriangle) (*perTriangle)[t] = e;
    worst = std::max(worst, e);
  }
  return worst;
}

SampleRect dikeBoundRegion(const BlockLayout& layout, NodeId node) {
  assert(layout.exists(node) && "dikeBoundRegion: the node is not in the layout");
  const SampleRect f = layout.footprint(node);
  const int reach = layout.pitch() * layout.stride(node);
  return SampleRect{std::max(f.x0 - reach, 0), std::max(f.y0 - reach, 0), f.x1, f.y1};
}

float dikeErrorBound(const Heightfield& field, const BlockLayout& layout, NodeId node) {
  assert(field.width == layout.width() && field.height == layout.height() &&
         "dikeErrorBound: the field and the layout differ in size");
  const SampleRect r = dikeBoundRegion(layout, node);
  float lo = std::numeric_limits<float>::infinity(), hi = -lo;
  for (int y = r.y0; y <= r.y1; ++y) {
    const float* row = field.heights.data() + std::size_t(y) * std::size_t(field.width);
    for (int x = r.x0; x <= r.x1; ++x) {
      lo = std::min(lo, row[x]);
      hi = std::max(hi, row[x]);
    }
  }
  return roundUp(double(hi) - double(lo));
}

Result<DikeErrorBounds> DikeErrorBounds::build(const Heightfield& field, const BlockLayout& layout) {
  if (field.width != layout.width() || field.height != layout.height())
    return makeError(ErrorKind::InvalidArgument, "DikeErrorBounds: the field and the layout differ in size");
  if (field.heights.size() != field.sampleCount())
    return makeError(ErrorKind::InvalidArgument, "DikeErrorBounds: heights do not match width * height");
  DikeErrorBounds bounds;
  bounds.m_layout = layout;
  std::size_t total = 0;
  for (int level = 0; level <= layout.rootLevel(); ++level) {
    bounds.m_levelOffset.push_back(total);
    total += std::size_t(layout.nodesX(level)) * std::size_t(layout.nodesY(level));
  }
  bounds.m_levelOffset.push_back(total);
  bounds.m_min.assign(total, std::numeric_limits<float>::infinity());
  bounds.m_max.assign(total, -std::numeric_limits<float>::infinity());
  // Level 0: every sample of each footprint (closed: shared edges count for both sides).
  const int bx = layout.nodesX(0), by = layout.nodesY(0);
  for (int j = 0; j < by; ++j) {
    for (int i = 0; i < bx; ++i) {
      const SampleRect f = layout.footprint(NodeId{0, std::uint32_t(i), std::uint32_t(j)});
      float lo = std::numeric_limits<float>::infinity(), hi = -lo;
      for (int y = f.y0; y <= f.y1; ++y) {
        const float* row = field.heights.data() + std::size_t(y) * std::size_t(field.width);
        for (int x = f.x0; x <= f.x1; ++x) {
          lo = std::min(lo, row[x]);
          hi = std::max(hi, row[x]);
        }
      }
      bounds.m_min[std::size_t(j) * bx + i] = lo;
      bounds.m_max[std::size_t(j) * bx + i] = hi;
    }
  }
  // Coarser levels: a footprint is the union of its children's.
  for (int level = 1; level <= layout.rootLevel(); ++level) {
    const int nx = layout.nodesX(level), ny = layout.nodesY(level);
    const int cx = layout.nodesX(level - 1), cy = layout.nodesY(level - 1);
    const std::size_t base = bounds.m_levelOffset[std::size_t(level)],
                      childBase = bounds.m_levelOffset[std::size_t(level) - 1];
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        float lo = std::numeric_limits<float>::infinity(), hi = -lo;
        for (int q = 0; q < 4; ++q) {
          const int ci = 2 * i + (q & 1), cj = 2 * j + (q >> 1);
          if (ci >= cx || cj >= cy) continue;
          lo = std::min(lo, bounds.m_min[childBase + std::size_t(cj) * cx + ci]);
          hi = std::max(hi, bounds.m_max[childBase + std::size_t(cj) * cx + ci]);
        }
        bounds.m_min[base + std::size_t(j) * nx + i] = lo;
        bounds.m_max[base + std::size_t(j) * nx + i] = hi;
      }
    }
  }
  return bounds;
}

float DikeErrorBounds::bound(NodeId node) const {
  assert(m_layout.exists(node) && "DikeErrorBounds::bound: the node is not in the layout");
  // dikeBoundRegion is exactly the union of the footprints of the node and of its west,
  // south and south-west neighbours at its level.
  const int nx = m_layout.nodesX(node.level);
  const std::size_t base = m_levelOffset[node.level];
  float lo = std::numeric_limits<float>::infinity(), hi = -lo;
  for (int j = int(node.by) - 1; j <= int(node.by); ++j) {
    for (int i = int(node.bx) - 1; i <= int(node.bx); ++i) {
      if (i < 0 || j < 0) continue;
      lo = std::min(lo, m_min[base + std::size_t(j) * nx + i]);
      hi = std::max(hi, m_max[base + std::size_t(j) * nx + i]);
    }
  }
  return roundUp(double(hi) - double(lo));
}

}  // namespace polder::terrain
