// Fuzz target: a prepared pyramid (polder prep), opened and, when small, read whole.
#include <cstddef>
#include <cstdint>

#include <polder/terrain/pyramid.hpp>

#include "fuzz_input_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = polder::fuzz::writeInput(data, size, ".pyr");
  auto pyramid = polder::terrain::Pyramid::open(path);
  if (!pyramid) return 0;
  const auto& header = (*pyramid)->header();
  if (std::uint64_t(header.width) * std::uint64_t(header.height) <= (std::uint64_t(1) << 22))
    (void)polder::terrain::readFullResolution(**pyramid);
  return 0;
}
