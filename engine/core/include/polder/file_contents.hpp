// Whole files in memory: read with the checks a reader owes its user (the path exists, is not
// a folder, is no larger than the caller can afford, was read in full), and written whole or
// not at all (core::PartialFile).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include <polder/result.hpp>

namespace polder::core {

// The file's bytes. Io for a missing file, a folder, or a failed read; InvalidData for a
// file over `maxBytes`; OutOfMemory when its bytes do not fit. Messages do not name the
// file: the caller, which knows what the file is for, does.
Result<std::string> readFileContents(const std::filesystem::path& file, std::uint64_t maxBytes);

// Writes `bytes` under a temporary name beside `file`, then renames it into place: a failed
// write, sync or close (a full disk, a size limit) is an Io error naming the file, and leaves
// no file at the destination. An existing file there is replaced only on success.
Status writeFileContents(const std::filesystem::path& file, std::string_view bytes);

}  // namespace polder::core
