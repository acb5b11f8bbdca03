// Per-block LOD (rtin.hpp): exact and monotone errors, nested radii, conforming meshes from
// every extraction, honest reported errors, the view-dependent bound, clipped blocks.
// Everything is checked against brute force written here, independently of rtin_build.cpp and
// rtin_extract.cpp. The true surface is the full-resolution triangulation of heightfield.hpp
// (each cell cut from (x+1, y) to (x, y+1)), not only its samples.
#include <polder/terrain/rtin.hpp>

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <map>
#include <numeric>
#include <random>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "geometry_reference.hpp"

namespace polder::terrain {
namespace {

enum class Shape { Flat, Plane, Random, Sines, Fractal };

const char* shapeName(Shape shape) {
  switch (shape) {
    case Shape::Flat:
      return "flat";
    case Shape::Plane:
      return "plane";
    case Shape::Random:
      return "random";
    case Shape::Sines:
      return "sines";
    case Shape::Fractal:
      return "fractal";
  }
  return "?";
}

// Value noise: octaves of bilinearly interpolated random lattices, hills without erosion.
float fractalAt(const std::vector<std::vector<float>>& lattices, int x, int y) {
  float sum = 0.0f;
  for (std::size_t o = 0; o < lattices.size(); ++o) {
    const int period = 64 >> o;
    const int side = 1024 / period + 2;
    const int gx = x / period, gy = y / period;
    const float fx = float(x % period) / period, fy = float(y % period) / period;
    const auto& l = lattices[o];
    const float v00 = l[gy * side + gx], v10 = l[gy * side + gx + 1];
    const float v01 = l[(gy + 1) * side + gx], v11 = l[(gy + 1) * side + gx + 1];
    const float v0 = v00 + (v10 - v00) * fx, v1 = v01 + (v11 - v01) * fx;
    sum += (v0 + (v1 - v0) * fy) * (120.0f / float(1 << o));
  }
  return sum;
}

Heightfield makeField(Shape shape, int width, int height, unsigned seed, double sx = 10.0, double sy = 10.0) {
  Heightfield field(width, height, sx, sy);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<std::vector<float>> lattices;
  if (shape == Shape::Fractal) {
    for (int o = 0; o < 6; ++o) {
      const int side = 1024 / (64 >> o) + 2;
      std::vector<float> l(std::size_t(side) * side);
      for (float& v : l) v = unit(rng);
      lattices.push_back(std::move(l));
    }
  }
  const float phase = unit(rng) * 6.0f;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      float h = 0.0f;
      switch (shape) {
        case Shape::Flat:
          h = 12.5f;
          break;
        case Shape::Plane:
          h = float(x + 2 * y);
          break;  // exact in float: a true plane
        case Shape::Random:
          h = 100.0f * unit(rng);
          break;
        case Shape::Sines:
          h = 40.0f * std::sin(0.05f * x + phase) + 25.0f * std::cos(0.083f * y - 0.3f * phase) +
              6.0f * std::sin(0.31f * (x + y)) + 2.0f * std::sin(1.7f * x - 0.9f * y);
          break;
        // A last octave of per-sample jitter: bilinear octaves alone are exactly planar
        // along many lines, which makes vertices free.
        case Shape::Fractal:
          h = fractalAt(lattices, x, y) + 0.5f * unit(rng);
          break;
      }
      field.at(x, y) = h;
    }
  }
  return field;
}

struct P2 {
  long long x, y;
};

long long cross(P2 o, P2 a, P2 b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); }

// Full-resolution corners of block-local vertex (i, j).
P2 fullRes(const BlockFootprint& fp, int i, int j) {
  return {fp.x0 + (long long)i * fp.stride, fp.y0 + (long long)j * fp.stride};
}

// Brute force: largest vertical distance between the plane through the triangle's full-resolution
// corners and the full-resolution triangulated surface over the closed triangle. Their difference is
// linear on every piece of the overlay of the two triangulations, so its extremes lie at the
// overlay's vertices: samples, and points where the triangle's edges cross cell diagonals. Those
// crossings are cell centres (a bintree edge is axis-aligned or at 45 degrees), so taking every
// sample and every cell centre in the closed triangle (a superset of the overlay's vertices, all on
// the surface) gives the exact maximum. At a cell centre the surface is the mean of the diagonal's
// ends, (x+1, y) and (x, y+1). Works in doubled coordinates so that centres are integers.
double bruteError(const Heightfield& field, const BlockFootprint& fp, GridVertex a, GridVertex b, GridVertex c) {
  const P2 pa = fullRes(fp, a.i, a.j), pb = fullRes(fp, b.i, b.j), pc = fullRes(fp, c.i, c.j);
  const P2 qa{2 * pa.x, 2 * pa.y}, qb{2 * pb.x, 2 * pb.y}, qc{2 * pc.x, 2 * pc.y};
  const long long area2 = cross(qa, qb, qc);
  const double za = field.at(int(pa.x), int(pa.y)), zb = field.at(int(pb.x), int(pb.y)),
               zc = field.at(int(pc.x), int(pc.y));
  const long long x0 = std::min({pa.x, pb.x, pc.x}), x1 = std::max({pa.x, pb.x, pc.x});
  const long long y0 = std::min({pa.y, pb.y, pc.y}), y1 = std::max({pa.y, pb.y, pc.y});
  double err = 0.0;
  for (long long y2 = 2 * y0; y2 <= 2 * y1; ++y2) {
    for (long long x2 = 2 * x0; x2 <= 2 * x1; ++x2) {
      const bool sample = (x2 % 2 == 0) && (y2 % 2 == 0), centre = (x2 % 2 == 1) && (y2 % 2 == 1);
      if (!sample && !centre) continue;
      const P2 p{x2, y2};
      const long long wa = cross(qb, qc, p), wb = cross(qc, qa, p), wc = cross(qa, qb, p);
      if (area2 > 0 ? (wa < 0 || wb < 0 || wc < 0) : (wa > 0 || wb > 0 || wc > 0)) continue;
      const double plane = (wa * za + wb * zb + wc * zc) / double(area2);
      const int x = int(x2 / 2), y = int(y2 / 2);
      const double surface =
          sample ? double(field.at(x, y)) : 0.5 * (double(field.at(x + 1, y)) + double(field.at(x, y + 1)));
      err = std::max(err, std::fabs(surface - plane));
    }
  }
  return err;
}

double tolerance(double value) { return 1e-6 + 1e-6 * std::fabs(value); }

glm::dvec3 worldRelative(const Heightfield& field, const BlockFootprint& fp, long long x, long long y) {
  return {(x - fp.x0) * field.spacingX, (y - fp.y0) * field.spacingY, double(field.at(int(x), int(y)))};
}

using test::pointTriangleDistance;

