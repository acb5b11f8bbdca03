// The right-triangle bintree over a block's grid (rtin.hpp), shared by the build of the error
// hierarchy (rtin_build.cpp) and the extractions (rtin_extract.cpp): the triangles a vertex
// splits, which of the two triangles on a hypotenuse one is, and the walk over the triangles
// of a mesh, which draws half cells the way the surface cuts them.
//
// Follows W. Evans, D. Kirkpatrick, G. Townsend, "Right-triangulated irregular networks"
// (Algorithmica 2001) for the bintree.
//
// Layout. Vertex (i, j) of a block with n = 2^k cells per side is the hypotenuse midpoint of
// the triangles it splits, found from its coordinates alone: with h the lowest set bit of
// (i | j), a vertex with i/h and j/h both odd is the centre of a square of side 2h (its two
// triangles share that square's diagonal); otherwise it is the midpoint of an axis-aligned
// hypotenuse of length 2h (one triangle on the block's side, two inside).
//
// Drawn half cells. At stride 1 the bintree cuts half of the cells (a checkerboard) south-west
// to north-east, off the surface by the gap between the cell's two cuts at its centre
// (rtin_build.cpp, "Exact errors"). So a cell whose two halves are both in the mesh (a
// diamond) is drawn cut like the surface (walkTriangle): error 0, same four sides, so
// conformity, the side lists and the neighbours are unchanged. A half cell whose hypotenuse
// neighbour is the coarser triangle on the other side of the cell's diagonal (that triangle's
// midpoint, the cell's other corner, is inactive) cannot be flipped without a T-junction there;
// it keeps the bintree's cut and error, the gap, which that coarser triangle's error (its leg is
// the same diagonal, crossing the same centre) already bounds, so it never exceeds what the
// extraction accepted.
#pragma once

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdlib>
#include <limits>

#include <polder/terrain/rtin.hpp>

