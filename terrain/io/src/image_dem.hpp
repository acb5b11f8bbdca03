// Reading PNG, TIFF/GeoTIFF and OpenEXR DEMs through OpenImageIO.
#pragma once

#include <cstdint>
#include <filesystem>

#include <polder/result.hpp>
#include <polder/terrain/dem.hpp>

namespace polder::terrain::io {

// Errors name the problem; readDem adds the file.
Result<Dem> readImageDem(const std::filesystem::path& path, std::uint64_t fileLength, const DemOptions& options);

}  // namespace polder::terrain::io
