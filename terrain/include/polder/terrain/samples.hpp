// Stored raster samples to heights in metres: the step every single-channel reader shares
// (images, GeoTIFF, SRTM .hgt, raw). It flips the rows (files store the north row first,
// a Heightfield the south row), applies the height scale, and marks voids as NaN.
#pragma once

#include <cstddef>
#include <optional>

#include <polder/result.hpp>
#include <polder/terrain/heightfield.hpp>

namespace polder::terrain {

enum class SampleFormat { U8, U16, I16, U32, I32, F32, F64 };

std::size_t sampleFormatBytes(SampleFormat format);
const char* sampleFormatName(SampleFormat format);  // "uint8", "int16", "float32", ...

// A north-row-first raster of interleaved samples in memory.
struct SampleSource {
  const std::byte* data = nullptr;  // width * height * channels samples
  SampleFormat format = SampleFormat::U16;
  int width = 0;
  int height = 0;
  int channels = 1;        // samples per pixel
  int channel = 0;         // the one that holds the height
  bool swapBytes = false;  // stored in the opposite byte order to this machine's
};

// How stored values become metres and which of them are voids.
struct SampleDecoding {
  double scale = 1.0;  // metres = offset + stored * scale
  double offset = 0.0;
  std::optional<double> nodata;  // a stored value that marks a void (NaN: NaN samples are voids)
  bool int16Voids = false;       // stored -32768 and -32767 are voids (SRTM and GDAL habit)
};

// Heights in metres, row 0 south, voids as NaN, spacing 1. Fails (InvalidData) on a NaN or
// infinite sample that is not a void, or a height outside float range, naming the sample.
Result<Heightfield> decodeSamples(const SampleSource& source, const SampleDecoding& decoding);

}  // namespace polder::terrain
