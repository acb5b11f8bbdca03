// An independent statement of the heightfield's triangulation convention
// (terrain/heightfield.hpp), for tests to hold meshes and queries against.
#pragma once

#include <algorithm>

#include <polder/terrain/heightfield.hpp>

namespace polder::test {

// Height of the piecewise-linear surface at world (x, y): cell (cx, cy) is split along the
// diagonal from (cx+1, cy) to (cx, cy+1); the lower-left triangle holds a + b <= 1.
inline double conventionHeight(const terrain::Heightfield& field, double x, double y) {
  const double sx = x / field.spacingX, sy = y / field.spacingY;
  const int cx = std::min(int(sx), field.width - 2), cy = std::min(int(sy), field.height - 2);
  const double a = sx - cx, b = sy - cy;
  const double z00 = field.at(cx, cy), z10 = field.at(cx + 1, cy);
  const double z01 = field.at(cx, cy + 1), z11 = field.at(cx + 1, cy + 1);
  if (a + b <= 1.0) return z00 + a * (z10 - z00) + b * (z01 - z00);
  return z11 + (1.0 - a) * (z01 - z11) + (1.0 - b) * (z10 - z11);
}

}  // namespace polder::test