// Conformity: the triangles are counter-clockwise, tile [0, cellsX] x [0, cellsY] exactly once,
// share every interior edge with exactly one other triangle, have no vertex inside another's
// edge; the side lists are the sorted mesh vertices on each side, corners included.
void expectConforming(const BlockMesh& mesh) {
  const int cx = mesh.cellsX, cy = mesh.cellsY;
  ASSERT_GT(cx, 0);
  ASSERT_GT(cy, 0);
  ASSERT_EQ(mesh.indices.size() % 3, 0u);
  const int side = mesh.footprint.verticesPerSide();
  std::vector<int> at(std::size_t(side) * side, -1);
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    const GridVertex g = mesh.vertices[v];
    ASSERT_LE(g.i, cx);
    ASSERT_LE(g.j, cy);
    ASSERT_EQ(at[g.j * side + g.i], -1) << "duplicate vertex " << g.i << "," << g.j;
    at[g.j * side + g.i] = int(v);
  }
  std::vector<int> used(mesh.vertices.size(), 0);
  std::vector<int> cover(std::size_t(cx) * cy * 4, 0);
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  long long area2Sum = 0;
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    std::uint32_t id[3];
    P2 p[3];
    for (int c = 0; c < 3; ++c) {
      id[c] = mesh.indices[3 * t + c];
      ASSERT_LT(id[c], mesh.vertices.size());
      used[id[c]] = 1;
      p[c] = {mesh.vertices[id[c]].i, mesh.vertices[id[c]].j};
    }
    const long long area2 = cross(p[0], p[1], p[2]);
    ASSERT_GT(area2, 0) << "triangle " << t << " is not counter-clockwise";
    area2Sum += area2;
    // Coverage at four points per cell (quadrupled coordinates), never on any bintree edge.
    const long long x0 = std::min({p[0].x, p[1].x, p[2].x}), x1 = std::max({p[0].x, p[1].x, p[2].x});
    const long long y0 = std::min({p[0].y, p[1].y, p[2].y}), y1 = std::max({p[0].y, p[1].y, p[2].y});
    const P2 q[3] = {{4 * p[0].x, 4 * p[0].y}, {4 * p[1].x, 4 * p[1].y}, {4 * p[2].x, 4 * p[2].y}};
    for (long long y = y0; y < y1; ++y) {
      for (long long x = x0; x < x1; ++x) {
        const P2 pts[4] = {
            {4 * x + 1, 4 * y + 2}, {4 * x + 3, 4 * y + 2}, {4 * x + 2, 4 * y + 1}, {4 * x + 2, 4 * y + 3}};
        for (int k = 0; k < 4; ++k) {
          if (cross(q[0], q[1], pts[k]) > 0 && cross(q[1], q[2], pts[k]) > 0 && cross(q[2], q[0], pts[k]) > 0)
            ++cover[(y * cx + x) * 4 + k];
        }
      }
    }
    for (int e = 0; e < 3; ++e) {
      const std::uint32_t u = id[e], v = id[(e + 1) % 3];
      ASSERT_EQ(directed[std::make_pair(u, v)]++, 0) << "directed edge used twice";
      // No mesh vertex strictly inside this edge (no T-junction).
      const P2 a = p[e], b = p[(e + 1) % 3];
      const long long dx = b.x - a.x, dy = b.y - a.y;
      const long long g = std::gcd(std::llabs(dx), std::llabs(dy));
      for (long long s = 1; s < g; ++s) {
        const long long x = a.x + s * dx / g, y = a.y + s * dy / g;
        ASSERT_EQ(at[y * side + x], -1) << "T-junction at " << x << "," << y;
      }
    }
  }
  EXPECT_EQ(area2Sum, 2LL * cx * cy);
  for (std::size_t c = 0; c < cover.size(); ++c) ASSERT_EQ(cover[c], 1) << "cell point " << c << " covered wrongly";
  for (std::size_t v = 0; v < used.size(); ++v) ASSERT_EQ(used[v], 1) << "unused vertex " << v;
  for (const auto& [edge, count] : directed) {
    if (directed.count({edge.second, edge.first}) != 0) continue;
    const GridVertex a = mesh.vertices[edge.first], b = mesh.vertices[edge.second];
    const bool onSide =
        (a.i == 0 && b.i == 0) || (a.i == cx && b.i == cx) || (a.j == 0 && b.j == 0) || (a.j == cy && b.j == cy);
    ASSERT_TRUE(onSide) << "interior edge with one triangle: " << a.i << "," << a.j << " - " << b.i << "," << b.j;
  }
  // Side lists.
  auto expectSide = [&](BlockEdge which, int i0, int j0, int di, int dj, int steps) {
    std::vector<std::uint32_t> expected;
    for (int s = 0; s <= steps; ++s) {
      const int v = at[(j0 + s * dj) * side + (i0 + s * di)];
      if (v >= 0) expected.push_back(std::uint32_t(v));
    }
    EXPECT_EQ(mesh.edge(which), expected) << "side " << int(which);
    ASSERT_GE(mesh.edge(which).size(), 2u);
    const GridVertex first = mesh.vertices[mesh.edge(which).front()], last = mesh.vertices[mesh.edge(which).back()];
    EXPECT_TRUE(first.i == i0 && first.j == j0) << "side " << int(which) << " misses its first corner";
    EXPECT_TRUE(last.i == i0 + steps * di && last.j == j0 + steps * dj) << "side " << int(which) << " misses a corner";
  };
  expectSide(BlockEdge::South, 0, 0, 1, 0, cx);
  expectSide(BlockEdge::East, cx, 0, 0, 1, cy);
  expectSide(BlockEdge::North, 0, cy, 1, 0, cx);
  expectSide(BlockEdge::West, 0, 0, 0, 1, cy);
}

// Every triangle's brute-force error is within the reported mesh error, which is their maximum.
void expectHonest(const Heightfield& field, const BlockMesh& mesh) {
  double worst = 0.0;
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    const GridVertex a = mesh.vertices[mesh.indices[3 * t]], b = mesh.vertices[mesh.indices[3 * t + 1]],
                     c = mesh.vertices[mesh.indices[3 * t + 2]];
    const double err = bruteError(field, mesh.footprint, a, b, c);
    ASSERT_LE(err, double(mesh.maxError)) << "triangle " << t << " hides more error than reported";
    worst = std::max(worst, err);
  }
  EXPECT_NEAR(worst, double(mesh.maxError), tolerance(worst)) << "reported error is not the mesh's";
}

// At stride 1, the half of cell (i, j) with apex `a` cut south-west to north-east (the bintree's
// cut), as drawn cut like the surface: apex p10 -> {p00, p10, p01}, apex p01 -> {p11, p01, p10}.
std::array<GridVertex, 3> surfaceHalf(GridVertex a, GridVertex b, GridVertex c) {
  const std::uint16_t i = std::min(b.i, c.i), j = std::min(b.j, c.j);
  const GridVertex p00{i, j}, p10{std::uint16_t(i + 1), j}, p01{i, std::uint16_t(j + 1)},
      p11{std::uint16_t(i + 1), std::uint16_t(j + 1)};
  if (a.i > i) return {p00, p10, p01};
  return {p11, p01, p10};
}

// How the mesh cuts its half cells: a cell with both halves (a diamond) is cut like the surface
// at stride 1 (north-west to south-east), like the bintree's checkerboard otherwise (south-west to
// north-east where i + j is even); a lone half cell is always the bintree's. Returns how many
// lone half cells at stride 1 keep the cut against the surface.
int expectHalfCellCuts(const BlockMesh& mesh) {
  std::map<std::pair<int, int>, std::vector<bool>> cells;  // cell -> its halves, cut south-west to north-east?
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    GridVertex v[3];
    for (int c = 0; c < 3; ++c) v[c] = mesh.vertices[mesh.indices[3 * t + c]];
    const int i0 = std::min({v[0].i, v[1].i, v[2].i}), i1 = std::max({v[0].i, v[1].i, v[2].i});
    const int j0 = std::min({v[0].j, v[1].j, v[2].j}), j1 = std::max({v[0].j, v[1].j, v[2].j});
    if (i1 - i0 != 1 || j1 - j0 != 1) continue;
    bool hasP00 = false, hasP11 = false;
    for (const GridVertex& g : v) {
      hasP00 |= g.i == i0 && g.j == j0;
      hasP11 |= g.i == i1 && g.j == j1;
    }
    cells[{i0, j0}].push_back(hasP00 && hasP11);
  }
  int lonelyAgainstSurface = 0;
  for (const auto& [cell, cuts] : cells) {
    const bool checkerboardSouthWestToNorthEast = ((cell.first + cell.second) & 1) == 0;
    EXPECT_LE(cuts.size(), 2u);
    if (cuts.size() == 2) {
      EXPECT_EQ(cuts[0], cuts[1]) << "cell " << cell.first << "," << cell.second;
    }
    const bool expected = (cuts.size() == 2 && mesh.footprint.stride == 1) ? false : checkerboardSouthWestToNorthEast;
    for (bool cut : cuts) {
      EXPECT_EQ(cut, expected) << "cell " << cell.first << "," << cell.second << " with " << cuts.size() << " halves";
    }
    lonelyAgainstSurface += mesh.footprint.stride == 1 && cuts.size() == 1 && cuts[0];
  }
  return lonelyAgainstSurface;
}

