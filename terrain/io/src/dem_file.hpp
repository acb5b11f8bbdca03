// Which reader a DEM file needs, decided the same way for readDem and openDemRows: the
// options and the file's existence first, then the content (PNG, TIFF, OpenEXR signatures),
// then the extension (.hgt; raw only with a layout).
#pragma once

#include <cstdint>
#include <filesystem>

#include <polder/result.hpp>
#include <polder/terrain/dem.hpp>

namespace polder::terrain::io {

enum class DemFileKind { Image, Hgt, Raw };

struct DemFile {
  DemFileKind kind = DemFileKind::Image;
  std::uint64_t length = 0;  // bytes
};

// Fails on bad options (InvalidArgument), a missing or unreadable file (Io), an empty or
// corrupt one (InvalidData), an unknown format (Unsupported). Errors name the problem; the
// caller adds the file.
Result<DemFile> classifyDemFile(const std::filesystem::path& path, const DemOptions& options);

// Fails (InvalidData) unless a raw file of `length` bytes holds exactly options.raw's samples.
Status checkRawLength(const RawLayout& layout, std::uint64_t length);

}  // namespace polder::terrain::io
