// Background pixels enclosed by terrain in a rendered frame. Terrain is a height field seen
// from above it, so a background (sky) pixel with terrain directly above and below it, or
// directly left and right of it, is a gap between triangles or a notch of a silhouette
// (polder/query/frame_cracks.hpp tells the two apart). Frames mark terrain with alpha 255
// and background with alpha 0 (polder::render's contract).
#pragma once

#include <cstddef>

#include <polder/image.hpp>

namespace polder {

// (x, y) must be at least one pixel inside the image.
inline bool isEnclosedBackground(const RgbaImage& image, int x, int y) {
  auto terrain = [&](int px, int py) { return image.at(px, py)[3] != 0; };
  if (terrain(x, y)) return false;
  return (terrain(x, y - 1) && terrain(x, y + 1)) || (terrain(x - 1, y) && terrain(x + 1, y));
}

inline std::size_t countEnclosedBackground(const RgbaImage& image) {
  std::size_t enclosed = 0;
  for (int y = 1; y + 1 < image.height; ++y)
    for (int x = 1; x + 1 < image.width; ++x) enclosed += isEnclosedBackground(image, x, y) ? 1 : 0;
  return enclosed;
}

}  // namespace polder