// Walks the bintree (written here independently) and checks every triangle and vertex.
void expectHierarchy(const Heightfield& field, const BlockLod& lod) {
  const BlockFootprint& fp = lod.footprint();
  const int n = fp.cells();
  std::vector<std::vector<int>> pending = {{0, 0, n, 0, 0, n}, {n, n, 0, n, n, 0}};
  int checked = 0;
  double floor = 0.0;
  while (!pending.empty()) {
    const std::vector<int> t = pending.back();
    pending.pop_back();
    const GridVertex a{std::uint16_t(t[0]), std::uint16_t(t[1])}, b{std::uint16_t(t[2]), std::uint16_t(t[3])},
        c{std::uint16_t(t[4]), std::uint16_t(t[5])};
    const bool inside = std::max({a.i, b.i, c.i}) <= lod.cellsX() && std::max({a.j, b.j, c.j}) <= lod.cellsY();
    const float stored = lod.triangleError(a, b, c);
    if (inside) {
      const double brute = bruteError(field, fp, a, b, c);
      ASSERT_GE(double(stored), brute) << "triangle error below the exact error";
      ASSERT_LE(double(stored), brute + tolerance(brute)) << "triangle error not exact";
    }
    if (std::abs(b.i - c.i) == 1) {  // half cell: a leaf, whose error is the floor
      if (fp.stride == 1 && (b.i - c.i) == (b.j - c.j)) {
        // Cut against the surface: the full-detail mesh draws it as the surface's half, exact.
        const std::array<GridVertex, 3> f = surfaceHalf(a, b, c);
        EXPECT_EQ(lod.triangleError(f[0], f[1], f[2]), 0.0f);
        EXPECT_EQ(lod.triangleError(f[0], f[2], f[1]), 0.0f);  // either winding
        if (inside) {
          ASSERT_LE(bruteError(field, fp, f[0], f[1], f[2]), tolerance(0.0)) << "the surface's half is not exact";
        }
        continue;
      }
      if (inside) floor = std::max(floor, double(stored));
      continue;
    }
    ++checked;
    const int mi = (b.i + c.i) / 2, mj = (b.j + c.j) / 2;
    const double em = lod.vertexError(mi, mj), rm = lod.vertexRadius(mi, mj);
    ASSERT_GE(em, double(stored)) << "vertex error below its triangle's";
    const glm::dvec3 pm = lod.position(mi, mj);
    if (inside) {
      // The sphere holds the triangle's corners and the samples under it.
      for (GridVertex v : {a, b, c}) ASSERT_LE(glm::length(lod.position(v.i, v.j) - pm), rm);
      const P2 pa = fullRes(fp, a.i, a.j), pb = fullRes(fp, b.i, b.j), pc = fullRes(fp, c.i, c.j);
      for (long long y = std::min({pa.y, pb.y, pc.y}); y <= std::max({pa.y, pb.y, pc.y}); ++y) {
        for (long long x = std::min({pa.x, pb.x, pc.x}); x <= std::max({pa.x, pb.x, pc.x}); ++x) {
          const P2 p{x, y};
          if (cross(pa, pb, p) < 0 || cross(pb, pc, p) < 0 || cross(pc, pa, p) < 0) continue;
          ASSERT_LE(glm::length(worldRelative(field, fp, x, y) - pm), rm) << "sample outside the sphere";
        }
      }
      // And the surface at the cell centres on its edges (see bruteError), in doubled coordinates.
      const P2 qa{2 * pa.x, 2 * pa.y}, qb{2 * pb.x, 2 * pb.y}, qc{2 * pc.x, 2 * pc.y};
      for (long long y = std::min({pa.y, pb.y, pc.y}); y < std::max({pa.y, pb.y, pc.y}); ++y) {
        for (long long x = std::min({pa.x, pb.x, pc.x}); x < std::max({pa.x, pb.x, pc.x}); ++x) {
          const P2 p{2 * x + 1, 2 * y + 1};
          if (cross(qa, qb, p) < 0 || cross(qb, qc, p) < 0 || cross(qc, qa, p) < 0) continue;
          const glm::dvec3 centre((x + 0.5 - fp.x0) * field.spacingX, (y + 0.5 - fp.y0) * field.spacingY,
                                  0.5 * (double(field.at(int(x) + 1, int(y))) + double(field.at(int(x), int(y) + 1))));
          ASSERT_LE(glm::length(centre - pm), rm) << "cell centre outside the sphere";
        }
      }
    }
    const int children[2][6] = {{mi, mj, a.i, a.j, b.i, b.j}, {mi, mj, c.i, c.j, a.i, a.j}};
    for (const auto& child : children) {
      pending.push_back(std::vector<int>(child, child + 6));
      const int sx = child[4] + child[2], sy = child[5] + child[3];
      if ((sx & 1) || (sy & 1)) continue;  // the child is a half cell
      const int ci = sx / 2, cj = sy / 2;
      // Monotone errors and nested spheres (nesting with every descendant follows from the
      // triangle inequality).
      ASSERT_GE(em, double(lod.vertexError(ci, cj))) << "error not monotone at " << mi << "," << mj;
      ASSERT_GE(rm, glm::length(lod.position(ci, cj) - pm) + lod.vertexRadius(ci, cj))
          << "radius not nested at " << mi << "," << mj;
    }
  }
  EXPECT_EQ(checked, 2 * (n * n - 1));
  // The full-detail mesh's error: its half cells' (0 at stride 1, where the halves cut against
  // the surface are drawn as the surface's).
  if (fp.stride == 1) {
    EXPECT_EQ(lod.floorError(), 0.0f);
  }
  EXPECT_GE(double(lod.floorError()), floor);
  EXPECT_NEAR(double(lod.floorError()), floor, tolerance(floor));
}

struct Block {
  Heightfield field;
  BlockLod lod;
};

Block makeBlock(Shape shape, int k, int stride, unsigned seed) {
  const int n = 1 << k;
  Block block;
  block.field = makeField(shape, n * stride + 1 + 3 + 5, n * stride + 1 + 2 + 4, seed);
  auto built = BlockLod::build(block.field, BlockFootprint{3, 2, k, stride});
  EXPECT_TRUE(built.ok()) << (built.ok() ? "" : built.error().message);
  if (built.ok()) block.lod = std::move(built).value();
  return block;
}

struct Config {
  Shape shape;
  int k;
  int stride;
};

std::string configName(const testing::TestParamInfo<Config>& info) {
  return std::string(shapeName(info.param.shape)) + "_k" + std::to_string(info.param.k) + "_s" +
         std::to_string(info.param.stride);
}

class RtinBlockTest : public testing::TestWithParam<Config> {};

TEST_P(RtinBlockTest, ErrorsAreExactMonotoneAndNested) {
  const Config cfg = GetParam();
  const Block block = makeBlock(cfg.shape, cfg.k, cfg.stride, 17u + cfg.k);
  expectHierarchy(block.field, block.lod);
  // The node error is the two root triangles' exact error.
  const int n = 1 << cfg.k;
  const BlockFootprint& fp = block.lod.footprint();
  const double roots = std::max(
      bruteError(block.field, fp, {0, 0}, {std::uint16_t(n), 0}, {0, std::uint16_t(n)}),
      bruteError(block.field, fp, {std::uint16_t(n), std::uint16_t(n)}, {0, std::uint16_t(n)}, {std::uint16_t(n), 0}));
  EXPECT_GE(double(block.lod.maxError()), roots);
  EXPECT_NEAR(double(block.lod.maxError()), roots, tolerance(roots));
}

TEST_P(RtinBlockTest, ThresholdExtractionIsConformingAndHonest) {
  const Config cfg = GetParam();
  const Block block = makeBlock(cfg.shape, cfg.k, cfg.stride, 29u + cfg.k);
  BlockMesh mesh;
  RtinScratch scratch;
  const float top = block.lod.maxError();
  std::size_t previous = 0;
  for (float fraction : {2.0f, 1.0f, 0.5f, 0.2f, 0.05f, 0.01f, 0.0f}) {
    const float threshold = top * fraction;
    block.lod.extractThreshold(threshold, mesh, scratch);
    SCOPED_TRACE("threshold " + std::to_string(threshold) + ", " + std::to_string(mesh.triangleCount()) + " triangles");
    expectConforming(mesh);
    expectHonest(block.field, mesh);
    expectHalfCellCuts(mesh);
    // Only half cells (the floor) may exceed the threshold, and at stride 1 not even those.
    EXPECT_LE(mesh.maxError, cfg.stride == 1 ? threshold : std::max(threshold, block.lod.floorError()));
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
      const GridVertex a = mesh.vertices[mesh.indices[3 * t]], b = mesh.vertices[mesh.indices[3 * t + 1]],
                       c = mesh.vertices[mesh.indices[3 * t + 2]];
      if (cfg.stride == 1 || std::abs(b.i - c.i) != 1) {
        ASSERT_LE(block.lod.triangleError(a, b, c), threshold) << "triangle " << t;
      }
    }
    EXPECT_GE(mesh.triangleCount(), previous);
    previous = mesh.triangleCount();
  }
  EXPECT_EQ(mesh.triangleCount(), std::size_t(2) << (2 * cfg.k));  // threshold 0 on rough ground
  block.lod.extractThreshold(-1.0f, mesh, scratch);
  EXPECT_EQ(mesh.triangleCount(), std::size_t(2) << (2 * cfg.k));
  EXPECT_EQ(mesh.vertices.size(), blockMeshVertexBound(cfg.k));
  EXPECT_EQ(mesh.maxError, block.lod.floorError());
  block.lod.extractThreshold(FLT_MAX, mesh, scratch);
  EXPECT_EQ(mesh.triangleCount(), 2u);
  EXPECT_EQ(mesh.maxError, block.lod.maxError());
}

