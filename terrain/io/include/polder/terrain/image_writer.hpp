// Writing heightfields and rendered frames as image files.
//
// Height files are self-describing: readDem reads them back with their spacing and heights
// in metres, with no options.
//   16-bit PNG: greyscale, north row first; PNG text chunks hold the spacing and the mapping
//     to metres: "polder:spacingX", "polder:spacingY" (metres), "polder:metresPerUnit",
//     "polder:offsetM" (metres = offsetM + value * metresPerUnit), as decimal text.
//   float TIFF: 32-bit float metres, north row first, deflate-compressed, with GeoTIFF
//     ModelPixelScale (spacing), ModelTiepoint and GeoKeys for a projected CRS in metres.
#pragma once

#include <filesystem>
#include <optional>

#include <polder/image.hpp>
#include <polder/result.hpp>
#include <polder/terrain/heightfield.hpp>

namespace polder::terrain {

// How a 16-bit PNG stores metres: metres = offsetM + value * metresPerUnit, value 0..65535.
struct HeightQuantization {
  double metresPerUnit = 1.0;
  double offsetM = 0.0;
};

// The finest quantization that holds the field's heights: its lowest height at 0, its
// highest at 65535 (metresPerUnit 1 for a flat field).
HeightQuantization fitHeightQuantization(const Heightfield& field);

// Fails with InvalidArgument on an empty field, a non-finite height or one outside the
// quantization's range, and with Io when the file cannot be written.
Status writeHeightPng16(const std::filesystem::path& path, const Heightfield& field,
                        std::optional<HeightQuantization> quantization = std::nullopt);

// Lossless: heights as 32-bit floats. Fails like writeHeightPng16.
Status writeHeightTiffFloat(const std::filesystem::path& path, const Heightfield& field);

// An 8-bit RGBA PNG, rows top to bottom as RgbaImage stores them.
Status writeRgbaPng(const std::filesystem::path& path, const RgbaImage& image);

}  // namespace polder::terrain
