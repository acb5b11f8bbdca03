// The error hierarchy of one block (rtin.hpp BlockLod::build): every bintree triangle's exact
// error, the vertices' monotone errors and nested bounding radii, the block's summaries (node
// error, floor error, height range), and the queries on them.
//
// Follows W. Evans, D. Kirkpatrick, G. Townsend, "Right-triangulated irregular networks"
// (Algorithmica 2001) for the bintree (rtin_grid.hpp); P. Lindstrom et al., "Real-time,
// continuous level of detail rendering of height fields" (SIGGRAPH 1996), R. Pajarola, "Large
// scale terrain visualization using the restricted quadtree triangulation" (Visualization 1998)
// and M. Duchaineau et al., "ROAMing terrain" (Visualization 1997) for monotone errors;
// P. Lindstrom, V. Pascucci, "Visualization of large terrains made easy" (Visualization 2001)
// for nested bounding spheres.
//
// Order. Building visits vertices from fine to coarse (h = 1, 2, ...; side midpoints before
// square centres, rtin_grid.hpp "Layout"), so a vertex's children (the midpoints of its
// triangles' legs) are final when it is reached.
//
// Exact errors. The true surface is the full-resolution triangulation (heightfield.hpp: each
// cell cut from (x+1, y) to (x, y+1)). A triangle's plane minus that surface is linear on each
// piece of their overlay, so its largest magnitude is at an overlay vertex: a sample in the
// triangle, or a point where the triangle's edges cross full-resolution edges. Bintree edges
// are axis-aligned or at 45 degrees at every stride: axis-aligned ones and those running north-
// west to south-east (along cell diagonals) cross full-resolution edges only at samples, while
// one running south-west to north-east crosses the diagonal of every cell it passes at the
// cell's centre, where the surface is the mean of the diagonal's ends. So every error is a scan
// of the samples plus, for such an edge, its cell centres (exactTriangleError). At stride 1 that
// makes the half cells cut south-west to north-east (half of them, in a checkerboard) differ
// from the surface by the gap between the cell's two cuts at its centre (cellCentreGap).
#include <polder/terrain/rtin.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "rtin_grid.hpp"