TEST_P(RtinBlockTest, CountExtractionMeetsTheTarget) {
  const Config cfg = GetParam();
  const Block block = makeBlock(cfg.shape, cfg.k, cfg.stride, 31u + cfg.k);
  const std::size_t full = std::size_t(2) << (2 * cfg.k);
  BlockMesh mesh;
  RtinScratch scratch;
  for (std::size_t target : {std::size_t(0), std::size_t(2), std::size_t(3), std::size_t(10), std::size_t(57),
                             std::size_t(200), full / 3, full - 1, full, full + 10}) {
    block.lod.extractCount(target, mesh, scratch);
    SCOPED_TRACE("target " + std::to_string(target) + ", got " + std::to_string(mesh.triangleCount()));
    expectConforming(mesh);
    expectHonest(block.field, mesh);
    expectHalfCellCuts(mesh);
    const std::size_t expected = std::max<std::size_t>(2, std::min(target, full));
    EXPECT_LE(mesh.triangleCount(), expected);
    EXPECT_GE(mesh.triangleCount() + 1, expected);  // a split adds one or two triangles
  }
}

// Greedy refinement by monotone errors passes through every threshold mesh: asked for the
// triangle count of a threshold mesh, it returns that mesh.
TEST_P(RtinBlockTest, CountExtractionMatchesThresholdMeshes) {
  const Config cfg = GetParam();
  const Block block = makeBlock(cfg.shape, cfg.k, cfg.stride, 41u + cfg.k);
  BlockMesh byThreshold, byCount;
  RtinScratch scratch;
  for (float fraction : {0.5f, 0.1f, 0.02f}) {
    const float threshold = block.lod.maxError() * fraction;
    block.lod.extractThreshold(threshold, byThreshold, scratch);
    block.lod.extractCount(byThreshold.triangleCount(), byCount, scratch);
    EXPECT_EQ(byCount.triangleCount(), byThreshold.triangleCount()) << "threshold " << threshold;
    EXPECT_EQ(byCount.maxError, byThreshold.maxError) << "threshold " << threshold;
  }
}

TEST_P(RtinBlockTest, ViewExtractionKeepsProjectedErrorWithinTolerance) {
  const Config cfg = GetParam();
  const Block block = makeBlock(cfg.shape, cfg.k, cfg.stride, 37u + cfg.k);
  const BlockLod& lod = block.lod;
  const double extentX = lod.footprint().cells() * lod.footprint().stride * block.field.spacingX;
  const double extentY = lod.footprint().cells() * lod.footprint().stride * block.field.spacingY;
  std::mt19937 rng(99u + cfg.k * 7u + cfg.stride);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  BlockMesh mesh;
  RtinScratch scratch;
  const double kConstant = 720.0 / (2.0 * std::tan(glm::radians(30.0)));
  int refinedSomewhere = 0;
  for (int trial = 0; trial < 12; ++trial) {
    LodView view;
    view.camera = {(unit(rng) * 2.0 - 0.5) * extentX, (unit(rng) * 2.0 - 0.5) * extentY,
                   lod.maxHeight() + 2.0 + unit(rng) * (trial < 6 ? 30.0 : 600.0)};
    view.projectionConstant = kConstant;
    view.tolerancePx = trial % 3 == 0 ? 0.5 : (trial % 3 == 1 ? 2.0 : 8.0);
    view.nearM = 1.0;
    lod.extractView(view, mesh, scratch);
    SCOPED_TRACE("trial " + std::to_string(trial) + ", " + std::to_string(mesh.triangleCount()) + " triangles");
    expectConforming(mesh);
    expectHonest(block.field, mesh);
    expectHalfCellCuts(mesh);
    refinedSomewhere += mesh.triangleCount() > 2;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
      const GridVertex a = mesh.vertices[mesh.indices[3 * t]], b = mesh.vertices[mesh.indices[3 * t + 1]],
                       c = mesh.vertices[mesh.indices[3 * t + 2]];
      if (std::abs(b.i - c.i) == 1) continue;  // a half cell: only a finer quadtree level refines it
      const double err = bruteError(block.field, lod.footprint(), a, b, c);
      const double distance =
          pointTriangleDistance(view.camera, lod.position(a.i, a.j), lod.position(b.i, b.j), lod.position(c.i, c.j));
      const double projected = kConstant * err / std::max(distance, view.nearM);
      ASSERT_LE(projected, view.tolerancePx * (1.0 + 1e-9)) << "triangle " << t;
    }
  }
  EXPECT_GT(refinedSomewhere, 0);
}

INSTANTIATE_TEST_SUITE_P(Blocks, RtinBlockTest,
                         testing::Values(Config{Shape::Random, 4, 1}, Config{Shape::Random, 4, 4},
                                         Config{Shape::Sines, 5, 1}, Config{Shape::Sines, 5, 4},
                                         Config{Shape::Fractal, 5, 1}, Config{Shape::Fractal, 4, 4},
                                         Config{Shape::Fractal, 6, 1}, Config{Shape::Sines, 6, 4}),
                         configName);

TEST(Rtin, FlatBlockIsTwoTriangles) {
  for (int k : {4, 5, 6}) {
    for (int stride : {1, 4}) {
      const Block block = makeBlock(Shape::Flat, k, stride, 1u);
      EXPECT_EQ(block.lod.maxError(), 0.0f);
      EXPECT_EQ(block.lod.floorError(), 0.0f);
      BlockMesh mesh;
      RtinScratch scratch;
      block.lod.extractThreshold(0.0f, mesh, scratch);
      EXPECT_EQ(mesh.triangleCount(), 2u);
      expectConforming(mesh);
      EXPECT_EQ(mesh.edge(BlockEdge::South).size(), 2u);
      block.lod.extractCount(1000, mesh, scratch);
      EXPECT_EQ(mesh.triangleCount(), 2u);  // no split lowers the error
      block.lod.extractView(LodView{glm::dvec3(5.0, 5.0, 20.0), 1000.0, 0.1, 1.0}, mesh, scratch);
      EXPECT_EQ(mesh.triangleCount(), 2u);
      block.lod.extractThreshold(-1.0f, mesh, scratch);
      EXPECT_EQ(mesh.triangleCount(), std::size_t(2) << (2 * k));
    }
  }
}

TEST(Rtin, LargestBlocksStayConforming) {
  const Block block = makeBlock(Shape::Sines, 7, 1, 8u);
  BlockMesh mesh;
  RtinScratch scratch;
  block.lod.extractThreshold(0.05f, mesh, scratch);
  expectConforming(mesh);
  expectHonest(block.field, mesh);
  EXPECT_LE(mesh.maxError, std::max(0.05f, block.lod.floorError()));
  block.lod.extractCount(5000, mesh, scratch);
  expectConforming(mesh);
  EXPECT_LE(mesh.triangleCount(), 5000u);
  EXPECT_GE(mesh.triangleCount(), 4999u);
}

TEST(Rtin, TiltedPlaneIsTwoTriangles) {
  const Block block = makeBlock(Shape::Plane, 5, 2, 1u);
  EXPECT_EQ(block.lod.maxError(), 0.0f);
  BlockMesh mesh;
  RtinScratch scratch;
  block.lod.extractThreshold(0.0f, mesh, scratch);
  EXPECT_EQ(mesh.triangleCount(), 2u);
}

// The triangles of a mesh, each rotated to start at its smallest vertex (winding kept).
std::vector<std::array<int, 6>> triangleSet(const BlockMesh& mesh) {
  std::vector<std::array<int, 6>> out;
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    GridVertex v[3];
    for (int c = 0; c < 3; ++c) v[c] = mesh.vertices[mesh.indices[3 * t + c]];
    int first = 0;
    for (int c = 1; c < 3; ++c) {
      if (std::make_pair(v[c].j, v[c].i) < std::make_pair(v[first].j, v[first].i)) first = c;
    }
    std::array<int, 6> tri;
    for (int c = 0; c < 3; ++c) {
      tri[2 * c] = v[(first + c) % 3].i;
      tri[2 * c + 1] = v[(first + c) % 3].j;
    }
    out.push_back(tri);
  }
  std::sort(out.begin(), out.end());
  return out;
}

