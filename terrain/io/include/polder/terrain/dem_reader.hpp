// Reading a DEM file of any supported format into a Heightfield in metres (row 0 south).
//
// Formats, recognised by content first and then by extension:
//   PNG (8/16-bit greyscale; 8-bit RGB(A) as Terrain-RGB or Terrarium), TIFF and GeoTIFF
//   (8/16/32-bit integer, float; strips or tiles; any compression libtiff reads), OpenEXR,
//   SRTM .hgt, and headerless raw .r16/.raw/.f32 (needs options.raw; with options.raw set,
//   any file is read as raw).
// Spacing: options.spacingM; else the file's georeferencing (GeoTIFF ModelPixelScale in
//   degrees, Web Mercator or projected units; the spacing a Polder-written PNG carries; an
//   .hgt tile's name); else 1 m with info.spacingAssumed.
// Heights: stored value * options.zScale for single-channel data (a Polder PNG's own scale
//   and offset unless zScale is not 1); Terrain-RGB and Terrarium decode to metres.
// Voids: GDAL_NODATA, int16 -32768 and -32767, alpha 0 in RGBA tiles; filled from their
//   neighbours and counted in info.voids, unless options.nodataEnabled is false.
// info.format: "png", "tiff", "geotiff", "openexr", "hgt" or "raw"; info.encoding: the
//   sample type ("uint8", "uint16", "int16", "uint32", "int32", "float16", "float32",
//   "float64") or "terrain-rgb" / "terrarium".
//
// Errors never assert or throw; the message is one line naming the file and the problem.
// ErrorKind: Io (missing, unreadable), InvalidData (corrupt, truncated, NaN, all voids),
// Unsupported (unknown format), OutOfMemory (over 2^31 samples or more than
// options.memoryLimitBytes / physical memory, checked before allocating), InvalidArgument
// (bad options). Thread-safe: calls on different files may run concurrently.
#pragma once

#include <filesystem>

#include <polder/result.hpp>
#include <polder/terrain/dem.hpp>

namespace polder::terrain {

Result<Dem> readDem(const std::filesystem::path& path, const DemOptions& options = {});

}  // namespace polder::terrain
