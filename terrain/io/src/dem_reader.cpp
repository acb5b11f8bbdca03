#include <polder/terrain/dem_reader.hpp>

#include <cerrno>
#include <fstream>
#include <new>
#include <string>
#include <system_error>
#include <vector>

#include <polder/terrain/dem_validation.hpp>
#include <polder/terrain/hgt.hpp>
#include <polder/terrain/raw.hpp>

#include "dem_file.hpp"
#include "image_dem.hpp"

namespace polder::terrain {
namespace {

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
  // Checked before reading a file of the wrong size.
  if (Status fits = io::checkRawLength(layout, length); !fits) return fits.error();
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
  const auto file = io::classifyDemFile(path, options);
  if (!file) return file.error();
  switch (file->kind) {
    case io::DemFileKind::Raw:
      return readRaw(path, file->length, options);
    case io::DemFileKind::Hgt:
      return readHgt(path, file->length, options);
    case io::DemFileKind::Image:
      break;
  }
  return io::readImageDem(path, file->length, options);
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