// At stride 1 the full-detail mesh is the full-resolution triangulation of heightfield.hpp:
// every cell cut from (x+1, y) to (x, y+1), nothing left over against the surface.
TEST(Rtin, FullDetailAtStrideOneIsTheSurfaceTriangulation) {
  struct Case {
    Shape shape;
    int k;
    int cellsX, cellsY;  // < 2^k: clipped
  };
  for (const Case& cs : {Case{Shape::Random, 3, 8, 8}, Case{Shape::Fractal, 5, 32, 32}, Case{Shape::Sines, 4, 16, 16},
                         Case{Shape::Random, 4, 11, 7}, Case{Shape::Fractal, 5, 19, 26}}) {
    const int x0 = 2, y0 = 3;
    const Heightfield field = makeField(cs.shape, x0 + cs.cellsX + 1, y0 + cs.cellsY + 1, 7u + cs.k);
    auto built = BlockLod::build(field, BlockFootprint{x0, y0, cs.k, 1});
    ASSERT_TRUE(built.ok()) << built.error().message;
    const BlockLod& lod = *built;
    SCOPED_TRACE(std::string(shapeName(cs.shape)) + " k " + std::to_string(cs.k) + ", " + std::to_string(cs.cellsX) +
                 " x " + std::to_string(cs.cellsY) + " cells");
    EXPECT_EQ(lod.floorError(), 0.0f);
    std::vector<std::array<int, 6>> expected;
    for (int y = 0; y < cs.cellsY; ++y) {
      for (int x = 0; x < cs.cellsX; ++x) {
        expected.push_back({x, y, x + 1, y, x, y + 1});
        expected.push_back({x + 1, y, x + 1, y + 1, x, y + 1});  // {(x+1,y+1), (x,y+1), (x+1,y)} rotated
      }
    }
    std::sort(expected.begin(), expected.end());
    BlockMesh mesh;
    RtinScratch scratch;
    auto expectSurface = [&](const std::string& what) {
      SCOPED_TRACE(what);
      expectConforming(mesh);
      expectHonest(field, mesh);
      EXPECT_EQ(expectHalfCellCuts(mesh), 0);
      EXPECT_EQ(triangleSet(mesh), expected);
      EXPECT_EQ(mesh.maxError, 0.0f);
      for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        const GridVertex a = mesh.vertices[mesh.indices[3 * t]], b = mesh.vertices[mesh.indices[3 * t + 1]],
                         c = mesh.vertices[mesh.indices[3 * t + 2]];
        ASSERT_EQ(lod.triangleError(a, b, c), 0.0f) << "triangle " << t;
      }
    };
    lod.extractThreshold(-1.0f, mesh, scratch);
    expectSurface("threshold -1");
    if (cs.shape == Shape::Random) {  // every vertex costs something: these refine fully too
      lod.extractThreshold(0.0f, mesh, scratch);
      expectSurface("threshold 0");
      lod.extractCount(std::size_t(1) << 20, mesh, scratch);
      expectSurface("count");
      lod.extractView(LodView{glm::dvec3(30.0, 30.0, lod.maxHeight() + 5.0), 1000.0, 0.01, 1.0}, mesh, scratch);
      expectSurface("view");
    }
  }
}

// A half cell whose cell's other half is not in the mesh (its hypotenuse is a leg of the coarser
// triangle beside it) keeps the bintree's cut: flipping it would put a vertex on that triangle's
// hypotenuse. Its error, the gap at the cell's centre, is within the threshold anyway.
TEST(Rtin, LoneHalfCellsKeepTheBintreeCut) {
  // One raised sample at (0, 1): vertex (0, 1) costs 2 m, vertex (1, 0) only the gap of cell
  // (0, 0), 1 m; cell (0, 0) is cut south-west to north-east by the bintree.
  Heightfield field(5, 5, 10.0, 10.0);
  field.at(0, 1) = 2.0f;
  auto built = BlockLod::build(field, BlockFootprint{0, 0, 2, 1});
  ASSERT_TRUE(built.ok());
  const BlockLod& lod = *built;
  EXPECT_EQ(lod.vertexError(0, 1), 2.0f);
  EXPECT_EQ(lod.vertexError(1, 0), 1.0f);
  EXPECT_EQ(lod.floorError(), 0.0f);
  BlockMesh mesh;
  RtinScratch scratch;
  lod.extractThreshold(1.5f, mesh, scratch);
  expectConforming(mesh);
  expectHonest(field, mesh);
  EXPECT_EQ(expectHalfCellCuts(mesh), 1);
  const std::vector<std::array<int, 6>> tris = triangleSet(mesh);
  const std::array<int, 6> lone = {0, 0, 1, 1, 0, 1};  // apex (0, 1), the bintree's cut
  EXPECT_TRUE(std::find(tris.begin(), tris.end(), lone) != tris.end());
  EXPECT_EQ(lod.triangleError({0, 1}, {1, 1}, {0, 0}), 1.0f);
  EXPECT_EQ(mesh.maxError, 1.0f);             // the lone half's gap, within the threshold
  lod.extractThreshold(0.5f, mesh, scratch);  // now vertex (1, 0) too: the cell is a diamond
  expectConforming(mesh);
  expectHonest(field, mesh);
  EXPECT_EQ(expectHalfCellCuts(mesh), 0);
  EXPECT_LE(mesh.maxError, 0.5f);
}

// The full-resolution surface at sample coordinates (x, y), from heightfield.hpp's convention
// alone: cell (cx, cy) is cut from (cx+1, cy) to (cx, cy+1) into {(cx,cy), (cx+1,cy), (cx,cy+1)}
// and {(cx+1,cy+1), (cx,cy+1), (cx+1,cy)}, each linear.
double trueSurface(const Heightfield& field, double x, double y) {
  const int cx = std::clamp(int(std::floor(x)), 0, field.width - 2);
  const int cy = std::clamp(int(std::floor(y)), 0, field.height - 2);
  const double fx = x - cx, fy = y - cy;
  const double h00 = field.at(cx, cy), h10 = field.at(cx + 1, cy), h01 = field.at(cx, cy + 1),
               h11 = field.at(cx + 1, cy + 1);
  if (fx + fy <= 1.0) return h00 + fx * (h10 - h00) + fy * (h01 - h00);
  return h11 + (1.0 - fx) * (h01 - h11) + (1.0 - fy) * (h10 - h11);
}

// Largest |plane - trueSurface| over a dense grid inside the closed triangle: 16 x 16 points per
// full-resolution cell of its bounding box (and its far sides), whatever lies in the triangle.
double denseError(const Heightfield& field, const BlockFootprint& fp, GridVertex a, GridVertex b, GridVertex c) {
  constexpr int kSub = 16;
  const P2 pa = fullRes(fp, a.i, a.j), pb = fullRes(fp, b.i, b.j), pc = fullRes(fp, c.i, c.j);
  const P2 qa{kSub * pa.x, kSub * pa.y}, qb{kSub * pb.x, kSub * pb.y}, qc{kSub * pc.x, kSub * pc.y};
  const long long area2 = cross(qa, qb, qc);
  const double za = field.at(int(pa.x), int(pa.y)), zb = field.at(int(pb.x), int(pb.y)),
               zc = field.at(int(pc.x), int(pc.y));
  double err = 0.0;
  for (long long y = std::min({qa.y, qb.y, qc.y}); y <= std::max({qa.y, qb.y, qc.y}); ++y) {
    for (long long x = std::min({qa.x, qb.x, qc.x}); x <= std::max({qa.x, qb.x, qc.x}); ++x) {
      const P2 p{x, y};
      const long long wa = cross(qb, qc, p), wb = cross(qc, qa, p), wc = cross(qa, qb, p);
      if (area2 > 0 ? (wa < 0 || wb < 0 || wc < 0) : (wa > 0 || wb > 0 || wc > 0)) continue;
      const double plane = (wa * za + wb * zb + wc * zc) / double(area2);
      err = std::max(err, std::fabs(plane - trueSurface(field, double(x) / kSub, double(y) / kSub)));
    }
  }
  return err;
}

