// The measured screen-space error of a frame (docs/design.md "Queries and measurement"): the
// ground truth that benchmarks and tests hold the LOD selection to, rather than the bound
// the selector believed.
//
// For each sampled pixel, the ray through its centre is cast against the frame's LOD mesh;
// the true surface point directly above or below the hit (same x, y, full-resolution
// height) and the hit are both projected to the screen, and their distance in pixels is
// that pixel's error.
#pragma once

#include <cstddef>

#include <polder/camera.hpp>
#include <polder/query/query_scene.hpp>

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
};

// `lodMesh`: the frame's LOD surface (QueryScene::createFromMeshes); `truth`: the
// full-resolution surface (QueryScene::create from the heightfield).
ScreenError measureScreenError(const QueryScene& lodMesh, const QueryScene& truth, const Camera& camera,
                               const ScreenErrorOptions& options = {});

}  // namespace polder::query
