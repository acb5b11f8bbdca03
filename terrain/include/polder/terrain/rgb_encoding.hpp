// Heights packed into the 8-bit R, G, B channels of web map tiles: Mapbox Terrain-RGB and
// Mapzen Terrarium, and telling the two apart when a file does not say.
#pragma once

#include <cstdint>

#include <polder/result.hpp>
#include <polder/terrain/dem.hpp>
#include <polder/terrain/heightfield.hpp>

namespace polder::terrain {

// Mapbox Terrain-RGB: h = -10000 + (R*65536 + G*256 + B) * 0.1 metres.
inline double decodeTerrainRgb(std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  return -10000.0 + (r * 65536.0 + g * 256.0 + b) * 0.1;
}

// Mapzen Terrarium: h = R*256 + G + B/256 - 32768 metres.
inline double decodeTerrarium(std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  return r * 256.0 + g + b / 256.0 - 32768.0;
}

// 8-bit pixels of three or four interleaved channels (R, G, B[, A]), north row first.
struct RgbView {
  const std::uint8_t* pixels = nullptr;
  int width = 0;
  int height = 0;
  int channels = 3;  // 3 or 4
};

// Heights in metres (row 0 south, spacing 1) for encoding TerrainRgb or Terrarium. With
// `alphaVoids`, pixels of alpha 0 become voids (NaN).
Heightfield decodeRgbHeights(const RgbView& view, HeightEncoding encoding, bool alphaVoids);

// Which encoding the pixels use: Greyscale when R = G = B everywhere (a grey image saved as
// RGB), else TerrainRgb or Terrarium, whichever decodes to plausible Earth heights
// (-11 km..9 km) and, if both do, is the smoother. Fails (InvalidData) when neither is
// plausible.
Result<HeightEncoding> detectRgbEncoding(const RgbView& view);

}  // namespace polder::terrain
