// Where things lie in a pyramid file (pyramid.hpp): shared by the writer and the reader.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

#include <polder/terrain/pyramid.hpp>

namespace polder::terrain::pyramid_layout {

// Header fields, at fixed byte offsets. The CRC in the last four bytes covers everything
// after the magic and before itself, so the magic can be written last.
inline constexpr std::size_t kVersionAt = 8, kHeaderBytesAt = 12, kWidthAt = 16, kHeightAt = 20, kSpacingXAt = 24,
                             kSpacingYAt = 32, kKAt = 40, kRootLevelAt = 44, kMinAt = 48, kMaxAt = 52,
                             kNodeCountAt = 56, kNodesOffsetAt = 64, kBorderOffsetAt = 72, kTilesOffsetAt = 80,
                             kTileSlotAt = 88, kTileSideAt = 92, kFileBytesAt = 96, kSourceLengthAt = 104,
                             kSourceAt = 108, kCrcAt = kPyramidHeaderBytes - 4;
inline constexpr std::size_t kMaxSourceBytes = 1024;

template <class T>
void put(unsigned char* bytes, std::size_t at, T value) {
  std::memcpy(bytes + at, &value, sizeof(T));
}
template <class T>
T get(const unsigned char* bytes, std::size_t at) {
  T value;
  std::memcpy(&value, bytes + at, sizeof(T));
  return value;
}

inline std::size_t nodeTableBytes(std::uint64_t nodeCount) {
  const std::size_t chunks = (nodeCount + kPyramidNodeChunk - 1) / kPyramidNodeChunk;
  return std::size_t(nodeCount) * sizeof(PyramidNode) + chunks * 4;
}
inline std::size_t borderBytes(int width, int height) {
  return (std::size_t(width) + std::size_t(height)) * sizeof(float) + 8;
}
inline std::uint32_t tileSide(int k) { return (1u << k) + 2; }
// A tile slot: the header, room for tileSide^2 samples, then the cells' residuals: one float
// step (metres) and one byte per cell, the residual being at most byte * step.
inline std::size_t tileResidualAt(int k) {
  return kPyramidTileHeaderBytes + std::size_t(tileSide(k)) * tileSide(k) * sizeof(float);
}
inline std::size_t tileCellsMax(int k) { return std::size_t(tileSide(k) - 1) * (tileSide(k) - 1); }
inline std::uint32_t tileSlotBytes(int k) { return std::uint32_t(tileResidualAt(k) + sizeof(float) + tileCellsMax(k)); }

}  // namespace polder::terrain::pyramid_layout
