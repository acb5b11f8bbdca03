// The ray-cast reference renderer: the ground truth that image and error tests compare the
// OpenGL renderer against. It draws what the GL renderer draws for a full-resolution
// terrain mesh with per-vertex normals, one ray per pixel centre.
#pragma once

#include <polder/camera.hpp>
#include <polder/image.hpp>
#include <polder/query/query_scene.hpp>
#include <polder/terrain/heightfield.hpp>
#include <polder/terrain_style.hpp>

namespace polder::query {

// Renders `scene` (built from `field`) as seen by `camera`, widthPx x heightPx, row 0 at
// the top. A pixel whose ray through its centre (camera.pixelRay(x + 0.5, y + 0.5)) hits
// the surface between the near and far planes (eye depth, as GL clips) gets
// shadeTerrain(style, normal, hit z, hit distance) with alpha 255, the normal interpolated
// barycentrically from terrain::sampleNormal at the hit triangle's three samples (as GL
// interpolates vertex normals); any other pixel gets style.skyColour with alpha 0.
// Rows are spread over up to `threads` threads of the pool (0 = one per hardware thread).
RgbaImage renderReference(const QueryScene& scene, const terrain::Heightfield& field, const Camera& camera,
                          const TerrainStyle& style, int threads = 0);

}  // namespace polder::query
