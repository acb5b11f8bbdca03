// CRC-32C (Castagnoli polynomial, reflected, as iSCSI and ext4 use it): the checksum every
// tile and table of a Polder file carries, so that a flipped bit or a torn write is found
// when the data is read rather than drawn. Table-driven, eight bytes per step (slice-by-8),
// on any CPU; the tables are constants, so there is no state to set up.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

namespace polder::core {

// The CRC-32C of `bytes`, continuing from `crc` (the CRC of what came before; 0 to start).
std::uint32_t crc32c(std::span<const std::byte> bytes, std::uint32_t crc = 0) noexcept;

inline std::uint32_t crc32c(const void* data, std::size_t size, std::uint32_t crc = 0) noexcept {
  return crc32c(std::span<const std::byte>(static_cast<const std::byte*>(data), size), crc);
}

}  // namespace polder::core
