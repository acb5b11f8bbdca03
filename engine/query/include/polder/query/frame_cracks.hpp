// Cracks in a rendered frame: background pixels enclosed by terrain (polder/
// enclosed_background.hpp) that the frame's own triangles cover. An enclosed background pixel
// is either a gap between triangles, which the rasteriser left although the mesh covers the
// pixel's centre, or a notch of a silhouette against the sky (between two distant peaks, the
// surface itself leaves the centre uncovered); rays through the pixel's centre and a tenth
// of a pixel around it, against the frame's mesh, tell them apart.
#pragma once

#include <cstddef>

#include <polder/camera.hpp>
#include <polder/image.hpp>
#include <polder/query/query_scene.hpp>

namespace polder::query {

struct FrameCracks {
  std::size_t enclosedBackground = 0;  // background pixels with terrain above and below, or left and right
  std::size_t cracks = 0;              // of those, pixels the frame's mesh covers around the centre
};

// `image` as the renderer read it back (alpha 0 for background) for `camera`; `frameMesh`
// holds the triangles that frame drew.
FrameCracks findFrameCracks(const RgbaImage& image, const QueryScene& frameMesh, const Camera& camera);

}  // namespace polder::query
