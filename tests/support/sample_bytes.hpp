// Test inputs: sample values as the bytes of a raw or .hgt file, in a chosen byte order.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace polder::test {

template <class T>
std::string storeSamples(const std::vector<T>& values, bool bigEndian) {
  std::string bytes(values.size() * sizeof(T), '\0');
  std::memcpy(bytes.data(), values.data(), bytes.size());
  const std::uint16_t probe = 1;
  const bool littleMachine = *reinterpret_cast<const std::uint8_t*>(&probe) == 1;
  if (bigEndian == littleMachine)
    for (std::size_t i = 0; i < bytes.size(); i += sizeof(T)) std::reverse(&bytes[i], &bytes[i] + sizeof(T));
  return bytes;
}

}  // namespace polder::test
