// What a DEM reader is asked for and what it reports. The reading itself lives in the
// OpenImageIO adapter (polder::terrain_io, <polder/terrain/dem_reader.hpp>); the pure
// decoders it uses (SRTM .hgt, raw, Terrain-RGB, Terrarium, void filling) live here.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include <polder/terrain/heightfield.hpp>

namespace polder::terrain {

// How the RGB(A) channels of an image carry height.
enum class HeightEncoding {
  Auto,        // greyscale as is; an RGB(A) PNG is decoded as Terrain-RGB or Terrarium, detected
  Greyscale,   // one channel holds the height (scaled by zScale)
  TerrainRgb,  // Mapbox: h = -10000 + (R*65536 + G*256 + B) * 0.1
  Terrarium,   // Mapzen:  h = R*256 + G + B/256 - 32768
};

enum class SampleType { U16, I16, F32 };

// The layout of a headerless .r16/.raw/.f32 file (`--raw WxH:u16|i16|f32[:le|be]`).
struct RawLayout {
  int width = 0;
  int height = 0;
  SampleType type = SampleType::U16;
  bool bigEndian = false;
};

struct DemOptions {
  std::optional<double> spacingM;  // overrides the file's georeferencing (metres, > 0)
  double zScale = 1.0;             // metres per stored unit (greyscale and raw)
  HeightEncoding encoding = HeightEncoding::Auto;
  bool nodataEnabled = true;     // false: `--nodata none`, no value is a void
  std::optional<RawLayout> raw;  // required for headerless raw files
  // Refuse rasters whose heights need more bytes than this; 0 = the machine's physical memory.
  std::uint64_t memoryLimitBytes = 0;
};

struct DemInfo {
  std::string path;
  std::string format;           // e.g. "png", "tiff", "geotiff", "openexr", "hgt", "raw"
  std::string encoding;         // "greyscale", "terrain-rgb", "terrarium", "int16", "float32", ...
  bool spacingAssumed = false;  // nothing gave a spacing: 1 m was used
  std::int64_t voids = 0;       // no-data samples found (and filled)
  double minM = 0.0;            // height range after void filling
  double maxM = 0.0;
};

struct Dem {
  Heightfield field;
  DemInfo info;
};

}  // namespace polder::terrain
