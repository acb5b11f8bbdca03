// The query scene: Polder's one Embree adapter (docs/design.md "Queries and measurement").
//
// It holds a surface in Embree and answers height under a point, ray casts, line of sight
// and batches of rays. Two kinds of surface:
//  - a heightfield at full resolution, as Embree grid primitives (one per block of
//    `blockCells` cells, neighbouring blocks sharing their boundary samples, so the surface
//    is continuous), triangulated exactly as terrain/heightfield.hpp says: each cell cut
//    along the diagonal from sample (x+1, y) to sample (x, y+1);
//  - general triangle meshes (MeshData), e.g. the LOD meshes whose screen-space error is
//    measured against the full-resolution surface.
//
// Precision. Embree works in single precision, so vertices are stored as floats relative
// to a scene origin at the centre of the surface's footprint (heights stay absolute: they
// are floats in the heightfield already). Embree's traversal therefore resolves about one
// float ulp of the largest coordinate, `floatResolution()`: 0.002 m for 2049 samples at
// 30 m, 0.125 m for 256 samples at 9783.94 m, 2 m for 4096 samples at 9.8 km. Unrefined
// hits land within about that times the local slope (measured on slanted rays over
// slopes up to 0.35: 0.05 m at 256 x 9783.94 m, 0.6 m at 4096 x 9783.94 m). With
// `refineHits` (the default) each hit Embree finds is intersected again in double
// precision against the exact triangle (for a heightfield: the convention's triangles of
// the hit cell and its neighbours, with sample positions x * spacingX, y * spacingY), so
// reported points, normals and distances are exact to double rounding (below 1e-8 m at
// 40,000 km extent). What float still decides is only whether a ray grazing a ridge
// within `floatResolution()` hits or misses it. height() on a heightfield is computed in
// closed form from the samples (exact); on meshes it is a vertical ray cast, exact to the
// mesh's own float positions.
//
// No-data: Embree drops a whole grid primitive with one non-finite vertex, so blocks with
// non-finite samples go in as triangles instead, leaving out only the triangles that touch
// such a sample; nothing hits there and height() is nullopt there.
//
// Borders: Embree treats the outer edges on the high side of a surface as open, so a ray
// that meets a heightfield exactly on its east (x = extentX) or north (y = extentY) border,
// or a mesh exactly on such an outer edge, may miss. Interior edges are shared and
// watertight (robust mode). height() on a heightfield includes every border.
//
// Thread contract (Embree's modify/commit/query): create() builds and commits the scene;
// afterwards it is immutable, so every const member may run from any number of threads at
// once without locking. A future call that changes the surface must not overlap queries.
#pragma once

#include <cstddef>
#include <limits>
#include <memory>
#include <optional>
#include <span>

#include <glm/glm.hpp>

#include <polder/mesh_data.hpp>
#include <polder/query/ray.hpp>
#include <polder/query/true_surface.hpp>
#include <polder/result.hpp>
#include <polder/terrain/heightfield.hpp>

namespace polder::query {

struct QueryOptions {
  int blockCells = 256;              // heightfield cells per grid primitive side, 1..32766
  bool refineHits = true;            // re-intersect hits in double precision (see above)
  bool robust = true;                // Embree's watertight mode: no ray slips between triangles
  int buildThreads = 0;              // threads Embree builds with; 0 = Embree's default (all)
  std::size_t memoryLimitBytes = 0;  // Embree's allocations may not exceed this; 0 = no limit
};

class QueryScene final : public TrueSurface {
 public:
  // The full-resolution surface of `field`. Fails with InvalidArgument for a field smaller
  // than 2x2 samples, a size that does not match its heights, or a bad spacing or option;
  // with OutOfMemory past memoryLimitBytes; with Environment for other Embree errors.
  // Samples that are not finite (no-data) leave their triangles out (see above).
  static Result<std::unique_ptr<QueryScene>> create(const terrain::Heightfield& field,
                                                    const QueryOptions& options = {});

  // Triangle meshes (each relative to its own origin). Fails with InvalidArgument for an
  // index count not a multiple of three or an index out of range. Meshes without
  // triangles are skipped; an empty scene answers every query with a miss.
  static Result<std::unique_ptr<QueryScene>> createFromMeshes(std::span<const MeshData> meshes,
                                                              const QueryOptions& options = {});

  ~QueryScene();
  QueryScene(const QueryScene&) = delete;
  QueryScene& operator=(const QueryScene&) = delete;

  // Height of the surface at world (x, y): for a heightfield, of its triangulation;
  // for meshes, of the highest surface under the point. nullopt outside the footprint
  // (or over no-data samples).
  std::optional<double> height(double x, double y) const override;
  bool meets(const QueryRay& ray) const override { return raycast(ray).has_value(); }

  // The nearest hit within maxDistance metres of origin. nullopt for a miss, a zero or
  // non-finite direction, or an origin that is not finite or lies beyond 1e15 m.
  std::optional<RayHit> raycast(const glm::dvec3& origin, const glm::dvec3& direction,
                                double maxDistance = std::numeric_limits<double>::infinity()) const;
  std::optional<RayHit> raycast(const QueryRay& ray) const;

  // True when nothing lies on the segment from a to b. Both ends are pulled in by a few
  // floatResolution() so that points on the surface do not hide themselves. A segment
  // with an end that is not finite or lies beyond 1e15 m is reported as blocked.
  bool lineOfSight(const glm::dvec3& a, const glm::dvec3& b) const;

  // raycast() for each ray, hits[i] for rays[i], traced 16 at a time (Embree packets).
  // Asserts that both spans have the same size.
  void raycastMany(std::span<const QueryRay> rays, std::span<std::optional<RayHit>> hits,
                   RayCoherence coherence = RayCoherence::Incoherent) const;

  // World-frame bounds of the surface (empty scene: min > max).
  glm::dvec3 boundsMin() const;
  glm::dvec3 boundsMax() const;

  // Metres Embree resolves: one float ulp of the largest scene-frame coordinate.
  double floatResolution() const;

  // Bytes held: Embree's allocations (BVH) plus the vertex and index copies kept here.
  std::size_t memoryBytes() const;

 private:
  struct Impl;
  explicit QueryScene(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> m_impl;
};

}  // namespace polder::query
