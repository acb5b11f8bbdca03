// The measured screen-space error of a frame (docs/design.md "Queries and measurement"): the
// ground truth that benchmarks and tests hold the LOD selection to, rather than the bound
// the selector believed.
//
// For each sampled pixel, the ray through its centre is cast against the frame's LOD mesh;
// the true surface point directly above or below the hit (same x, y, full-resolution
// height) and the hit are both projected to the screen, and their distance in pixels is
// that pixel's error.
//
// Holes: pixels that look through a gap in the LOD mesh (a crack or a missing block). Terrain
// is seen from above, so a ray that first meets a triangle's underside has passed through a
// gap; and a ray that meets nothing although sampled pixels above and below it in its column
// meet the mesh, while the true surface is there, has too: seen from an unrolled camera, a
// heightfield leaves no sky below terrain within one image column, and the silhouette's own
// deviation within tau never makes such a pixel.
#pragma once

#include <cstddef>

#include <polder/camera.hpp>
#include <polder/query/query_scene.hpp>
#include <polder/query/true_surface.hpp>

namespace polder::query {

struct ScreenErrorOptions {
  int pixelStride = 1;  // measure every n-th pixel in x and y
  int threads = 0;      // most threads measuring at once; 0 = one per hardware thread
};

struct ScreenError {
  double maxPx = 0.0;
  double p99Px = 0.0;
  double meanPx = 0.0;
  std::size_t pixelsMeasured = 0;  // pixels whose ray hit the LOD mesh over the true surface
  std::size_t holePixels = 0;      // sampled pixels that look through a gap in the LOD mesh
};

// `lodMesh`: the frame's LOD surface (QueryScene::createFromMeshes); `truth`: the
// full-resolution surface (QueryScene::create from the heightfield, or a PyramidSurface).
ScreenError measureScreenError(const QueryScene& lodMesh, const TrueSurface& truth, const Camera& camera,
                               const ScreenErrorOptions& options = {});

}  // namespace polder::query
