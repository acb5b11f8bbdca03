#include <polder/terrain/dem_reader.hpp>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <fstream>
#include <new>
#include <string>
#include <system_error>
#include <vector>

#include <polder/terrain/dem_parsing.hpp>
#include <polder/terrain/dem_validation.hpp>
#include <polder/terrain/hgt.hpp>
#include <polder/terrain/raw.hpp>

#include "image_dem.hpp"
#include "png_check.hpp"

namespace polder::terrain {
namespace {

enum class FileKind { Png, Tiff, Exr, Unknown };

FileKind sniff(const std::array<unsigned char, 8>& head, std::size_t length) {
  const auto starts = [&](std::initializer_list<unsigned char> magic) {
    return length >= magic.size() && std::equal(magic.begin(), magic.end(), head.begin());
  };
  if (starts({0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'})) return FileKind::Png;
  if (starts({'I', 'I', 42, 0}) || starts({'M', 'M', 0, 42}) || starts({'I', 'I', 43, 0}) || starts({'M', 'M', 0, 43}))
    return FileKind::Tiff;  // classic and BigTIFF
  if (starts({0x76, 0x2f, 0x31, 0x01})) return FileKind::Exr;
  return FileKind::Unknown;
}

std::string lowerExtension(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  for (char& c : extension) c = char(std::tolower(static_cast<unsigned char>(c)));
  return extension;
}

Result<std::vector<std::byte>> readWholeFile(const std::filesystem::path& path, std::uint64_t length) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return makeError(ErrorKind::Io, "cannot open the file: " + std::generic_category().message(errno));
  std::vector<std::byte> bytes(length);
  in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(length));
  if (std::uint64_t(in.gcount()) != length)
    return makeError(ErrorKind::Io,
                     "could read only " + std::to_string(in.gcount()) + " of its " + std::to_string(length) + " bytes");
  return bytes;
}

Result<Dem> readRaw(const std::filesystem::path& path, std::uint64_t length, const DemOptions& options) {
  const RawLayout& layout = *options.raw;
  const std::uint64_t bytesPerSample =
      rawByteSize(layout) / (std::uint64_t(layout.width) * std::uint64_t(layout.height));
  if (Status size = checkRasterSize(std::uint64_t(layout.width), std::uint64_t(layout.height),
                                    demBytesPerSample(bytesPerSample), options.memoryLimitBytes);
      !size)
    return size.error();
  if (length != rawByteSize(layout))  // checked before reading a file of the wrong size
    return makeError(ErrorKind::InvalidData, "raw layout " + rawLayoutName(layout) + " needs " +
                                                 std::to_string(rawByteSize(layout)) + " bytes but the file has " +
                                                 std::to_string(length));
  auto bytes = readWholeFile(path, length);
  if (!bytes) return bytes.error();
  return decodeRaw(*bytes, layout, options);
}

Result<Dem> readHgt(const std::filesystem::path& path, std::uint64_t length, const DemOptions& options) {
  if (Status valid = checkHgtLength(length); !valid) return valid.error();
  const int size = hgtSizeFromLength(length);
  if (Status fits =
          checkRasterSize(std::uint64_t(size), std::uint64_t(size), demBytesPerSample(2), options.memoryLimitBytes);
      !fits)
    return fits.error();
  auto bytes = readWholeFile(path, length);
  if (!bytes) return bytes.error();
  return decodeHgt(*bytes, path.filename().string(), options);
}

Result<Dem> readAny(const std::filesystem::path& path, const DemOptions& options) {
  if (Status valid = checkDemOptions(options); !valid) return valid.error();

  std::error_code error;
  const auto status = std::filesystem::status(path, error);
  if (error && error != std::errc::no_such_file_or_directory)
    return makeError(ErrorKind::Io, "cannot access the file: " + error.message());
  if (!std::filesystem::exists(status)) return makeError(ErrorKind::Io, "no such file");
  if (std::filesystem::is_directory(status)) return makeError(ErrorKind::Io, "is a directory, not a DEM file");
  if (!std::filesystem::is_regular_file(status)) return makeError(ErrorKind::Io, "is not a regular file");
  const std::uint64_t length = std::filesystem::file_size(path, error);
  if (error) return makeError(ErrorKind::Io, "cannot read the file size: " + error.message());
  if (length == 0) return makeError(ErrorKind::InvalidData, "the file is empty");

  std::array<unsigned char, 8> head{};
  {
    std::ifstream in(path, std::ios::binary);
    if (!in) return makeError(ErrorKind::Io, "cannot open the file: " + std::generic_category().message(errno));
    in.read(reinterpret_cast<char*>(head.data()), std::streamsize(head.size()));
  }

  if (options.raw) return readRaw(path, length, options);
  const FileKind kind = sniff(head, std::size_t(std::min<std::uint64_t>(length, head.size())));
  if (kind == FileKind::Png)
    if (Status structure = io::checkPngStructure(path, length); !structure) return structure.error();
  if (kind != FileKind::Unknown) return io::readImageDem(path, length, options);

  const std::string extension = lowerExtension(path);
  if (extension == ".hgt") return readHgt(path, length, options);
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

}  // namespace

Result<Dem> readDem(const std::filesystem::path& path, const DemOptions& options) {
  const auto named = [&](const Error& error) { return makeError(error.kind, path.string() + ": " + error.message); };
  try {
    auto dem = readAny(path, options);
    if (!dem) return named(dem.error());
    dem->info.path = path.string();
    return dem;
  } catch (const std::bad_alloc&) {
    return named(makeError(ErrorKind::OutOfMemory, "out of memory while reading"));
  } catch (const std::exception& exception) {
    // Nothing should throw here, but no exception may cross the API.
    return named(makeError(ErrorKind::InvalidData, std::string("unexpected failure: ") + exception.what()));
  }
}

}  // namespace polder::terrain
