// The LOD cache's block-level reuse test: summary and test (lod_reuse.hpp has the argument).
//
// Follows Chuang, "Level-of-Detail Modeling Technique for Virtual Reality (I)", 2001, part B: the cached LOD of a block
// is reused while "its projected error with respect to the new viewpoint is within a
// pre-specified error"; the test is "block-based, rather than vertex-based".
#include <polder/cache/lod_reuse.hpp>

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <cstdlib>
#include <limits>

namespace polder::cache {
namespace {

using terrain::BlockLod;
using terrain::BlockMesh;
using terrain::GridVertex;
using terrain::LodView;

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// A margin below zero by this relative amount or less is rounding in re-deriving the
// extraction's own comparison (e K > tau max(d - r, near)); see lod_reuse.hpp.
constexpr double kMarginRounding = 1e-9;

int edgeLength2(GridVertex p, GridVertex q) {
  const int di = int(p.i) - int(q.i), dj = int(p.j) - int(q.j);
  return di * di + dj * dj;
}

// Distance from p to sub-region (rx, ry)'s box B(S). The summary and the test compute the
// rectangle with the same arithmetic as BlockLod::position (i * spacing), so both see one box.
double regionDistance(const LodSummary& s, const LodRegion& region, int rx, int ry, const glm::dvec3& p) {
  const int i0 = rx * s.regionCells, i1 = std::min(i0 + s.regionCells, s.cellsX);
  const int j0 = ry * s.regionCells, j1 = std::min(j0 + s.regionCells, s.cellsY);
  const double dx = std::max({i0 * s.spacingX - p.x, 0.0, p.x - i1 * s.spacingX});
  const double dy = std::max({j0 * s.spacingY - p.y, 0.0, p.y - j1 * s.spacingY});
  const double dz = std::max({region.minZ - p.z, 0.0, p.z - region.maxZ});
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

// The allowed error per unit distance: a(S) = this * max(distance, near).
double allowedPerMetre(const LodView& view) { return view.tolerancePx / view.projectionConstant; }

// An upper bound on how much closer the camera got, moving from c0 to c1, to any point q of
// sub-region (rx, ry)'s box: sup over q of f(q) = |q - c0| - |q - c1| (see lod_reuse.hpp).
// With w = c1 - c0, f(q) = (2 (q - c0).w - |w|^2) / (|q - c0| + |q - c1|): the numerator is
// linear in q, so its largest value over the box is at a corner chosen axis by axis; the
// denominator is at least dist(c0, box) + dist(c1, box). And f <= |w| always.
double approachBound(const LodSummary& s, const LodRegion& region, int rx, int ry, const glm::dvec3& c1,
                     double distanceNow) {
  const glm::dvec3& c0 = s.view.camera;
  const glm::dvec3 w = c1 - c0;
  const double moved = glm::length(w);
  const int i0 = rx * s.regionCells, i1 = std::min(i0 + s.regionCells, s.cellsX);
  const int j0 = ry * s.regionCells, j1 = std::min(j0 + s.regionCells, s.cellsY);
  const double lo[3] = {i0 * s.spacingX - c0.x, j0 * s.spacingY - c0.y, region.minZ - c0.z};
  const double hi[3] = {i1 * s.spacingX - c0.x, j1 * s.spacingY - c0.y, region.maxZ - c0.z};
  double numerator = -moved * moved, magnitude = moved * moved;
  for (int a = 0; a < 3; ++a) {
    const double term = 2.0 * std::max(lo[a] * w[a], hi[a] * w[a]);
    numerator += term;
    magnitude += std::fabs(term);
  }
  // An allowance for rounding in the sum, always towards a larger bound.
  numerator += 1e-12 * magnitude;
  if (numerator <= 0.0) return 0.0;  // no point of the box got closer
  const double denominator = region.buildDistanceM + distanceNow;
  if (!(denominator > 0.0)) return moved;
  return std::min(moved, numerator / denominator * (1.0 + 1e-12));
}

double densityRatio(double ratio, double exponent) {
  if (exponent == 1.0) return ratio;
  if (exponent == 2.0) return ratio * ratio;
  return std::pow(ratio, exponent);
}

}  // namespace

void summarizeLod(const BlockLod& lod, const LodView& view, const BlockMesh& mesh, LodSummary& out) {
  assert(view.projectionConstant > 0.0 && "summarizeLod: projectionConstant must be positive");
  const int cells = lod.footprint().cells();
  const int perSide = std::min(kLodRegionsPerSide, cells);  // k = 1 blocks have 2 cells per side
  const int width = cells / perSide;                        // cells per sub-region side
  const int shift = std::countr_zero(unsigned(width));      // a power of two: shifts, not divisions
  const int cellsX = lod.cellsX(), cellsY = lod.cellsY();

  out.view = view;
  out.spacingX = lod.position(1, 0).x;  // = 1 * spacing exactly
  out.spacingY = lod.position(0, 1).y;
  out.regionCells = width;
  out.cellsX = cellsX;
  out.cellsY = cellsY;
  out.regionsX = (cellsX + width - 1) / width;
  out.regionsY = (cellsY + width - 1) / width;
  out.triangles = std::uint32_t(mesh.triangleCount());
  for (LodRegion& region : out.regions) {
    region = LodRegion{};
    region.marginM = kInfinity;
  }

  // Per triangle: E(S) and M(S) over the sub-regions its rectangle overlaps, n(S) at its centroid.
  const double k = view.projectionConstant, tau = view.tolerancePx;
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    const GridVertex v[3] = {mesh.vertices[mesh.indices[3 * t]], mesh.vertices[mesh.indices[3 * t + 1]],
                             mesh.vertices[mesh.indices[3 * t + 2]]};
    const int iMin = std::min({v[0].i, v[1].i, v[2].i}), iMax = std::max({v[0].i, v[1].i, v[2].i});
    const int jMin = std::min({v[0].j, v[1].j, v[2].j}), jMax = std::max({v[0].j, v[1].j, v[2].j});
    const int centreX = std::min(((v[0].i + v[1].i + v[2].i) / 3) >> shift, out.regionsX - 1);
    const int centreY = std::min(((v[0].j + v[1].j + v[2].j) / 3) >> shift, out.regionsY - 1);
    ++out.regions[std::size_t(centreY * kLodRegionsPerSide + centreX)].triangles;

    // The apex is opposite the hypotenuse, the longest edge in grid units (the bintree's
    // triangles are right isosceles there); the mesh's index order is not part of its contract.
    const int l0 = edgeLength2(v[1], v[2]), l1 = edgeLength2(v[2], v[0]), l2 = edgeLength2(v[0], v[1]);
    const int apex = (l0 >= l1 && l0 >= l2) ? 0 : (l1 >= l2 ? 1 : 2);
    const GridVertex b = v[(apex + 1) % 3], c = v[(apex + 2) % 3];
    if (std::abs(int(b.i) - int(c.i)) == 1) continue;  // a half cell: drawn by every extraction
    const float error = lod.triangleError(v[apex], b, c);

    double margin = kInfinity;
    if (double(error) * k > tau * view.nearM) {
      const int mi = (b.i + c.i) / 2, mj = (b.j + c.j) / 2;
      // L(T): the larger of two lower bounds on dist(c0, T), the extraction's sphere (which
      // makes the margin non-negative) and T's bounding box (tighter near the camera).
      const double sphere = glm::length(lod.position(mi, mj) - view.camera) - double(lod.vertexRadius(mi, mj));
      const glm::dvec3 p0 = lod.position(v[0].i, v[0].j), p1 = lod.position(v[1].i, v[1].j),
                       p2 = lod.position(v[2].i, v[2].j);
      const glm::dvec3 gap =
          glm::max(glm::max(glm::min(glm::min(p0, p1), p2) - view.camera, view.camera - glm::max(glm::max(p0, p1), p2)),
                   glm::dvec3(0.0));
      const double reach = std::max(sphere, glm::length(gap));
      margin = reach - double(error) * k / tau;
      if (margin < 0.0 && margin >= -kMarginRounding * std::max(1.0, std::fabs(reach))) margin = 0.0;
    }
    for (int ry = jMin >> shift; ry <= (jMax - 1) >> shift; ++ry) {
      for (int rx = iMin >> shift; rx <= (iMax - 1) >> shift; ++rx) {
        LodRegion& region = out.regions[std::size_t(ry * kLodRegionsPerSide + rx)];
        region.errorM = std::max(region.errorM, error);
        region.marginM = std::min(region.marginM, margin);
      }
    }
  }

