// SRTM .hgt tiles: headerless big-endian int16, north row first, 1201^2 (3 arc-seconds) or
// 3601^2 (1 arc-second) samples, voids -32768; the file name (N46W122.hgt) gives the
// latitude of the tile's south edge.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

#include <polder/result.hpp>
#include <polder/terrain/dem.hpp>

namespace polder::terrain {

// Samples per side of a tile of this many bytes: 1201 or 3601, or 0 if it is neither size.
int hgtSizeFromLength(std::uint64_t bytes);

// Fails (InvalidData) unless a file of this many bytes can be a tile.
Status checkHgtLength(std::uint64_t bytes);

// Latitude of the tile's south edge from its file name: "N46W122.hgt" -> 46,
// "S12E130.hgt" -> -12 (case-insensitive, folders ignored); nullopt if it does not parse.
std::optional<int> hgtSouthLatitude(std::string_view fileName);

// Decodes a whole tile. Spacing: the tile's arc-seconds in metres at its centre latitude
// (from the name; 1 m and spacingAssumed if the name gives none) unless options.spacingM.
// Voids are filled and counted. Errors name the problem, not the file (the caller knows it).
Result<Dem> decodeHgt(std::span<const std::byte> bytes, std::string_view fileName, const DemOptions& options);

}  // namespace polder::terrain