// Ridges across the cell diagonals: every reported error bounds the distance between the drawn
// triangle and the full-resolution triangulated surface at every point under it, not only at
// the samples (bintree edges running south-west to north-east cross each cell's diagonal at
// its centre, where the surface is the mean of the diagonal's ends).
TEST(Rtin, ReportedErrorsBoundTheTriangulatedSurfaceEverywhere) {
  enum class Ground { Random, Checkerboard, Sines };
  struct Case {
    Ground ground;
    int k, stride;
    bool clipped;
  };
  const Case cases[] = {{Ground::Random, 4, 1, false},       {Ground::Random, 3, 4, false},
                        {Ground::Checkerboard, 4, 1, false}, {Ground::Checkerboard, 3, 2, false},
                        {Ground::Sines, 5, 1, false},        {Ground::Random, 4, 2, true},
                        {Ground::Checkerboard, 4, 1, true}};
  std::mt19937 rng(2024u);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int failures = 0;
  for (const Case& cs : cases) {
    const int n = 1 << cs.k;
    const int x0 = 2, y0 = 1;
    // A clipped block keeps 11 x 6 of its cells (and a remainder narrower than the stride).
    const int w = x0 + (cs.clipped ? 11 : n) * cs.stride + 1 + (cs.clipped ? cs.stride - 1 : 2);
    const int h = y0 + (cs.clipped ? 6 : n) * cs.stride + 1 + (cs.clipped ? 0 : 3);
    Heightfield field(w, h, 5.0, 5.0);
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        float z = 0.0f;
        switch (cs.ground) {
          case Ground::Random:
            z = float(100.0 * unit(rng));
            break;
          // In every cell one diagonal's ends are high and the other's low: a ridge or valley
          // along each full-resolution diagonal, on a tilt.
          case Ground::Checkerboard:
            z = ((x + y) & 1 ? 30.0f : 0.0f) + 0.7f * float(x) - 0.4f * float(y);
            break;
          case Ground::Sines:
            z = 20.0f * std::sin(0.9f * float(x) - 0.6f * float(y)) + 8.0f * std::cos(0.2f * float(y));
            break;
        }
        field.at(x, y) = z;
      }
    }
    auto built = BlockLod::build(field, BlockFootprint{x0, y0, cs.k, cs.stride});
    ASSERT_TRUE(built.ok()) << built.error().message;
    const BlockLod& lod = *built;
    ASSERT_EQ(lod.clipped(), cs.clipped);
    BlockMesh mesh;
    RtinScratch scratch;
    auto check = [&](const std::string& what) {
      SCOPED_TRACE("ground " + std::to_string(int(cs.ground)) + ", k " + std::to_string(cs.k) + ", stride " +
                   std::to_string(cs.stride) + (cs.clipped ? ", clipped" : "") + ", " + what + ", " +
                   std::to_string(mesh.triangleCount()) + " triangles");
      expectConforming(mesh);
      expectHalfCellCuts(mesh);
      for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        const GridVertex a = mesh.vertices[mesh.indices[3 * t]], b = mesh.vertices[mesh.indices[3 * t + 1]],
                         c = mesh.vertices[mesh.indices[3 * t + 2]];
        const double dense = denseError(field, lod.footprint(), a, b, c);
        const double reported = lod.triangleError(a, b, c), slack = 1e-9 * (1.0 + dense);
        if (dense > reported + slack || dense > double(mesh.maxError) + slack) {
          if (++failures <= 10) {
            ADD_FAILURE() << "triangle (" << a.i << "," << a.j << ") (" << b.i << "," << b.j << ") (" << c.i << ","
                          << c.j << "): surface " << dense << " m off, reported " << reported << " (mesh "
                          << mesh.maxError << ")";
          }
        }
      }
    };
    for (float fraction : {2.0f, 0.6f, 0.3f, 0.1f, 0.02f, 0.0f, -1.0f}) {
      lod.extractThreshold(fraction < 0.0f ? -1.0f : lod.maxError() * fraction * float(0.5 + unit(rng)), mesh, scratch);
      check("threshold fraction " + std::to_string(fraction));
    }
    for (int trial = 0; trial < 6; ++trial) {
      lod.extractCount(std::size_t(2 + unit(rng) * 2.0 * n * n), mesh, scratch);
      check("count trial " + std::to_string(trial));
      const double extent = n * cs.stride * field.spacingX;
      LodView view{glm::dvec3(unit(rng) * extent, unit(rng) * extent, lod.maxHeight() + 5.0 + unit(rng) * 200.0), 600.0,
                   0.5 + 4.0 * unit(rng), 1.0};
      lod.extractView(view, mesh, scratch);
      check("view trial " + std::to_string(trial));
    }
  }
  EXPECT_EQ(failures, 0) << "triangles whose reported error misses the triangulated surface";
}

TEST(Rtin, AnisotropicSpacingKeepsRadiiNested) {
  Heightfield field = makeField(Shape::Fractal, 70, 70, 5u, 30.0, 7.5);
  auto built = BlockLod::build(field, BlockFootprint{1, 4, 5, 2});
  ASSERT_TRUE(built.ok());
  expectHierarchy(field, *built);
}

// A block that runs past the field's east and north edges keeps its valid rectangle.
class RtinClippedTest : public testing::TestWithParam<int> {};

TEST_P(RtinClippedTest, ClippedBlockTilesItsValidRectangle) {
  const int stride = GetParam();
  const int k = 5;
  // 11 + 2/stride cells east, 19 north, plus a remainder narrower than the stride.
  const int x0 = 8, y0 = 3;
  Heightfield field = makeField(Shape::Fractal, x0 + 11 * stride + 1 + (stride - 1), y0 + 19 * stride + 1, 77u);
  auto built = BlockLod::build(field, BlockFootprint{x0, y0, k, stride});
  ASSERT_TRUE(built.ok()) << built.error().message;
  const BlockLod& lod = *built;
  EXPECT_TRUE(lod.clipped());
  EXPECT_EQ(lod.cellsX(), 11);
  EXPECT_EQ(lod.cellsY(), 19);
  expectHierarchy(field, lod);
  EXPECT_TRUE(std::isinf(lod.vertexError(16, 16)));  // the root split straddles the border

  BlockMesh mesh;
  RtinScratch scratch;
  lod.extractThreshold(FLT_MAX, mesh, scratch);  // only the forced splits
  expectConforming(mesh);
  expectHonest(field, mesh);
  EXPECT_EQ(mesh.maxError, lod.maxError());
  const std::size_t coarsest = mesh.triangleCount();
  for (float threshold : {10.0f, 1.0f, 0.1f, 0.0f, -1.0f}) {
    lod.extractThreshold(threshold, mesh, scratch);
    SCOPED_TRACE("threshold " + std::to_string(threshold));
    expectConforming(mesh);
    expectHonest(field, mesh);
    EXPECT_LE(mesh.maxError, std::max(std::max(threshold, 0.0f), lod.floorError()));
  }
  EXPECT_EQ(mesh.triangleCount(), 2u * 11u * 19u);
  for (std::size_t target : {std::size_t(0), coarsest + 1, std::size_t(100), std::size_t(300), std::size_t(1000)}) {
    lod.extractCount(target, mesh, scratch);
    SCOPED_TRACE("target " + std::to_string(target));
    expectConforming(mesh);
    expectHonest(field, mesh);
    const std::size_t expected = std::max(coarsest, std::min<std::size_t>(target, 2u * 11u * 19u));
    EXPECT_LE(mesh.triangleCount(), expected);
    EXPECT_GE(mesh.triangleCount() + 1, expected);
  }
  LodView view{glm::dvec3(40.0, 60.0, lod.maxHeight() + 20.0), 600.0, 1.0, 1.0};
  lod.extractView(view, mesh, scratch);
  expectConforming(mesh);
  expectHonest(field, mesh);
}

INSTANTIATE_TEST_SUITE_P(Strides, RtinClippedTest, testing::Values(1, 4));

// ---- boundary pins (BlockLod::extractView with BoundaryPins) -------------------------------

// The bintree's vertex dependencies, from a walk written here: for every triangle whose
// hypotenuse has a grid midpoint, midpoint -> apex. A vertex is in a conforming mesh only with
// the apexes of the triangles it splits (their parents are split), recursively.
std::map<std::pair<int, int>, std::vector<std::pair<int, int>>> dependencyApexes(int n) {
  std::map<std::pair<int, int>, std::vector<std::pair<int, int>>> apexes;
  std::vector<std::array<int, 6>> pending = {{0, 0, n, 0, 0, n}, {n, n, 0, n, n, 0}};
  while (!pending.empty()) {
    const std::array<int, 6> t = pending.back();
    pending.pop_back();
    if (std::abs(t[2] - t[4]) == 1) continue;  // a half cell: its hypotenuse has no grid midpoint
    const int mi = (t[2] + t[4]) / 2, mj = (t[3] + t[5]) / 2;
    apexes[{mi, mj}].push_back({t[0], t[1]});
    pending.push_back({mi, mj, t[0], t[1], t[2], t[3]});
    pending.push_back({mi, mj, t[4], t[5], t[0], t[1]});
  }
  return apexes;
}

using VertexSet = std::set<std::pair<int, int>>;

VertexSet vertexSet(const BlockMesh& mesh) {
  VertexSet out;
  for (const GridVertex& v : mesh.vertices) out.insert({v.i, v.j});
  return out;
}