  // Boxes from the vertex heights (the corners of every T ∩ S are grid vertices), then the
  // build distances.
  for (int ry = 0; ry < out.regionsY; ++ry) {
    for (int rx = 0; rx < out.regionsX; ++rx) {
      LodRegion& region = out.regions[std::size_t(ry * kLodRegionsPerSide + rx)];
      const int i0 = rx * width, i1 = std::min(i0 + width, cellsX);
      const int j0 = ry * width, j1 = std::min(j0 + width, cellsY);
      float lo = lod.height(i0, j0), hi = lo;
      for (int j = j0; j <= j1; ++j) {
        for (int i = i0; i <= i1; ++i) {
          const float h = lod.height(i, j);
          lo = std::min(lo, h);
          hi = std::max(hi, h);
        }
      }
      region.minZ = double(lo) - double(region.errorM);
      region.maxZ = double(hi) + double(region.errorM);
      region.buildDistanceM = regionDistance(out, region, rx, ry, view.camera);
    }
  }
}

LodVerdict testLodReuse(const LodSummary& summary, const LodView& view, const LodReuseOptions& options) {
  assert(view.projectionConstant > 0.0 && "testLodReuse: projectionConstant must be positive");
  assert(options.fineFactor > 1.0 && "testLodReuse: fineFactor must exceed 1");
  const bool sameView = view.projectionConstant == summary.view.projectionConstant &&
                        view.tolerancePx == summary.view.tolerancePx && view.nearM == summary.view.nearM;
  const double k = view.projectionConstant, tau = view.tolerancePx;
  const double allowedNow = allowedPerMetre(view), allowedThen = allowedPerMetre(summary.view);

  double estimate = 0.0;  // N': triangles a fresh mesh would draw, by the density model
  bool estimateValid = true;
  for (int ry = 0; ry < summary.regionsY; ++ry) {
    for (int rx = 0; rx < summary.regionsX; ++rx) {
      const LodRegion& region = summary.regions[std::size_t(ry * kLodRegionsPerSide + rx)];
      const double boxDistance = regionDistance(summary, region, rx, ry, view.camera);
      const double distance = std::max(boxDistance, view.nearM);
      const bool boxPasses = k * double(region.errorM) <= tau * distance;  // test (a)
      if (!boxPasses) {                                                    // test (b)
        if (!sameView || !(approachBound(summary, region, rx, ry, view.camera, boxDistance) <= region.marginM))
          return LodVerdict::TooCoarse;
      }
      if (region.triangles == 0) continue;
      const double now = allowedNow * distance;
      const double then = allowedThen * std::max(region.buildDistanceM, summary.view.nearM);
      if (!(now > 0.0)) {
        estimateValid = false;  // the view allows no error: nothing is needlessly fine
        continue;
      }
      estimate += double(region.triangles) * densityRatio(then / now, options.densityExponent);
    }
  }
  // The coarsest mesh (two triangles) cannot get coarser: rebuilding it would only repeat it.
  if (estimateValid && summary.triangles > 2 && double(summary.triangles) > options.fineFactor * estimate)
    return LodVerdict::NeedlesslyFine;
  return LodVerdict::Reuse;
}

}  // namespace polder::cache
