// How far a simplified mesh strays from its original: the figures `polder simplify`
// reports (a Metro-style measure: P. Cignoni, C. Rocchini, R. Scopigno, "Metro: measuring
// error on simplified surfaces", 1998).
//
// Both surfaces are sampled: area-weighted uniform random points (deterministic from the
// seed, whatever the thread count; stratified: the i-th of n falls in the i-th of n
// equal-area slices of the triangles in index order) plus every vertex some triangle uses. Each sample's distance to
// the other surface is exact — the closest point on the other mesh's triangles, found with Embree point queries and
// computed in double precision — so vertices pushed out or pulled in by the simplification are measured exactly, and
// the random samples cover the faces between. Zero-area triangles take part as their edges and never receive random
// samples.
//
// The two meshes need not share a vertex table; the simplified one may also reuse the
// original's positions with fewer indices (unused vertices are not sampled).
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>

#include <polder/mesh/triangle_mesh.hpp>
#include <polder/result.hpp>

namespace polder::query {

struct SurfaceDeviationOptions {
  std::size_t samplesPerSurface = 200000;  // random points on each surface, besides its vertices
  std::uint64_t seed = 1;
  int threads = 0;  // most threads querying at once (and Embree builds with); 0 = one per hardware thread
};

// Distances are relative to the diagonal of the bounding box of the original's used
// vertices, so figures compare across models of any size.
struct SurfaceDeviation {
  // Symmetric Hausdorff distance: the largest distance from a sample of either surface to
  // the other surface.
  double hausdorff = 0.0;
  // Root mean square of the same distances, both directions pooled.
  double rms = 0.0;
  // Where both meshes have colours: the RMS over the original's samples of the RGB
  // (Euclidean, alpha ignored) difference between the original's colour at the sample and
  // the simplified mesh's colour at its closest point, both interpolated barycentrically
  // within their triangle. Not relative to anything (colours are in [0, 1], so at most
  // sqrt(3)). NaN where either mesh has no colours.
  double colourRms = std::numeric_limits<double>::quiet_NaN();
  std::size_t samples = 0;  // samples on both surfaces together
};

// Fails with InvalidArgument where either mesh has no triangles or the original's used
// vertices all coincide (no diagonal to relate to), with validateMesh's error for a
// malformed mesh, with Embree's error (mostly Environment or OutOfMemory) where Embree fails.
Result<SurfaceDeviation> measureSurfaceDeviation(const mesh::TriangleMesh& original,
                                                 const mesh::TriangleMesh& simplified,
                                                 const SurfaceDeviationOptions& options = {});

}  // namespace polder::query
