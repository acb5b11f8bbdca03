// A structural check of a PNG before libpng sees it: every chunk complete, every CRC right,
// an IEND at the end. libpng reports a truncated or corrupt file by printing to stderr from
// inside OpenImageIO, which a library must not do; this finds those files first and names
// the problem better. (Corruption inside the zlib stream with intact CRCs still reaches
// libpng; such files are made on purpose, not by failing disks or downloads.)
#pragma once

#include <cstdint>
#include <filesystem>

#include <polder/result.hpp>

namespace polder::terrain::io {

// Fails (InvalidData) on a truncated or corrupt PNG, naming the chunk and its byte offset.
Status checkPngStructure(const std::filesystem::path& path, std::uint64_t fileLength);

}  // namespace polder::terrain::io
