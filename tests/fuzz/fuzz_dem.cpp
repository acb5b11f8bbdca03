// Fuzz target: every DEM format through both readers (whole and by rows). The first byte
// picks the extension the readers dispatch on; the rest is the file.
#include <cstddef>
#include <cstdint>
#include <vector>

#include <polder/terrain/dem_reader.hpp>
#include <polder/terrain/dem_rows.hpp>

#include "fuzz_input_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  constexpr const char* kExtensions[] = {".png", ".tif", ".hgt", ".exr", ".r16", ".f32"};
  const std::size_t kind = data[0] % std::size(kExtensions);
  const auto path = polder::fuzz::writeInput(data + 1, size - 1, kExtensions[kind]);
  polder::terrain::DemOptions options;
  options.memoryLimitBytes = std::uint64_t(256) << 20;  // bounded memory is part of the contract
  if (kind >= 4)
    options.raw = polder::terrain::RawLayout{
        16, 16, kind == 4 ? polder::terrain::SampleType::U16 : polder::terrain::SampleType::F32};
  (void)polder::terrain::readDem(path, options);
  if (auto rows = polder::terrain::openDemRows(path, options)) {
    std::vector<float> band(std::size_t((*rows)->width()) * 8);
    for (int y = 0; y < (*rows)->height(); y += 8) {
      const int count = std::min(8, (*rows)->height() - y);
      if (!(*rows)->readRows(y, count,
                             std::span<float>(band.data(), std::size_t(count) * std::size_t((*rows)->width()))))
        break;
    }
  }
  return 0;
}
