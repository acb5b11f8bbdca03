#include "dem_file.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <fstream>
#include <string>
#include <system_error>

#include <polder/terrain/dem_parsing.hpp>
#include <polder/terrain/dem_validation.hpp>
#include <polder/terrain/raw.hpp>

#include <polder/png_check.hpp>

namespace polder::terrain::io {
namespace {

enum class Signature { Png, Tiff, Exr, Unknown };

Signature sniff(const std::array<unsigned char, 8>& head, std::size_t length) {
  const auto starts = [&](std::initializer_list<unsigned char> magic) {
    return length >= magic.size() && std::equal(magic.begin(), magic.end(), head.begin());
  };
  if (starts({0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'})) return Signature::Png;
  if (starts({'I', 'I', 42, 0}) || starts({'M', 'M', 0, 42}) || starts({'I', 'I', 43, 0}) || starts({'M', 'M', 0, 43}))
    return Signature::Tiff;  // classic and BigTIFF
  if (starts({0x76, 0x2f, 0x31, 0x01})) return Signature::Exr;
  return Signature::Unknown;
}

std::string lowerExtension(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  for (char& c : extension) c = char(std::tolower(static_cast<unsigned char>(c)));
  return extension;
}

}  // namespace

Result<DemFile> classifyDemFile(const std::filesystem::path& path, const DemOptions& options) {
  if (Status valid = checkDemOptions(options); !valid) return valid.error();

  std::error_code error;
  const auto status = std::filesystem::status(path, error);
  if (error && error != std::errc::no_such_file_or_directory)
    return makeError(ErrorKind::Io, "cannot access the file: " + error.message());
  if (!std::filesystem::exists(status)) return makeError(ErrorKind::Io, "no such file");
  if (std::filesystem::is_directory(status)) return makeError(ErrorKind::Io, "is a directory, not a DEM file");
  if (!std::filesystem::is_regular_file(status)) return makeError(ErrorKind::Io, "is not a regular file");
  DemFile file;
  file.length = std::filesystem::file_size(path, error);
  if (error) return makeError(ErrorKind::Io, "cannot read the file size: " + error.message());
  if (file.length == 0) return makeError(ErrorKind::InvalidData, "the file is empty");

  std::array<unsigned char, 8> head{};
  {
    std::ifstream in(path, std::ios::binary);
    if (!in) return makeError(ErrorKind::Io, "cannot open the file: " + std::generic_category().message(errno));
    in.read(reinterpret_cast<char*>(head.data()), std::streamsize(head.size()));
  }

  if (options.raw) return DemFile{DemFileKind::Raw, file.length};
  const Signature signature = sniff(head, std::size_t(std::min<std::uint64_t>(file.length, head.size())));
  if (signature == Signature::Png)
    if (Status structure = image_check::checkPngStructure(path, file.length); !structure) return structure.error();
  if (signature != Signature::Unknown) return DemFile{DemFileKind::Image, file.length};

  const std::string extension = lowerExtension(path);
  if (extension == ".hgt") return DemFile{DemFileKind::Hgt, file.length};
  if (extension == ".r16" || extension == ".raw" || extension == ".f32")
    return makeError(ErrorKind::InvalidArgument,
                     "a headerless raw file needs its layout (options.raw, --raw WxH:u16|i16|f32[:le|be])");
  if (extension == ".png")
    return makeError(ErrorKind::InvalidData, "not a PNG: the PNG signature is missing (corrupt?)");
  if (extension == ".tif" || extension == ".tiff")
    return makeError(ErrorKind::InvalidData, "not a TIFF: the TIFF header is missing (corrupt?)");
  if (extension == ".exr")
    return makeError(ErrorKind::InvalidData, "not an OpenEXR: the EXR magic number is missing (corrupt?)");
  return makeError(ErrorKind::Unsupported,
                   "unknown DEM format (expected PNG, TIFF/GeoTIFF, OpenEXR, SRTM .hgt, or raw with a layout)");
}

Status checkRawLength(const RawLayout& layout, std::uint64_t length) {
  if (length == rawByteSize(layout)) return {};
  return makeError(ErrorKind::InvalidData, "raw layout " + rawLayoutName(layout) + " needs " +
                                               std::to_string(rawByteSize(layout)) + " bytes but the file has " +
                                               std::to_string(length));
}

}  // namespace polder::terrain::io