// Side position -> block-local vertex, for a mesh of cellsX x cellsY cells.
std::pair<int, int> sideVertex(BlockEdge side, int position, int cellsX, int cellsY) {
  switch (side) {
    case BlockEdge::South:
      return {position, 0};
    case BlockEdge::East:
      return {cellsX, position};
    case BlockEdge::North:
      return {position, cellsY};
    case BlockEdge::West:
      return {0, position};
  }
  return {-1, -1};
}

bool sameMeshExactly(const BlockMesh& a, const BlockMesh& b) {
  if (a.vertices.size() != b.vertices.size() || a.indices != b.indices || a.edges != b.edges) return false;
  if (a.maxError != b.maxError || a.cellsX != b.cellsX || a.cellsY != b.cellsY) return false;
  for (std::size_t v = 0; v < a.vertices.size(); ++v)
    if (a.vertices[v].i != b.vertices[v].i || a.vertices[v].j != b.vertices[v].j) return false;
  return true;
}

// Random pins: a few ranges per side, some single positions, some past the side's end (and, for
// a clipped block, past its valid rectangle: ignored).
BoundaryPins randomPins(std::mt19937& rng, int n) {
  std::uniform_int_distribution<int> position(0, n), ranges(0, 3), length(0, 5), coin(0, 9);
  BoundaryPins pins;
  for (int side = 0; side < 4; ++side) {
    const int count = ranges(rng);
    for (int r = 0; r < count; ++r) {
      const int from = position(rng);
      const int to = coin(rng) == 0 ? from + 3 * n : from + length(rng);  // sometimes past the end
      pins.pin(BlockEdge(side), from, to);
    }
  }
  return pins;
}

struct PinCase {
  Shape shape;
  int k, stride;
  int cellsX, cellsY;  // < 2^k: a clipped block
};

// For random views and random pins: every pinned position (inside the valid rectangle) is a
// vertex of its side, the mesh is conforming and honest, its vertex set is the unpinned mesh's
// plus exactly the pins and what they depend on (computed here), the view's bound still holds,
// and empty pins give exactly the unpinned mesh.
TEST(Rtin, PinnedSideVerticesAreKeptAndTheMeshStaysConforming) {
  const PinCase cases[] = {{Shape::Random, 4, 1, 16, 16},  {Shape::Fractal, 5, 1, 32, 32}, {Shape::Sines, 5, 4, 32, 32},
                           {Shape::Fractal, 6, 2, 64, 64}, {Shape::Fractal, 5, 1, 11, 19}, {Shape::Sines, 5, 4, 11, 19},
                           {Shape::Random, 3, 2, 8, 8}};
  std::mt19937 rng(4242u);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double kConstant = 720.0 / (2.0 * std::tan(glm::radians(30.0)));
  int pinsAddedVertices = 0, pinsIgnored = 0;
  for (const PinCase& cs : cases) {
    const int n = 1 << cs.k;
    const bool clipped = cs.cellsX < n || cs.cellsY < n;
    const int x0 = 3, y0 = 2;
    // A clipped block also gets a remainder narrower than the stride.
    const int w = x0 + cs.cellsX * cs.stride + 1 + (clipped ? cs.stride - 1 : 4);
    const int h = y0 + cs.cellsY * cs.stride + 1 + (clipped ? 0 : 3);
    const Heightfield field = makeField(cs.shape, w, h, 5u + unsigned(cs.k) * 3u + unsigned(cs.stride));
    auto built = BlockLod::build(field, BlockFootprint{x0, y0, cs.k, cs.stride});
    ASSERT_TRUE(built.ok()) << built.error().message;
    const BlockLod& lod = *built;
    ASSERT_EQ(lod.clipped(), clipped);
    ASSERT_EQ(lod.cellsX(), cs.cellsX);
    ASSERT_EQ(lod.cellsY(), cs.cellsY);
    const auto apexes = dependencyApexes(n);
    const double extentX = n * cs.stride * field.spacingX, extentY = n * cs.stride * field.spacingY;
    BlockMesh plain, pinned, again;
    RtinScratch scratch;  // shared by every extraction: the marks must not leak from one to the next
    for (int trial = 0; trial < 16; ++trial) {
      LodView view;
      view.camera = {(unit(rng) * 2.0 - 0.5) * extentX, (unit(rng) * 2.0 - 0.5) * extentY,
                     lod.maxHeight() + 2.0 + unit(rng) * (trial < 8 ? 60.0 : 1500.0)};
      view.projectionConstant = kConstant;
      view.tolerancePx = trial % 3 == 0 ? 0.5 : (trial % 3 == 1 ? 2.0 : 8.0);
      view.nearM = 1.0;
      BoundaryPins pins = randomPins(rng, n);
      if (trial == 0) pins.clear();
      if (trial == 1) {  // every position of every side
        for (int side = 0; side < 4; ++side) pins.pin(BlockEdge(side), 0, n);
      }
      SCOPED_TRACE(std::string(shapeName(cs.shape)) + " k " + std::to_string(cs.k) + " stride " +
                   std::to_string(cs.stride) + " " + std::to_string(cs.cellsX) + "x" + std::to_string(cs.cellsY) +
                   " trial " + std::to_string(trial));

      lod.extractView(view, plain, scratch);
      lod.extractView(view, pinned, scratch, &pins);
      expectConforming(pinned);
      if (HasFatalFailure()) return;
      expectHonest(field, pinned);
      expectHalfCellCuts(pinned);

      // Every pin inside the valid rectangle is a vertex of its side's list.
      for (int side = 0; side < 4; ++side) {
        const BlockEdge which = BlockEdge(side);
        const int length = (which == BlockEdge::South || which == BlockEdge::North) ? cs.cellsX : cs.cellsY;
        std::set<int> onSide;
        for (std::uint32_t v : pinned.edge(which)) {
          const GridVertex g = pinned.vertices[v];
          onSide.insert((which == BlockEdge::South || which == BlockEdge::North) ? g.i : g.j);
        }
        for (int p = 0; p <= n; ++p) {
          if (!pins.pinned(which, p)) continue;
          if (p > length) {
            ++pinsIgnored;
            continue;
          }
          EXPECT_EQ(onSide.count(p), 1u) << "side " << side << " lost pinned position " << p;
        }
      }

      // The vertex set: the unpinned mesh's plus the pins' dependency closure (independent walk).
      const VertexSet plainSet = vertexSet(plain), pinnedSet = vertexSet(pinned);
      EXPECT_TRUE(std::includes(pinnedSet.begin(), pinnedSet.end(), plainSet.begin(), plainSet.end()))
          << "pinning dropped a vertex of the view's mesh";
      VertexSet closure;
      std::vector<std::pair<int, int>> stack;
      for (int side = 0; side < 4; ++side) {
        const BlockEdge which = BlockEdge(side);
        const int length = (which == BlockEdge::South || which == BlockEdge::North) ? cs.cellsX : cs.cellsY;
        for (int p = 0; p <= length; ++p) {
          if (pins.pinned(which, p)) stack.push_back(sideVertex(which, p, cs.cellsX, cs.cellsY));
        }
      }
      while (!stack.empty()) {
        const std::pair<int, int> v = stack.back();
        stack.pop_back();
        if (!closure.insert(v).second) continue;
        const auto it = apexes.find(v);
        if (it != apexes.end())
          for (const auto& a : it->second) stack.push_back(a);
      }
      VertexSet expected = plainSet;
      for (const auto& v : closure)
        if (v.first <= cs.cellsX && v.second <= cs.cellsY) expected.insert(v);
      if (!clipped) {
        EXPECT_EQ(pinnedSet, expected) << "the pinned mesh is not the view's mesh plus the pins' closure";
      } else {
        // Outside the valid rectangle the closure may reach further; what lies inside is kept,
        // and nothing beyond the closure is added.
        EXPECT_TRUE(std::includes(pinnedSet.begin(), pinnedSet.end(), expected.begin(), expected.end()));
        for (const auto& v : pinnedSet) {
          EXPECT_TRUE(plainSet.count(v) != 0 || closure.count(v) != 0)
              << "vertex " << v.first << "," << v.second << " added beyond the pins' closure";
        }
      }
      pinsAddedVertices += pinnedSet.size() > plainSet.size();
      if (trial == 1) {  // every side complete
        for (int side = 0; side < 4; ++side) {
          const BlockEdge which = BlockEdge(side);
          const int length = (which == BlockEdge::South || which == BlockEdge::North) ? cs.cellsX : cs.cellsY;
          EXPECT_EQ(pinned.edge(which).size(), std::size_t(length) + 1) << "side " << side;
        }
      }

      // A refinement of the view's mesh: the view's bound still holds (half cells aside).
      for (std::size_t t = 0; t < pinned.triangleCount(); ++t) {
        const GridVertex a = pinned.vertices[pinned.indices[3 * t]], b = pinned.vertices[pinned.indices[3 * t + 1]],
                         c = pinned.vertices[pinned.indices[3 * t + 2]];
        if (std::abs(b.i - c.i) == 1) continue;
        const double err = bruteError(field, lod.footprint(), a, b, c);
        const double distance =
            pointTriangleDistance(view.camera, lod.position(a.i, a.j), lod.position(b.i, b.j), lod.position(c.i, c.j));
        ASSERT_LE(kConstant * err / std::max(distance, view.nearM), view.tolerancePx * (1.0 + 1e-9))
            << "triangle " << t;
      }

      // Empty pins, or pins already in the mesh, change nothing; nor does the order of calls.
      const BoundaryPins none;
      lod.extractView(view, again, scratch, &none);
      EXPECT_TRUE(sameMeshExactly(again, plain)) << "empty pins changed the mesh";
      BoundaryPins present;
      for (int side = 0; side < 4; ++side) {
        for (std::uint32_t v : plain.edge(BlockEdge(side))) {
          const GridVertex g = plain.vertices[v];
          const BlockEdge which = BlockEdge(side);
          const int p = (which == BlockEdge::South || which == BlockEdge::North) ? g.i : g.j;
          present.pin(which, p, p);
        }
      }
      lod.extractView(view, again, scratch, &present);
      EXPECT_TRUE(sameMeshExactly(again, plain)) << "pinning the mesh's own side vertices changed it";
      lod.extractView(view, again, scratch, &pins);
      EXPECT_TRUE(sameMeshExactly(again, pinned)) << "the same pins gave another mesh";
      lod.extractView(view, again, scratch);
      EXPECT_TRUE(sameMeshExactly(again, plain)) << "a pinned extraction left marks in the scratch";
    }
  }
  EXPECT_GT(pinsAddedVertices, 40);  // the pins mattered in most trials
  EXPECT_GT(pinsIgnored, 0);         // and some fell outside a side
}