namespace polder::terrain {
using namespace detail;
namespace {

// Each nesting step grows a radius by this factor beyond the exact sum, so that rounding in
// camera distances cannot make a child active while its parent is not.
constexpr double kRadiusSlack = 1e-6;

// Rounds a non-negative value up to float, so that stored errors and radii never fall below
// the exact values.
float roundUp(double x) {
  const float f = float(x);
  // The next float up where rounding went down; branchless, the branch being a coin toss.
  return std::bit_cast<float>(std::bit_cast<std::uint32_t>(f) + std::uint32_t(double(f) < x));
}

// Where full-resolution samples come from: the field row by row, limited to the valid
// sub-rectangle [0, lastX] x [0, lastY] of offsets from the block's origin sample.
struct SampleWindow {
  const float* origin = nullptr;  // sample (x0, y0)
  std::ptrdiff_t pitch = 0;       // samples per field row
  int stride = 1;
  int lastX = 0;
  int lastY = 0;
};

// Largest |row[x] - (base + gx * x)| over x in [lo, hi]: the inner loop of every build.
double rowError(const float* row, int lo, int hi, double base, double gx) {
  double m = 0.0;
  int x = lo;
#if defined(__SSE2__)
  // Two doubles a lane pair, two independent maxima (scalar code chains every sample on the
  // previous maximum and does not vectorize without fast-math).
  if (hi - lo >= 3) {
    const __m128d vBase = _mm_set1_pd(base), vGx = _mm_set1_pd(gx), two = _mm_set1_pd(2.0);
    const __m128d absMask = _mm_castsi128_pd(_mm_set1_epi64x(0x7fffffffffffffffLL));
    __m128d fx = _mm_set_pd(lo + 1.0, double(lo));
    __m128d m0 = _mm_setzero_pd(), m1 = _mm_setzero_pd();
    for (; x + 3 <= hi; x += 4) {
      const __m128 h4 = _mm_loadu_ps(row + x);
      const __m128d fx2 = _mm_add_pd(fx, two);
      const __m128d d0 = _mm_sub_pd(_mm_cvtps_pd(h4), _mm_add_pd(vBase, _mm_mul_pd(vGx, fx)));
      const __m128d d1 = _mm_sub_pd(_mm_cvtps_pd(_mm_movehl_ps(h4, h4)), _mm_add_pd(vBase, _mm_mul_pd(vGx, fx2)));
      m0 = _mm_max_pd(m0, _mm_and_pd(d0, absMask));
      m1 = _mm_max_pd(m1, _mm_and_pd(d1, absMask));
      fx = _mm_add_pd(fx2, two);
    }
    m0 = _mm_max_pd(m0, m1);
    m = std::max(_mm_cvtsd_f64(m0), _mm_cvtsd_f64(_mm_unpackhi_pd(m0, m0)));
  }
#endif
  for (; x <= hi; ++x) {
    const double d = std::fabs(double(row[x]) - (base + gx * x));
    m = d > m ? d : m;
  }
  return m;
}

// Largest |surface - (c0 + gx X + gy Y)| at the centres (x + 1/2, y + 1/2) of the cells
// (x0 + t, y0 + t), t in [0, count): where an edge running south-west to north-east crosses the
// cells' diagonals, the surface being the mean of each diagonal's ends (x+1, y) and (x, y+1).
double diagonalEdgeError(const SampleWindow& window, int x0, int y0, int count, double c0, double gx, double gy) {
  const float* cell = window.origin + std::ptrdiff_t(y0) * window.pitch + x0;  // sample (x0, y0)
  const std::ptrdiff_t step = window.pitch + 1, up = window.pitch;
  const double g = gx + gy, plane0 = c0 + gx * (x0 + 0.5) + gy * (y0 + 0.5);
  // Twice the plane against the sum of the diagonal's ends; two independent maxima (one chain
  // of maxima would bound the loop by its latency).
  double m0 = 0.0, m1 = 0.0;
  int t = 0;
  for (; t + 1 < count; t += 2) {
    const float* c = cell + t * step;
    const double d0 = std::fabs((double(c[1]) + double(c[up])) - 2.0 * (plane0 + g * t));
    const double d1 = std::fabs((double(c[step + 1]) + double(c[step + up])) - 2.0 * (plane0 + g * (t + 1)));
    m0 = d0 > m0 ? d0 : m0;
    m1 = d1 > m1 ? d1 : m1;
  }
  if (t < count) {
    const float* c = cell + t * step;
    const double d0 = std::fabs((double(c[1]) + double(c[up])) - 2.0 * (plane0 + g * t));
    m0 = d0 > m0 ? d0 : m0;
  }
  return 0.5 * (m0 > m1 ? m0 : m1);
}

// At stride 1: the distance between the two ways of cutting the cell with corner heights h00
// (south-west), h10, h01, h11, at its centre, where it is largest. It is the error of both halves
// of a half cell cut south-west to north-east, against the surface cut the other way.
double cellCentreGap(double h00, double h10, double h01, double h11) {
  return 0.5 * std::fabs((h00 + h11) - (h10 + h01));
}

// Slope dx/dy of a triangle edge with dy != 0: the edges are vertical or at 45 degrees.
int unitSlope(int dx) { return (dx > 0) - (dx < 0); }

// Exact error of triangle t against the full-resolution surface (the triangulation of
// heightfield.hpp) over the closed triangle, the plane running through the vertex heights
// za, zb, zc. Their difference is linear on each piece of the two triangulations' overlay, so
// it peaks at the overlay's vertices: the samples in the triangle, and where its edges cross
// full-resolution edges. Axis-aligned edges and edges running north-west to south-east (on
// full-resolution diagonals) cross them only at samples; an edge running south-west to
// north-east crosses every cell diagonal it passes at the cell's centre. Each triangle edge is
// horizontal, vertical or at 45 degrees, so its rows are spans with integer ends.
double exactTriangleError(const SampleWindow& window, const Tri& t, double za, double zb, double zc) {
  const int s = window.stride;
  const int px[3] = {t.ax * s, t.bx * s, t.cx * s};
  const int py[3] = {t.ay * s, t.by * s, t.cy * s};
  const double e1x = px[1] - px[0], e1y = py[1] - py[0], e2x = px[2] - px[0], e2y = py[2] - py[0];
  const double dz1 = zb - za, dz2 = zc - za;
  const double invDet = 1.0 / (e1x * e2y - e1y * e2x);
  const double gx = (dz1 * e2y - dz2 * e1y) * invDet;
  const double gy = (e1x * dz2 - e2x * dz1) * invDet;
  const double c0 = za - gx * px[0] - gy * py[0];  // plane: z = c0 + gx X + gy Y

  int o0 = 0, o1 = 1, o2 = 2;  // vertices sorted by Y
  if (py[o1] < py[o0]) std::swap(o0, o1);
  if (py[o2] < py[o1]) std::swap(o1, o2);
  if (py[o1] < py[o0]) std::swap(o0, o1);
  const int x0 = px[o0], y0 = py[o0], x1 = px[o1], y1 = py[o1], x2 = px[o2], y2 = py[o2];
  const int slopeLong = unitSlope(x2 - x0);

  double err = 0.0;
  auto scanRow = [&](int y, int xa, int xb) {
    const int lo = std::max(std::min(xa, xb), 0);
    const int hi = std::min(std::max(xa, xb), window.lastX);
    const double rowErr = rowError(window.origin + std::ptrdiff_t(y) * window.pitch, lo, hi, c0 + gy * y, gx);
    err = rowErr > err ? rowErr : err;
  };
  if (y1 == y0) {
    if (y0 <= window.lastY) scanRow(y0, x0, x1);
  } else {
    const int slope01 = unitSlope(x1 - x0);
    const int end = std::min(y1, window.lastY);
    for (int y = y0; y <= end; ++y) scanRow(y, x0 + (y - y0) * slopeLong, x0 + (y - y0) * slope01);
  }
  if (y2 > y1) {
    const int slope12 = unitSlope(x2 - x1);
    const int end = std::min(y2, window.lastY);
    for (int y = y1 + 1; y <= end; ++y) scanRow(y, x0 + (y - y0) * slopeLong, x1 + (y - y1) * slope12);
  }
  // At most one edge runs south-west to north-east; its cells beyond the valid rectangle (a
  // clipped block's straddling triangles) are left out like the samples there.
  for (int e = 0; e < 3; ++e) {
    const int ex = px[(e + 1) % 3] - px[e], ey = py[(e + 1) % 3] - py[e];
    if (ex != ey || ex == 0) continue;
    const int sx = std::min(px[e], px[(e + 1) % 3]), sy = std::min(py[e], py[(e + 1) % 3]);
    const int count = std::min({std::abs(ex), window.lastX - sx, window.lastY - sy});
    const double edgeErr = diagonalEdgeError(window, sx, sy, count, c0, gx, gy);
    err = edgeErr > err ? edgeErr : err;
  }
  return err;
}

enum class Coverage { Inside, Straddles, Outside };

// How triangle t meets the valid rectangle [0, cx] x [0, cy] (separating axes: the
// rectangle's, then the triangle's edge normals; touching counts as outside).
Coverage coverage(const Tri& t, int cx, int cy) {
  const int maxX = std::max({t.ax, t.bx, t.cx}), maxY = std::max({t.ay, t.by, t.cy});
  if (maxX <= cx && maxY <= cy) return Coverage::Inside;
  const int minX = std::min({t.ax, t.bx, t.cx}), minY = std::min({t.ay, t.by, t.cy});
  if (minX >= cx || minY >= cy) return Coverage::Outside;
  const int vx[3] = {t.ax, t.bx, t.cx}, vy[3] = {t.ay, t.by, t.cy};
  const int rx[4] = {0, cx, cx, 0}, ry[4] = {0, 0, cy, cy};
  for (int e = 0; e < 3; ++e) {
    const int px = vx[e], py = vy[e];
    const int ex = vx[(e + 1) % 3] - px, ey = vy[(e + 1) % 3] - py;
    bool allOutside = true;  // outward normal of a counter-clockwise edge: (ey, -ex)
    for (int r = 0; r < 4 && allOutside; ++r)
      allOutside = (long long)ey * (rx[r] - px) - (long long)ex * (ry[r] - py) >= 0;
    if (allOutside) return Coverage::Outside;
  }
  return Coverage::Straddles;
}

}  // namespace

// ---- build ------------------------------------------------------------------------------

Result<BlockLod> BlockLod::build(const Heightfield& field, const BlockFootprint& footprint) {
  BlockLod lod;
  Status status = lod.rebuild(field, footprint);
  if (!status) return status.error();
  return lod;
}

Result<BlockLod> BlockLod::buildFromLevel(const Heightfield& samples, const BlockFootprint& footprint,
                                          float residualM) {
  if (!(residualM >= 0.0f))
    return makeError(ErrorKind::InvalidArgument, "BlockLod::buildFromLevel: the residual must be >= 0");
  std::vector<float> cells;
  if (samples.width >= 2 && samples.height >= 2)
    cells.assign(std::size_t(samples.width - 1) * std::size_t(samples.height - 1), residualM);
  return buildFromLevel(samples, footprint, cells);
}

Result<BlockLod> BlockLod::buildFromLevel(const Heightfield& samples, const BlockFootprint& footprint,
                                          std::span<const float> cellResidualM) {
  assert(footprint.stride >= 1 && std::has_single_bit(unsigned(footprint.stride)) &&
         "BlockLod::buildFromLevel: stride must be a power of two");
  const int pitch = samples.width - 1;
  if (samples.width >= 2 && samples.height >= 2 &&
      cellResidualM.size() != std::size_t(pitch) * std::size_t(samples.height - 1))
    return makeError(ErrorKind::InvalidArgument, "BlockLod::buildFromLevel: " + std::to_string(cellResidualM.size()) +
                                                     " cell residuals for a tile of " + std::to_string(samples.width) +
                                                     " x " + std::to_string(samples.height) + " samples");
  for (const float r : cellResidualM)
    if (!(r >= 0.0f) || std::isinf(r))
      return makeError(ErrorKind::InvalidArgument, "BlockLod::buildFromLevel: a residual is not finite and >= 0");
  BlockLod lod;
  Status status = lod.rebuild(samples, BlockFootprint{0, 0, footprint.k, 1});
  if (!status) return status.error();
  const bool noResidual = std::all_of(cellResidualM.begin(), cellResidualM.end(), [](float r) { return r == 0.0f; });
  if (footprint.stride == 1 && noResidual) {
    lod.m_footprint = footprint;
    lod.m_origin = glm::dvec3(footprint.x0 * samples.spacingX, footprint.y0 * samples.spacingY, 0.0);
    return lod;
  }
  lod.addCellResiduals(cellResidualM, pitch);
  lod.m_footprint = footprint;
  const double fullSpacingX = samples.spacingX / footprint.stride, fullSpacingY = samples.spacingY / footprint.stride;
  lod.m_origin = glm::dvec3(footprint.x0 * fullSpacingX, footprint.y0 * fullSpacingY, 0.0);
  return lod;
}

float BlockLod::coverResidual(int ax, int ay, int bx, int by, int cx, int cy, std::span<const float> residual,
                              int pitch, std::vector<float>& triangleResidual) const {
  if (std::min({ax, bx, cx}) >= m_cellsX || std::min({ay, by, cy}) >= m_cellsY) return 0.0f;  // clipped away
  if (isHalfCell(bx, cx)) {
    const int ci = std::min(bx, cx), cj = std::min(by, cy);
    return residual[std::size_t(cj) * std::size_t(pitch) + std::size_t(ci)];
  }
  const int mx = (bx + cx) / 2, my = (by + cy) / 2;
  const float r = std::max(coverResidual(mx, my, ax, ay, bx, by, residual, pitch, triangleResidual),
                           coverResidual(mx, my, cx, cy, ax, ay, residual, pitch, triangleResidual));
  const std::size_t v = std::size_t(my) * std::size_t(m_footprint.verticesPerSide()) + std::size_t(mx);
  triangleResidual[2 * v + std::size_t(triangleSide(ax, ay, bx, by, cx, cy))] = r;
  return r;
}

void BlockLod::addCellResiduals(std::span<const float> residual, int pitch) {
  const int n = m_footprint.cells(), side = n + 1;
  const std::size_t vertexCount = std::size_t(side) * std::size_t(side);
  // Against the level surface every half cell's error is what build() at stride 1 finds on the
  // fly (the gap at its centre, or 0 for a half cut like that surface); kept per half cell here,
  // as at any stride above 1, since the full-resolution surface is not the level's.
  m_leafError.assign(2 * std::size_t(n) * std::size_t(n), 0.0f);
  for (int cj = 0; cj < m_cellsY; ++cj)
    for (int ci = 0; ci < m_cellsX; ++ci) {
      const bool cutLikeSurface = ((ci + cj) & 1) != 0;
      const double gap = cutLikeSurface ? 0.0
                                        : cellCentreGap(height(ci, cj), height(ci + 1, cj), height(ci, cj + 1),
                                                        height(ci + 1, cj + 1));
      const double r = residual[std::size_t(cj) * std::size_t(pitch) + std::size_t(ci)];
      for (int sideIndex = 0; sideIndex < 2; ++sideIndex)
        m_leafError[(std::size_t(cj) * n + ci) * 2 + sideIndex] = roundUp(gap + r);
    }

  // Each bintree triangle's largest cell residual, then each vertex's largest over its own
  // triangles and every vertex below it (fine to coarse, as the build: side midpoints, whose
  // children are the finer square centres, before the square centres of the same size).
  std::vector<float> triangleResidual(2 * vertexCount, 0.0f);
  const float rootResidual = std::max(coverResidual(0, 0, n, 0, 0, n, residual, pitch, triangleResidual),
                                      coverResidual(n, n, 0, n, n, 0, residual, pitch, triangleResidual));
  std::vector<float> below(vertexCount, 0.0f);
  for (int shift = 0; shift < m_footprint.k; ++shift) {
    const int h = 1 << shift;
    for (const bool squareCentres : {false, true}) {
      for (int j = 0; j <= n; j += h)
        for (int i = 0; i <= n; i += h) {
          if ((i | j) == 0 || std::countr_zero(unsigned(i | j)) != shift) continue;
          const bool squareCentre = ((i >> shift) & 1) != 0 && ((j >> shift) & 1) != 0;
          if (squareCentre != squareCentres) continue;
          Tri tris[2];
          const int count = splitTriangles(i, j, n, tris);
          const std::size_t v = std::size_t(j) * side + i;
          float r = 0.0f;
          for (int t = 0; t < count; ++t) {
            const Tri& tri = tris[t];
            r = std::max(
                r, triangleResidual[2 * v + std::size_t(triangleSide(tri.ax, tri.ay, tri.bx, tri.by, tri.cx, tri.cy))]);
            if (shift == 0 && !squareCentres) continue;  // its legs are cell diagonals: half cells below
            r = std::max({r, below[std::size_t((tri.ay + tri.by) / 2) * side + std::size_t((tri.ax + tri.bx) / 2)],
                          below[std::size_t((tri.cy + tri.ay) / 2) * side + std::size_t((tri.cx + tri.ax) / 2)]});
          }
          below[v] = r;
        }
    }
  }

  for (std::size_t v = 0; v < vertexCount; ++v) {
    if (below[v] == 0.0f) continue;
    m_error[v] = roundUp(double(m_error[v]) + below[v]);  // +inf stays
    m_radius[v] = roundUp(double(m_radius[v]) + below[v]);
    for (int t = 0; t < 2; ++t)
      m_triangleError[2 * v + t] = roundUp(double(m_triangleError[2 * v + t]) + triangleResidual[2 * v + t]);
  }
  m_maxError = roundUp(double(m_maxError) + rootResidual);
  m_floorError = m_leafError.empty() ? 0.0f : *std::max_element(m_leafError.begin(), m_leafError.end());
}

Status BlockLod::rebuild(const Heightfield& field, const BlockFootprint& fp) {
  assert(fp.k >= 1 && fp.k <= kRtinMaxK && "BlockLod::build: k must be in 1..kRtinMaxK");
  assert(fp.stride >= 1 && std::has_single_bit(unsigned(fp.stride)) &&
         "BlockLod::build: stride must be a power of two");
  assert(fp.x0 >= 0 && fp.y0 >= 0 && "BlockLod::build: negative block origin");
  assert(field.heights.size() == field.sampleCount() && "BlockLod::build: heights do not match width * height");

  const int n = fp.cells(), s = fp.stride;
  if (field.width < 2 || field.height < 2 || fp.x0 >= field.width - 1 || fp.y0 >= field.height - 1 ||
      (field.width - 1 - fp.x0) / s < 1 || (field.height - 1 - fp.y0) / s < 1) {
    return makeError(ErrorKind::InvalidArgument, "BlockLod::build: block at sample (" + std::to_string(fp.x0) + ", " +
                                                     std::to_string(fp.y0) + ") with stride " + std::to_string(s) +
                                                     " has no whole cell inside the " + std::to_string(field.width) +
                                                     " x " + std::to_string(field.height) + " field");
  }
  const int cellsX = std::min(n, (field.width - 1 - fp.x0) / s);
  const int cellsY = std::min(n, (field.height - 1 - fp.y0) / s);

  SampleWindow window;
  window.origin = field.heights.data() + field.index(fp.x0, fp.y0);
  window.pitch = field.width;
  window.stride = s;
  window.lastX = cellsX * s;
  window.lastY = cellsY * s;

  // Height range and finiteness of everything the meshes will cover.
  float lo = std::numeric_limits<float>::infinity(), hi = -lo;
  bool finite = true;
  for (int y = 0; y <= window.lastY; ++y) {
    const float* row = window.origin + std::ptrdiff_t(y) * window.pitch;
    for (int x = 0; x <= window.lastX; ++x) {
      const float v = row[x];
      finite &= std::isfinite(v);
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  }
  if (!finite) {
    return makeError(ErrorKind::InvalidData, "BlockLod::build: the block at sample (" + std::to_string(fp.x0) + ", " +
                                                 std::to_string(fp.y0) +
                                                 ") has non-finite heights (no-data left unfilled?)");
  }

  m_footprint = fp;
  m_cellsX = cellsX;
  m_cellsY = cellsY;
  m_clipped = cellsX < n || cellsY < n;
  m_origin = glm::dvec3(fp.x0 * field.spacingX, fp.y0 * field.spacingY, 0.0);
  m_vertexSpacingX = s * field.spacingX;
  m_vertexSpacingY = s * field.spacingY;
  m_minHeight = lo;
  m_maxHeight = hi;

  const int side = n + 1;
  const std::size_t vertexCount = std::size_t(side) * std::size_t(side);
  m_height.resize(vertexCount);
  m_error.assign(vertexCount, 0.0f);
  m_radius.assign(vertexCount, 0.0f);
  m_triangleError.assign(2 * vertexCount, 0.0f);
  if (s > 1) {
    m_leafError.assign(2 * std::size_t(n) * std::size_t(n), 0.0f);
  } else {
    m_leafError.clear();  // at stride 1 a half cell's error is found from its corners (leafError)
  }

  // Vertex heights; outside a clipped block's rectangle, the nearest valid vertex's height
  // keeps radii sane (those triangles are never drawn).
  for (int j = 0; j <= n; ++j) {
    const float* row = window.origin + std::ptrdiff_t(std::min(j, cellsY)) * s * window.pitch;
    for (int i = 0; i <= n; ++i) m_height[std::size_t(j) * side + i] = row[std::min(i, cellsX) * s];
  }

  const bool clippedBlock = m_clipped;
  const float* heights = m_height.data();
  auto hAt = [heights, side](int i, int j) { return double(heights[std::size_t(j) * side + i]); };

  // Half cells: their error is what the stride leaves, never refined within this block.
  if (s > 1) {
    for (int cj = 0; cj < cellsY; ++cj) {
      for (int ci = 0; ci < cellsX; ++ci) {
        Tri halves[2];
        if (((ci + cj) & 1) == 0) {  // same checkerboard as the square centres, one level down
          halves[0] = counterClockwise(ci + 1, cj, ci, cj, ci + 1, cj + 1);
          halves[1] = counterClockwise(ci, cj + 1, ci, cj, ci + 1, cj + 1);
        } else {
          halves[0] = counterClockwise(ci, cj, ci + 1, cj, ci, cj + 1);
          halves[1] = counterClockwise(ci + 1, cj + 1, ci + 1, cj, ci, cj + 1);
        }
        for (const Tri& t : halves) {
          const double err = exactTriangleError(window, t, hAt(t.ax, t.ay), hAt(t.bx, t.by), hAt(t.cx, t.cy));
          const int sideIndex = triangleSide(t.ax, t.ay, t.bx, t.by, t.cx, t.cy);
          m_leafError[(std::size_t(cj) * n + ci) * 2 + sideIndex] = roundUp(err);
        }
      }
    }
  }

  const double dx = m_vertexSpacingX, dy = m_vertexSpacingY;
  const bool fastFinest = s == 1;  // the finest triangles then hold samples at known places

  // One triangle of vertex v = (i, j) at height zm: stores its exact error and widens v's
  // error, bounding sphere (cover2: squared radius of the triangle alone) and nested radius.
  struct Accumulator {
    double err = 0.0, cover2 = 0.0, radius = 0.0;
    bool forced = false;
  };
  auto addTriangle = [&](Accumulator& acc, int i, int j, double zm, const Tri& tri, int triSide, double horizontal2,
                         bool finestSquareHalf, bool finest) {
    const std::size_t v = std::size_t(j) * side + i;
    const Coverage cover = clippedBlock ? coverage(tri, cellsX, cellsY) : Coverage::Inside;
    const double za = hAt(tri.ax, tri.ay), zb = hAt(tri.bx, tri.by), zc = hAt(tri.cx, tri.cy);
    // (Non-clipped stride-1 blocks take the short paths below for the finest two levels.)
    const double exact = cover != Coverage::Outside ? exactTriangleError(window, tri, za, zb, zc) : 0.0;
    const float triErr = roundUp(exact);
    acc.forced |= cover == Coverage::Straddles;
    m_triangleError[2 * v + triSide] = triErr;
    acc.err = std::max(acc.err, double(triErr));

    // Sphere around the midpoint holding the triangle in 3D: its footprint lies within the
    // circle through its corners, its plane and the surface under it within the corner
    // heights widened by its error.
    const double vertical = std::max(std::max(std::fabs(za - zm), std::fabs(zb - zm)), std::fabs(zc - zm)) + triErr;
    acc.cover2 = std::max(acc.cover2, horizontal2 + vertical * vertical);

    // Children: the midpoints of the legs, unless the legs are cell diagonals.
    if (finest && !finestSquareHalf) return;
    const int child[2][2] = {{(tri.ax + tri.bx) / 2, (tri.ay + tri.by) / 2},
                             {(tri.cx + tri.ax) / 2, (tri.cy + tri.ay) / 2}};
    for (const auto& c : child) {
      const std::size_t ci = std::size_t(c[1]) * side + c[0];
      const double ex = (c[0] - i) * dx, ey = (c[1] - j) * dy, ez = double(heights[ci]) - zm;
      acc.err = std::max(acc.err, double(m_error[ci]));
      acc.radius = std::max(acc.radius, std::sqrt(ex * ex + ey * ey + ez * ez) + double(m_radius[ci]));
    }
  };
  auto finish = [&](const Accumulator& acc, int i, int j) {
    const std::size_t v = std::size_t(j) * side + i;
    m_error[v] = acc.forced ? kForced : float(acc.err);  // a max of floats already
    m_radius[v] = roundUp(std::max(acc.radius, std::sqrt(acc.cover2)) * (1.0 + kRadiusSlack));
  };

  for (int shift = 0; shift < fp.k; ++shift) {
    const int h = 1 << shift;
    const bool finest = shift == 0;
    // Side midpoints first (their children are the finer square centres): the hypotenuse
    // b-c runs along u, the apexes sit at +-w (side 1 at +w: north or east).
    const double sideHorizontal2 = std::max(h * dx, h * dy) * std::max(h * dx, h * dy);
    for (int j = 0; j <= n; j += h) {
      const bool alongX = ((j >> shift) & 1) == 0;  // j a multiple of 2h: hypotenuse runs west-east
      const int ux = alongX ? h : 0, uy = alongX ? 0 : h;
      for (int i = alongX ? h : 0; i <= n; i += 2 * h) {
        const double zm = hAt(i, j);
        if (finest && fastFinest && !clippedBlock) {
          // Half of all triangles, so a short path: at stride 1 each triangle holds no sample
          // but its corners and the hypotenuse midpoint, and of its legs (cell diagonals) the
          // one running south-west to north-east crosses the surface's diagonal at that cell's
          // centre: the cell at (i-1, j) for the apex at (i, j+1) or (i-1, j), the cell at
          // (i, j-1) for the apex at (i, j-1) or (i+1, j).
          const std::size_t v = std::size_t(j) * side + i;
          const double zb = hAt(i - ux, j - uy), zc = hAt(i + ux, j + uy);
          const double midpoint = std::fabs(zm - 0.5 * (zb + zc));
          // (The same value, rounded up alike, as leafError of that cell's bintree halves: a
          // half cell left unflipped never exceeds the coarser triangle beside it.)
          auto gap = [&](int x, int y) {
            return cellCentreGap(hAt(x, y), hAt(x + 1, y), hAt(x, y + 1), hAt(x + 1, y + 1));
          };
          double vertical = std::max(std::fabs(zb - zm), std::fabs(zc - zm));
          float err0 = 0.0f, err1 = 0.0f;  // sides as triangleSide: 1 for the apex north or east
          if (i - uy >= 0 && j - ux >= 0) {
            vertical = std::max(vertical, std::fabs(hAt(i - uy, j - ux) - zm));
            err0 = roundUp(std::max(midpoint, alongX ? gap(i, j - 1) : gap(i - 1, j)));
          }
          if (i + uy <= n && j + ux <= n) {
            vertical = std::max(vertical, std::fabs(hAt(i + uy, j + ux) - zm));
            err1 = roundUp(std::max(midpoint, alongX ? gap(i - 1, j) : gap(i, j - 1)));
          }
          m_triangleError[2 * v] = err0;
          m_triangleError[2 * v + 1] = err1;
          m_error[v] = std::max(err0, err1);
          vertical += double(m_error[v]);
          m_radius[v] = roundUp(std::sqrt(sideHorizontal2 + vertical * vertical) * (1.0 + kRadiusSlack));
          continue;
        }
        Accumulator acc;
        for (int sgn = -1; sgn <= 1; sgn += 2) {
          const int ax = i + sgn * uy, ay = j + sgn * ux;  // w is u turned a quarter
          if (ax < 0 || ax > n || ay < 0 || ay > n) continue;
          const Tri tri = counterClockwise(ax, ay, i - ux, j - uy, i + ux, j + uy);
          addTriangle(acc, i, j, zm, tri, sgn > 0 ? 1 : 0, sideHorizontal2, false, finest);
        }
        finish(acc, i, j);
      }
    }
    // Then the centres of the squares of side 2h (whose children are these side midpoints).
    // The diagonals alternate like a checkerboard, each pointing at the centre of the square
    // one level up; the root square's runs south-east to north-west.
    const double centreHorizontal2 = h * dx * (h * dx) + h * dy * (h * dy);
    for (int j = h; j < n; j += 2 * h) {
      for (int i = h; i < n; i += 2 * h) {
        const int qx = (i - h) / (2 * h), qy = (j - h) / (2 * h);
        const bool southWestToNorthEast = 2 * h != n && ((qx + qy) & 1) == 0;
        const double zm = hAt(i, j);
        if (finest && fastFinest && !clippedBlock) {
          // A quarter of all triangles, so a short path: at stride 1 a half square of side 2
          // holds, besides its corners, the midpoints of its sides: this centre and the two
          // side midpoints on its legs, where the plane is the mean of the leg's ends. Its legs
          // are axis-aligned; a hypotenuse running south-west to north-east crosses the
          // diagonals of cells (i-1, j-1) and (i, j) at their centres, a quarter of the way
          // along from each end.
          const std::size_t v = std::size_t(j) * side + i;
          const std::size_t west = v - 1, east = v + 1, south = v - side, north = v + side;
          const double zb = southWestToNorthEast ? hAt(i - 1, j - 1) : hAt(i + 1, j - 1);
          const double zc = southWestToNorthEast ? hAt(i + 1, j + 1) : hAt(i - 1, j + 1);
          const double za0 = southWestToNorthEast ? hAt(i - 1, j + 1) : hAt(i - 1, j - 1);  // apex west
          const double za1 = southWestToNorthEast ? hAt(i + 1, j - 1) : hAt(i + 1, j + 1);  // apex east
          double shared = std::fabs(zm - 0.5 * (zb + zc));
          if (southWestToNorthEast) {
            shared = std::max({shared, std::fabs(0.5 * (hAt(i, j - 1) + hAt(i - 1, j)) - (0.75 * zb + 0.25 * zc)),
                               std::fabs(0.5 * (hAt(i + 1, j) + hAt(i, j + 1)) - (0.25 * zb + 0.75 * zc))});
          }
          const double devWest = std::fabs(hAt(i - 1, j) - 0.5 * (hAt(i - 1, j - 1) + hAt(i - 1, j + 1)));
          const double devEast = std::fabs(hAt(i + 1, j) - 0.5 * (hAt(i + 1, j - 1) + hAt(i + 1, j + 1)));
          const double devSouth = std::fabs(hAt(i, j - 1) - 0.5 * (hAt(i - 1, j - 1) + hAt(i + 1, j - 1)));
          const double devNorth = std::fabs(hAt(i, j + 1) - 0.5 * (hAt(i - 1, j + 1) + hAt(i + 1, j + 1)));
          // The apex's legs end at the side midpoints next to it.
          const float err0 = roundUp(std::max({shared, devWest, southWestToNorthEast ? devNorth : devSouth}));
          const float err1 = roundUp(std::max({shared, devEast, southWestToNorthEast ? devSouth : devNorth}));
          m_triangleError[2 * v] = err0;
          m_triangleError[2 * v + 1] = err1;
          m_error[v] = std::max({err0, err1, m_error[west], m_error[east], m_error[south], m_error[north]});
          const double diagonal = std::max(std::fabs(zb - zm), std::fabs(zc - zm));
          const double vertical0 = std::max(diagonal, std::fabs(za0 - zm)) + err0;
          const double vertical1 = std::max(diagonal, std::fabs(za1 - zm)) + err1;
          double radius = std::sqrt(centreHorizontal2 + std::max(vertical0 * vertical0, vertical1 * vertical1));
          for (const std::size_t c : {west, east, south, north}) {
            const double ex = c == west ? -dx : (c == east ? dx : 0.0), ey = c == south ? -dy : (c == north ? dy : 0.0);
            const double ez = double(heights[c]) - zm;
            radius = std::max(radius, std::sqrt(ex * ex + ey * ey + ez * ez) + double(m_radius[c]));
          }
          m_radius[v] = roundUp(radius * (1.0 + kRadiusSlack));
          continue;
        }
        Accumulator acc;
        if (southWestToNorthEast) {
          addTriangle(acc, i, j, zm, counterClockwise(i + h, j - h, i - h, j - h, i + h, j + h), 1, centreHorizontal2,
                      true, finest);
          addTriangle(acc, i, j, zm, counterClockwise(i - h, j + h, i - h, j - h, i + h, j + h), 0, centreHorizontal2,
                      true, finest);
        } else {
          addTriangle(acc, i, j, zm, counterClockwise(i - h, j - h, i + h, j - h, i - h, j + h), 0, centreHorizontal2,
                      true, finest);
          addTriangle(acc, i, j, zm, counterClockwise(i + h, j + h, i + h, j - h, i - h, j + h), 1, centreHorizontal2,
                      true, finest);
        }
        finish(acc, i, j);
      }
    }
  }

  // Node error: the exact error of the coarsest mesh (only forced splits).
  float coarsest = 0.0f;
  auto forcedOnly = [&](int i, int j) { return m_error[std::size_t(j) * side + i] == kForced; };
  auto maxLeaf = [&](int ax, int ay, int bx, int by, int cx, int cy, float err) {
    if (insideRect(Tri{ax, ay, bx, by, cx, cy}, m_cellsX, m_cellsY)) coarsest = std::max(coarsest, err);
  };
  walk(forcedOnly, maxLeaf);
  m_maxError = coarsest;
  // The full-detail mesh's error: its half cells'. At stride 1 every cell is a diamond there,
  // drawn cut like the surface: 0.
  m_floorError = m_leafError.empty() ? 0.0f : *std::max_element(m_leafError.begin(), m_leafError.end());
  return {};
}

// ---- queries ----------------------------------------------------------------------------

float BlockLod::leafError(int ci, int cj, int sideIndex) const {
  if (!m_leafError.empty()) return m_leafError[(std::size_t(cj) * m_footprint.cells() + ci) * 2 + sideIndex];
  // Stride 1: the bintree's half cells are full-resolution cells, cut like the surface where
  // the checkerboard cuts them north-west to south-east, the other way otherwise (drawn so only
  // when the cell's other half is not drawn, see walkTriangle).
  if (((ci + cj) & 1) != 0) return 0.0f;
  return roundUp(cellCentreGap(m_height[vertexIndex(ci, cj)], m_height[vertexIndex(ci + 1, cj)],
                               m_height[vertexIndex(ci, cj + 1)], m_height[vertexIndex(ci + 1, cj + 1)]));
}

float BlockLod::storedTriangleError(int ax, int ay, int bx, int by, int cx, int cy) const {
  const int sideIndex = triangleSide(ax, ay, bx, by, cx, cy);
  if (isHalfCell(bx, cx)) {
    // At stride 1 a half cell cut north-west to south-east is the surface itself.
    if (m_leafError.empty() && (bx - cx) != (by - cy)) return 0.0f;
    return leafError(std::min(bx, cx), std::min(by, cy), sideIndex);
  }
  return m_triangleError[2 * vertexIndex((bx + cx) / 2, (by + cy) / 2) + sideIndex];
}

float BlockLod::triangleError(GridVertex apex, GridVertex b, GridVertex c) const {
#ifndef NDEBUG
  {
    const int n = m_footprint.cells();
    bool found = false;
    if (isHalfCell(b.i, c.i)) {
      const int ci = std::min(b.i, c.i), cj = std::min(b.j, c.j);
      const bool southWestToNorthEast = ((ci + cj) & 1) == 0;
      const bool cutSouthWestToNorthEast = (b.i - c.i) == (b.j - c.j);
      // The bintree's cut, or at stride 1 the surface's (how a diamond's halves are drawn).
      const bool isDiagonal =
          cutSouthWestToNorthEast == southWestToNorthEast || (m_footprint.stride == 1 && !cutSouthWestToNorthEast);
      found = std::abs(b.j - c.j) == 1 && isDiagonal && (apex.i == ci || apex.i == ci + 1) &&
              (apex.j == cj || apex.j == cj + 1) && !(apex.i == b.i && apex.j == b.j) &&
              !(apex.i == c.i && apex.j == c.j);
    } else if (((b.i + c.i) & 1) == 0 && ((b.j + c.j) & 1) == 0) {
      Tri tris[2];
      const int count = splitTriangles((b.i + c.i) / 2, (b.j + c.j) / 2, n, tris);
      for (int t = 0; t < count; ++t) found |= tris[t].ax == apex.i && tris[t].ay == apex.j;
    }
    assert(found && "BlockLod::triangleError: not a triangle of the bintree");
  }
#endif
  return storedTriangleError(apex.i, apex.j, b.i, b.j, c.i, c.j);
}

std::size_t BlockLod::memoryBytes() const {
  return sizeof(*this) + sizeof(float) * (m_height.capacity() + m_error.capacity() + m_radius.capacity() +
                                          m_triangleError.capacity() + m_leafError.capacity());
}

}  // namespace polder::terrain
