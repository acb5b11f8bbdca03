// Appending numbers as little-endian bytes, for the binary PLY and glTF writers.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <string>

namespace polder::mesh_io::detail {

template <class T>
void appendLittleEndian(std::string& out, T value) {
  auto bits = std::bit_cast<std::array<char, sizeof(T)>>(value);
  if constexpr (std::endian::native == std::endian::big) std::reverse(bits.begin(), bits.end());
  out.append(bits.data(), bits.size());
}

}  // namespace polder::mesh_io::detail