namespace polder::terrain {
namespace detail {

// The error of a vertex that must always be split (a clipped block's straddling triangles).
inline constexpr float kForced = std::numeric_limits<float>::infinity();

// A bintree triangle: right-angle apex a, hypotenuse b-c, counter-clockwise seen from above.
struct Tri {
  int ax, ay, bx, by, cx, cy;
};

inline Tri counterClockwise(int ax, int ay, int px, int py, int qx, int qy) {
  const long long cross = (long long)(px - ax) * (qy - ay) - (long long)(py - ay) * (qx - ax);
  return cross > 0 ? Tri{ax, ay, px, py, qx, qy} : Tri{ax, ay, qx, qy, px, py};
}

// Which of the two triangles on a hypotenuse this one is: 1 when its apex lies east of the
// hypotenuse's midpoint, or due north of it. Works in doubled coordinates for half cells.
inline int triangleSide(int ax, int ay, int bx, int by, int cx, int cy) {
  const int ax2 = 2 * ax, ay2 = 2 * ay, mx2 = bx + cx, my2 = by + cy;
  return (ax2 > mx2 || (ax2 == mx2 && ay2 > my2)) ? 1 : 0;
}

inline bool isHalfCell(int bx, int cx) { return std::abs(bx - cx) == 1; }

// The triangles that vertex (i, j) splits, in a block of n cells per side (see the top).
inline int splitTriangles(int i, int j, int n, Tri out[2]) {
  if ((i == 0 || i == n) && (j == 0 || j == n)) return 0;
  const int shift = std::countr_zero(unsigned(i | j));
  const int h = 1 << shift;
  const bool iOdd = ((i >> shift) & 1) != 0, jOdd = ((j >> shift) & 1) != 0;
  if (iOdd && jOdd) {
    // Square centres alternate their diagonal like a checkerboard, each diagonal pointing at
    // the centre of the square one level up; the root square uses south-east to north-west.
    const int qx = (i - h) / (2 * h), qy = (j - h) / (2 * h);
    const bool southWestToNorthEast = 2 * h != n && ((qx + qy) & 1) == 0;
    if (southWestToNorthEast) {
      out[0] = counterClockwise(i + h, j - h, i - h, j - h, i + h, j + h);
      out[1] = counterClockwise(i - h, j + h, i - h, j - h, i + h, j + h);
    } else {
      out[0] = counterClockwise(i - h, j - h, i + h, j - h, i - h, j + h);
      out[1] = counterClockwise(i + h, j + h, i + h, j - h, i - h, j + h);
    }
    return 2;
  }
  int count = 0;
  if (iOdd) {  // hypotenuse runs west-east
    if (j > 0) out[count++] = counterClockwise(i, j - h, i - h, j, i + h, j);
    if (j < n) out[count++] = counterClockwise(i, j + h, i - h, j, i + h, j);
  } else {  // hypotenuse runs south-north
    if (i > 0) out[count++] = counterClockwise(i - h, j, i, j - h, i, j + h);
    if (i < n) out[count++] = counterClockwise(i + h, j, i, j - h, i, j + h);
  }
  return count;
}

inline int splitTriangleCount(int i, int j, int n) {
  if ((i == 0 || i == n) && (j == 0 || j == n)) return 0;
  const int shift = std::countr_zero(unsigned(i | j));
  const bool iOdd = ((i >> shift) & 1) != 0, jOdd = ((j >> shift) & 1) != 0;
  if (iOdd && jOdd) return 2;
  if (iOdd) return int(j > 0) + int(j < n);
  return int(i > 0) + int(i < n);
}

inline bool insideRect(const Tri& t, int cx, int cy) {
  return std::max({t.ax, t.bx, t.cx}) <= cx && std::max({t.ay, t.by, t.cy}) <= cy;
}

}  // namespace detail

template <class Active, class Leaf>
void BlockLod::walk(Active& active, Leaf& leaf) const {
  const int n = m_footprint.cells();
  walkTriangle(0, 0, n, 0, 0, n, active, leaf);  // south-west half
  walkTriangle(n, n, 0, n, n, 0, active, leaf);  // north-east half
}

template <class Active, class Leaf>
void BlockLod::walkTriangle(int ax, int ay, int bx, int by, int cx, int cy, Active& active, Leaf& leaf) const {
  // Nothing of a clipped block's outside reaches the mesh.
  if (m_clipped && (std::min({ax, bx, cx}) >= m_cellsX || std::min({ay, by, cy}) >= m_cellsY)) return;
  const int mx2 = bx + cx, my2 = by + cy;                                           // doubled hypotenuse midpoint
  const int sideIndex = (2 * ax > mx2 || (2 * ax == mx2 && 2 * ay > my2)) ? 1 : 0;  // as triangleSide
  if (detail::isHalfCell(bx, cx)) {
    const int ci = std::min(bx, cx), cj = std::min(by, cy);
    // At stride 1 a half cell cut south-west to north-east, whose cell's other half is drawn too
    // (its apex, the opposite corner, is active: with a conforming mesh, that half's parent is
    // split), is drawn as the matching half of the surface's cut instead, error 0: apex p10 ->
    // {p00, p10, p01}, apex p01 -> {p11, p01, p10}, both counter-clockwise. Otherwise its
    // hypotenuse is a leg of the coarser triangle beside it and it keeps the bintree's cut.
    if (m_footprint.stride == 1 && (bx - cx) == (by - cy) && active(bx + cx - ax, by + cy - ay)) {
      if (ax > ci) {
        leaf(ci, cj, ci + 1, cj, ci, cj + 1, 0.0f);
      } else {
        leaf(ci + 1, cj + 1, ci, cj + 1, ci + 1, cj, 0.0f);
      }
      return;
    }
    leaf(ax, ay, bx, by, cx, cy, leafError(ci, cj, sideIndex));
    return;
  }
  const int mx = mx2 / 2, my = my2 / 2;
  if (active(mx, my)) {
    walkTriangle(mx, my, ax, ay, bx, by, active, leaf);
    walkTriangle(mx, my, cx, cy, ax, ay, active, leaf);
  } else {
    const std::size_t v = std::size_t(my) * m_footprint.verticesPerSide() + mx;
    leaf(ax, ay, bx, by, cx, cy, m_triangleError[2 * v + sideIndex]);
  }
}

}  // namespace polder::terrain
