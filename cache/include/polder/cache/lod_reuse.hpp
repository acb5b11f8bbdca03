// The block-level reuse test of the LOD cache (docs/design.md "One frame", step 2).
//
// Follows Chuang, "Level-of-Detail Modeling Technique for Virtual Reality (I)", 2001, part B: "we check to see if its
// cached LOD can be reused in the new frame. That is, the cached LOD can be reused if its
// projected error with respect to the new viewpoint is within a pre-specified error, or a new
// LOD should be re-generated if the test fails. The test is block-based, rather than
// vertex-based, and thus can be performed very efficiently."
//
// What is bounded. A cached mesh is safe from camera c when every triangle T it draws keeps
//     K * e(T) / max(dist(c, T), near) <= tau                                          (1)
// with e(T) T's exact vertical error against the full-resolution samples (BlockLod::
// triangleError) and dist(c, T) the distance from c to the drawn triangle in 3D: the bound
// BlockLod::extractView promises for a fresh mesh. The finest triangles of a strided block
// (hypotenuse a cell diagonal) are left out, as in extractView's contract: every extraction
// draws them whatever the view, so reusing never makes them worse than rebuilding would.
//
// The summary. The block is cut into a fixed grid of at most 4 x 4 sub-regions S (aligned to
// vertex lines; a clipped block has fewer). For each S, summarizeLod stores, over the drawn
// triangles whose bounding rectangle overlaps S with positive area:
//   E(S)  the largest e(T);
//   B(S)  a box: S's rectangle times [minH(S) - E(S), maxH(S) + E(S)], minH/maxH the vertex
//         heights in S. It holds T ∩ S for each such T: the corners of the polygon T ∩ S are
//         grid vertices (T's edges are axis-aligned or at 45 degrees in grid units, S's sides
//         lie on grid lines), which are full-resolution samples in T, where the drawn plane is
//         within e(T) <= E(S) of the sample height; a plane over a polygon takes its extremes
//         at the corners.
//   M(S)  a margin: the least, over those T with K e(T) / tau > near, of
//         L(T) - K e(T) / tau, where L(T) = max(|c0 - m| - r(m), dist(c0, box(T))) <= dist(c0, T)
//         for T's hypotenuse midpoint m (BlockLod::vertexRadius: the sphere of radius r(m)
//         about m holds T) and T's bounding box. extractView, run with a tolerance tau' <= tau,
//         left m inactive: K e(m) <= tau' max(|c0 - m| - r(m), near), and e(T) <= e(m)
//         (monotone errors), hence M(S) >= 0 (up to rounding): the cache passes at the camera
//         it built for.
// plus, for the "needlessly fine" test, the build distance of each box and the number of
// triangles whose centroid lies in S.
//
// The test, from camera c1 (view K1, tau1, near1), for every non-empty S:
//   (a) K1 E(S) <= tau1 max(dist(c1, B(S)), near1), or
//   (b) the view parameters equal the build's and U(S) <= M(S), where U(S) bounds how much
//       closer c1 is than c0 to any point of the box: U(S) >= sup over q in B(S) of
//       f(q) = |q - c0| - |q - c1|. With w = c1 - c0, f(q) = (2 (q - c0).w - |w|^2) /
//       (|q - c0| + |q - c1|); the numerator is linear in q (largest at a box corner picked
//       axis by axis), the denominator at least dist(c0, B(S)) + dist(c1, B(S)), and f <= |w|.
//       So U(S) <= 0 when the camera moved away from every point of the box (it rose, or
//       left the block behind), and about |w| times the box's angular size when it moved
//       across the line of sight.
// If every S passes, the mesh is reused.
//
// Why (1) then holds for every drawn triangle T (proof). Let p be a point of T nearest to c1.
// Some sub-region S whose rectangle contains p overlaps T's bounding rectangle with positive
// area (the sub-regions containing p cover a neighbourhood of p, and T's rectangle has
// positive area near p), so T counted in S: e(T) <= E(S), and p ∈ T ∩ S ⊂ B(S), so
// dist(c1, T) = dist(c1, T ∩ S) >= dist(c1, B(S)).
//   If (a) holds for S: K1 e(T) <= K1 E(S) <= tau1 max(dist(c1, B(S)), near1)
//                                           <= tau1 max(dist(c1, T), near1).
//   If (b) holds: either K e(T) / tau <= near, and then (1) holds from any camera; or
//   dist(c1, T) = |p - c1| = |p - c0| - f(p) >= dist(c0, T) - U(S) >= L(T) - M(S)
//   >= K e(T) / tau, since p ∈ B(S) and M(S) <= L(T) - K e(T) / tau.
// Everything is evaluated in double. Rounding allowances go the safe way (U is rounded up),
// except that a margin a few ulps below zero (the extraction's own comparison, re-derived)
// is taken as zero.
//
// Why two tests. (a) alone is conservative: B(S) reaches the part of S nearest the camera
// while the large triangles that set E(S) lie farther away, so a freshly built mesh may fail
// (a) at its own camera and would then be rebuilt every frame (23 % of fresh 33^2 meshes did,
// over 20 cameras above a generated DEM). (b) passes at the build camera by construction
// (M >= 0), whenever the camera moves away from a sub-region, and for approaches smaller than
// the slack the extraction left (LodCacheOptions::headroom adds some); (a) takes over when
// the camera has gone far enough for the whole sub-region's error.
//
// Needlessly fine. A mesh built near the camera stays within tau as the camera recedes, but
// carries triangles the new view does not need (docs/design.md: reuse while within tau "and not
// needlessly fine"). The allowed error in S scales with a(S) = tau max(dist(c, B(S)), near)/K,
// and the triangle density of a view-dependent mesh with a(S)^-p (p = densityExponent,
// measured on this project's terrains: the count of a fresh block grows about as tau^-p). The
// estimate of what a fresh mesh would draw is N' = sum_S n(S) (a0(S) / a1(S))^p; the mesh is
// rebuilt when N > fineFactor * N'. This weights the regions by where the triangles are (a
// block the camera left from above is over-refined where it was nearest, even if its far side
// barely moved), unlike "every region's allowed error grew by 2x", which a receding camera over
// a block meets late. A triangle-weighted estimate cannot cause rebuild loops: right after a
// rebuild N' = N.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include <polder/terrain/block_mesh.hpp>
#include <polder/terrain/rtin.hpp>

