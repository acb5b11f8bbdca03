// Makers of DEM files for the reader tests: images through OpenImageIO, GeoTIFFs through
// libtiff (OpenImageIO 2.4 cannot write GeoTIFF tags), and raw bytes.
#pragma once

#include "../wgs84_reference.hpp"
#include "sample_bytes.hpp"

#include <OpenImageIO/imageio.h>
#include <tiffio.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <initializer_list>
#include <string>
#include <type_traits>
#include <vector>

#include <gtest/gtest.h>

namespace polder::test {

struct ImageLayout {
  int tile = 0;             // 0: scanlines (strips)
  std::string compression;  // "" (the format's default), "none", "zip", "lzw", ...
};

inline std::string littleEndian(std::uint64_t value, int bytes) {
  std::string text;
  for (int i = 0; i < bytes; ++i) text += char((value >> (8 * i)) & 0xff);
  return text;
}

// One entry of a hand-made little-endian TIFF's directory, of SHORT (3) or LONG (4) values:
// a single value is stored in the entry, more at offset `value`.
struct TiffEntry {
  std::uint16_t tag, type;
  std::uint32_t count, value;
};

// A directory's bytes: the entry count, the entries (sorted by tag), no next directory.
inline std::string tiffDirectory(std::initializer_list<TiffEntry> entries) {
  std::string bytes = littleEndian(entries.size(), 2);
  for (const TiffEntry& e : entries)
    bytes += littleEndian(e.tag, 2) + littleEndian(e.type, 2) + littleEndian(e.count, 4) + littleEndian(e.value, 4);
  return bytes + littleEndian(0, 4);
}

// Writes width x height pixels of `channels` values of `type`, north row first.
inline void writeImage(const std::filesystem::path& path, int width, int height, int channels, OIIO::TypeDesc type,
                       const void* pixels, const ImageLayout& layout = {}) {
  OIIO::ImageSpec spec(width, height, channels, type);
  if (layout.tile) spec.tile_width = spec.tile_height = layout.tile;
  if (!layout.compression.empty()) spec.attribute("compression", layout.compression);
  if (channels == 4) spec.alpha_channel = 3;
  spec.attribute("oiio:UnassociatedAlpha", 1);
  auto output = OIIO::ImageOutput::create(path.string());
  ASSERT_TRUE(output) << OIIO::geterror();
  ASSERT_TRUE(output->open(path.string(), spec)) << output->geterror();
  ASSERT_TRUE(output->write_image(type, pixels)) << output->geterror();
  ASSERT_TRUE(output->close()) << output->geterror();
}

template <class T>
void writeImage(const std::filesystem::path& path, int width, int height, int channels, const std::vector<T>& pixels,
                const ImageLayout& layout = {}) {
  ASSERT_EQ(pixels.size(), std::size_t(width) * std::size_t(height) * std::size_t(channels));
  writeImage(path, width, height, channels, OIIO::TypeDesc(OIIO::BaseTypeFromC<T>::value), pixels.data(), layout);
}

// GeoTIFF tags to write; empty ones are left out.
struct GeoTags {
  std::vector<double> pixelScale;
  std::vector<double> tiepoint;
  std::vector<std::uint16_t> geoKeys;  // whole directory: header and entries
  std::string nodata;
};

// The directory for these (key, value) pairs.
inline std::vector<std::uint16_t> geoKeyDirectory(std::initializer_list<std::pair<std::uint16_t, std::uint16_t>> keys) {
  std::vector<std::uint16_t> directory = {1, 1, 0, std::uint16_t(keys.size())};
  for (auto [id, value] : keys) directory.insert(directory.end(), {id, 0, 1, value});
  return directory;
}

// A one-channel TIFF of T (int16, uint16, float), north row first, with GeoTIFF tags;
// tiled (16 x 16) and deflate-compressed when asked.
template <class T>
void writeGeoTiff(const std::filesystem::path& path, int width, int height, const std::vector<T>& samples,
                  const GeoTags& tags, bool tiledCompressed = false) {
  ASSERT_EQ(samples.size(), std::size_t(width) * std::size_t(height));
  static const TIFFFieldInfo kFields[] = {
      {33550, -1, -1, TIFF_DOUBLE, FIELD_CUSTOM, 1, 1, const_cast<char*>("ModelPixelScaleTag")},
      {33922, -1, -1, TIFF_DOUBLE, FIELD_CUSTOM, 1, 1, const_cast<char*>("ModelTiepointTag")},
      {34735, -1, -1, TIFF_SHORT, FIELD_CUSTOM, 1, 1, const_cast<char*>("GeoKeyDirectoryTag")},
      {42113, -1, -1, TIFF_ASCII, FIELD_CUSTOM, 1, 0, const_cast<char*>("GDAL_NODATA")},
  };
  TIFF* tif = TIFFOpen(path.c_str(), "w");
  ASSERT_NE(tif, nullptr);
  ASSERT_EQ(TIFFMergeFieldInfo(tif, kFields, 4), 0);
  const bool isFloat = std::is_floating_point_v<T>;
  TIFFSetField(tif, TIFFTAG_IMAGEWIDTH, std::uint32_t(width));
  TIFFSetField(tif, TIFFTAG_IMAGELENGTH, std::uint32_t(height));
  TIFFSetField(tif, TIFFTAG_SAMPLESPERPIXEL, 1);
  TIFFSetField(tif, TIFFTAG_BITSPERSAMPLE, int(8 * sizeof(T)));
  TIFFSetField(tif, TIFFTAG_SAMPLEFORMAT,
               isFloat               ? SAMPLEFORMAT_IEEEFP
               : std::is_signed_v<T> ? SAMPLEFORMAT_INT
                                     : SAMPLEFORMAT_UINT);
  TIFFSetField(tif, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_MINISBLACK);
  TIFFSetField(tif, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
  TIFFSetField(tif, TIFFTAG_COMPRESSION, tiledCompressed ? COMPRESSION_ADOBE_DEFLATE : COMPRESSION_NONE);
  if (tiledCompressed) {
    TIFFSetField(tif, TIFFTAG_PREDICTOR, isFloat ? PREDICTOR_FLOATINGPOINT : PREDICTOR_HORIZONTAL);
    TIFFSetField(tif, TIFFTAG_TILEWIDTH, 16);
    TIFFSetField(tif, TIFFTAG_TILELENGTH, 16);
  } else {
    TIFFSetField(tif, TIFFTAG_ROWSPERSTRIP, std::uint32_t(height));
  }
  if (!tags.pixelScale.empty()) TIFFSetField(tif, 33550, int(tags.pixelScale.size()), tags.pixelScale.data());
  if (!tags.tiepoint.empty()) TIFFSetField(tif, 33922, int(tags.tiepoint.size()), tags.tiepoint.data());
  if (!tags.geoKeys.empty()) TIFFSetField(tif, 34735, int(tags.geoKeys.size()), tags.geoKeys.data());
  if (!tags.nodata.empty()) TIFFSetField(tif, 42113, tags.nodata.c_str());
  if (tiledCompressed) {
    std::vector<T> tile(16 * 16);
    for (int ty = 0; ty < height; ty += 16)
      for (int tx = 0; tx < width; tx += 16) {
        std::fill(tile.begin(), tile.end(), T(0));
        for (int y = ty; y < std::min(ty + 16, height); ++y)
          for (int x = tx; x < std::min(tx + 16, width); ++x)
            tile[std::size_t((y - ty) * 16 + (x - tx))] = samples[std::size_t(y) * std::size_t(width) + std::size_t(x)];
        ASSERT_GE(TIFFWriteTile(tif, tile.data(), std::uint32_t(tx), std::uint32_t(ty), 0, 0), 0);
      }
  } else {
    for (int y = 0; y < height; ++y)
      ASSERT_GE(
          TIFFWriteScanline(tif, const_cast<T*>(&samples[std::size_t(y) * std::size_t(width)]), std::uint32_t(y), 0),
          0);
  }
  TIFFClose(tif);
}

// Stores values in the byte order asked for.

}  // namespace polder::test