// Pins at the coarsest view: a single pinned position in the middle of the south side pulls in
// exactly its chain of apexes, and the mesh stays conforming.
// Threshold extraction with pins (what the uniform-error mesh uses): the threshold's mesh
// plus the pins and what they depend on, still conforming and within the threshold.
TEST(Rtin, PinnedThresholdExtractionRefinesTheThresholdMesh) {
  std::mt19937 rng(777u);
  for (const PinCase& cs : {PinCase{Shape::Fractal, 5, 1, 32, 32}, PinCase{Shape::Sines, 4, 2, 16, 16},
                            PinCase{Shape::Random, 5, 1, 13, 21}}) {
    const int n = 1 << cs.k;
    const Heightfield field =
        makeField(cs.shape, cs.cellsX * cs.stride + 1, cs.cellsY * cs.stride + 1, 99u + unsigned(cs.k));
    auto built = BlockLod::build(field, BlockFootprint{0, 0, cs.k, cs.stride});
    ASSERT_TRUE(built.ok()) << built.error().message;
    BlockMesh plain, pinned;
    RtinScratch scratch;
    for (int trial = 0; trial < 8; ++trial) {
      const float threshold = built->maxError() * float(trial + 1) / 10.0f;
      const BoundaryPins pins = randomPins(rng, n);
      built->extractThreshold(threshold, plain, scratch);
      built->extractThreshold(threshold, pinned, scratch, &pins);
      expectConforming(pinned);
      if (HasFatalFailure()) return;
      expectHonest(field, pinned);
      EXPECT_LE(pinned.maxError, std::max(threshold, built->floorError()));
      const VertexSet plainSet = vertexSet(plain), pinnedSet = vertexSet(pinned);
      EXPECT_TRUE(std::includes(pinnedSet.begin(), pinnedSet.end(), plainSet.begin(), plainSet.end()));
      for (int side = 0; side < 4; ++side) {
        const BlockEdge which = BlockEdge(side);
        const int length = (which == BlockEdge::South || which == BlockEdge::North) ? cs.cellsX : cs.cellsY;
        for (int p = 0; p <= length; ++p)
          if (pins.pinned(which, p)) {
            EXPECT_EQ(pinnedSet.count(sideVertex(which, p, cs.cellsX, cs.cellsY)), 1u) << side << " " << p;
          }
      }
      built->extractThreshold(threshold, plain, scratch, nullptr);  // the marks do not leak into the next one
      EXPECT_EQ(vertexSet(plain), plainSet);
    }
  }
}

TEST(Rtin, OnePinRefinesOnlyItsDependencyChain) {
  const Block block = makeBlock(Shape::Fractal, 5, 1, 61u);
  const BlockLod& lod = block.lod;
  const LodView far{glm::dvec3(160.0, 160.0, 1.0e7), 600.0, 1.0, 1.0};  // nothing active
  BlockMesh mesh;
  RtinScratch scratch;
  lod.extractView(far, mesh, scratch);
  ASSERT_EQ(mesh.triangleCount(), 2u);
  BoundaryPins pins;
  EXPECT_TRUE(pins.pin(BlockEdge::South, 5, 5));
  EXPECT_FALSE(pins.pin(BlockEdge::South, 5, 5));  // already pinned
  lod.extractView(far, mesh, scratch, &pins);
  expectConforming(mesh);
  expectHalfCellCuts(mesh);
  VertexSet expected = {{0, 0}, {32, 0}, {0, 32}, {32, 32}};
  const auto apexes = dependencyApexes(32);
  std::vector<std::pair<int, int>> stack = {{5, 0}};
  while (!stack.empty()) {
    const auto v = stack.back();
    stack.pop_back();
    if (!expected.insert(v).second) continue;
    const auto it = apexes.find(v);
    if (it != apexes.end())
      for (const auto& a : it->second) stack.push_back(a);
  }
  EXPECT_EQ(vertexSet(mesh), expected);
  // (5, 0) depends on (4, 1)... up to the root centre (16, 16): more than the corners.
  EXPECT_GT(expected.size(), 8u);
  std::vector<int> south;
  for (std::uint32_t v : mesh.edge(BlockEdge::South)) south.push_back(mesh.vertices[v].i);
  EXPECT_TRUE(std::find(south.begin(), south.end(), 5) != south.end());
}

TEST(Rtin, SteadyStateExtractionDoesNotAllocate) {
  const Block block = makeBlock(Shape::Fractal, 5, 1, 3u);
  BlockMesh mesh;
  RtinScratch scratch;
  mesh.reserve(5);
  scratch.reserve(5);
  const GridVertex* vertices = mesh.vertices.data();
  const std::uint32_t* indices = mesh.indices.data();
  const std::uint32_t* south = mesh.edge(BlockEdge::South).data();
  block.lod.extractThreshold(-1.0f, mesh, scratch);
  block.lod.extractCount(500, mesh, scratch);
  block.lod.extractView(LodView{glm::dvec3(100.0, 50.0, 300.0), 600.0, 1.0, 1.0}, mesh, scratch);
  block.lod.extractThreshold(0.0f, mesh, scratch);
  EXPECT_EQ(mesh.vertices.data(), vertices);
  EXPECT_EQ(mesh.indices.data(), indices);
  EXPECT_EQ(mesh.edge(BlockEdge::South).data(), south);
}

TEST(Rtin, RebuildReusesTheObject) {
  const Heightfield a = makeField(Shape::Sines, 40, 40, 1u), b = makeField(Shape::Random, 40, 40, 2u);
  BlockLod lod;
  ASSERT_TRUE(lod.rebuild(a, BlockFootprint{0, 0, 5, 1}).ok());
  const float before = lod.maxError();
  ASSERT_TRUE(lod.rebuild(b, BlockFootprint{2, 3, 5, 1}).ok());
  EXPECT_NE(lod.maxError(), before);
  expectHierarchy(b, lod);
}

TEST(Rtin, BadBlocksReturnErrors) {
  Heightfield field = makeField(Shape::Sines, 20, 20, 1u);
  auto outside = BlockLod::build(field, BlockFootprint{19, 0, 4, 1});
  ASSERT_FALSE(outside.ok());
  EXPECT_EQ(outside.error().kind, ErrorKind::InvalidArgument);
  auto tooCoarse = BlockLod::build(field, BlockFootprint{0, 0, 4, 32});  // no whole cell
  ASSERT_FALSE(tooCoarse.ok());
  field.at(3, 4) = std::nanf("");
  auto noData = BlockLod::build(field, BlockFootprint{0, 0, 4, 1});
  ASSERT_FALSE(noData.ok());
  EXPECT_EQ(noData.error().kind, ErrorKind::InvalidData);
}

}  // namespace
}  // namespace polder::terrain