namespace polder::cache {

// Sub-regions per side of the block summary (fewer for blocks of fewer cells).
inline constexpr int kLodRegionsPerSide = 4;
inline constexpr int kLodRegionCount = kLodRegionsPerSide * kLodRegionsPerSide;

// One sub-region of the summary (see the top of this file).
// Doubles where a value enters the safety proof: rounding a bound to float could tighten it.
struct LodRegion {
  double minZ = 0.0;  // B(S) z-range, metres relative to BlockLod::origin()
  double maxZ = 0.0;
  double marginM = 0.0;         // M(S), metres; +infinity when no triangle constrains it
  double buildDistanceM = 0.0;  // dist(c0, B(S)); the allowed error then was a0 = tau * max(this, near) / K
  float errorM = 0.0f;          // E(S), metres (exact triangle errors are floats already)
  std::uint32_t triangles = 0;  // n(S): drawn triangles with their centroid in S
};

struct LodSummary {
  terrain::LodView view;  // the view the mesh was extracted for (camera relative to origin())
  double spacingX = 0.0;  // metres between neighbouring vertices
  double spacingY = 0.0;
  int regionCells = 0;  // cells per sub-region side
  int cellsX = 0;       // the valid rectangle, cells (BlockLod::cellsX, cellsY)
  int cellsY = 0;
  int regionsX = 0;             // non-empty sub-regions per side; region (rx, ry) is
  int regionsY = 0;             // regions[ry * kLodRegionsPerSide + rx]
  std::uint32_t triangles = 0;  // N: all drawn triangles
  std::array<LodRegion, kLodRegionCount> regions{};
};

enum class LodVerdict : std::uint8_t {
  Reuse,           // within tau from the new camera and not needlessly fine
  TooCoarse,       // some sub-region may exceed tau: rebuild
  NeedlesslyFine,  // within tau, but the view needs far fewer triangles: rebuild
};

struct LodReuseOptions {
  // Rebuild when the mesh has more than this factor times the triangles estimated for the
  // new view. Larger values reuse more and draw more triangles. > 1; +infinity disables.
  double fineFactor = 1.2;
  // p in the density model: a fresh mesh's triangles grow as (allowed error)^-p. Measured on
  // a generated 681^2 DEM (40 m, 441 blocks): each halving of tau, 4 -> 2 -> 1 -> 0.5 px,
  // multiplies the triangles by 1.87, 1.66, 1.54, i.e. p = 0.9 .. 0.6. 1 overestimates the saving a little,
  // which rebuilds receding blocks a little earlier: on flyovers it kept the triangle ratio
  // 1-4 points lower than 0.7 at the same reuse rate.
  double densityExponent = 1.0;
};

// Summarises `mesh`, which lod.extractView produced for `view`'s camera, K and near and a
// tolerance of at most view.tolerancePx (LodCacheOptions::headroom builds finer); the summary
// then vouches for view.tolerancePx. O(triangles + vertices); allocates nothing.
void summarizeLod(const terrain::BlockLod& lod, const terrain::LodView& view, const terrain::BlockMesh& mesh,
                  LodSummary& out);

// The reuse test from `view` (camera relative to the same block's origin()). O(sub-regions).
LodVerdict testLodReuse(const LodSummary& summary, const terrain::LodView& view, const LodReuseOptions& options = {});

}  // namespace polder::cache
