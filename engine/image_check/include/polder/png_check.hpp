// A structural check of a PNG before libpng sees it: every chunk complete, every CRC right,
// the image data one whole zlib stream (inflated and discarded, checksum included), an IEND
// at the end. libpng reports a truncated or corrupt file by printing to stderr from inside
// OpenImageIO, which a library must not do; this finds those files first and names the
// problem better. Memory stays bounded whatever the image size.
#pragma once

#include <cstdint>
#include <filesystem>

#include <polder/result.hpp>

namespace polder::image_check {

// Fails (InvalidData) on a truncated or corrupt PNG, naming the chunk and its byte offset.
// Reads the whole file once.
Status checkPngStructure(const std::filesystem::path& path, std::uint64_t fileLength);

// checkPngStructure where the file starts with the PNG signature; any other file passes
// (its own decoder judges it).
Status checkIfPng(const std::filesystem::path& path);

}  // namespace polder::image_check
