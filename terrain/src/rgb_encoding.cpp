#include <polder/terrain/rgb_encoding.hpp>

#include <cassert>
#include <limits>

namespace polder::terrain {

Heightfield decodeRgbHeights(const RgbView& view, HeightEncoding encoding, bool alphaVoids) {
  assert((encoding == HeightEncoding::TerrainRgb || encoding == HeightEncoding::Terrarium) &&
         "decodeRgbHeights: the encoding must be TerrainRgb or Terrarium");
  assert(view.pixels && (view.channels == 3 || view.channels == 4) && "decodeRgbHeights: needs RGB or RGBA pixels");
  Heightfield field(view.width, view.height);
  const bool hasAlpha = alphaVoids && view.channels == 4;
  const bool terrainRgb = encoding == HeightEncoding::TerrainRgb;
  for (int row = 0; row < view.height; ++row) {
    const std::uint8_t* in = view.pixels + std::size_t(row) * std::size_t(view.width) * std::size_t(view.channels);
    float* out = field.heights.data() + std::size_t(view.height - 1 - row) * std::size_t(view.width);
    for (int x = 0; x < view.width; ++x, in += view.channels) {
      if (hasAlpha && in[3] == 0)
        out[x] = std::numeric_limits<float>::quiet_NaN();
      else
        out[x] = float(terrainRgb ? decodeTerrainRgb(in[0], in[1], in[2]) : decodeTerrarium(in[0], in[1], in[2]));
    }
  }
  return field;
}

}  // namespace polder::terrain
