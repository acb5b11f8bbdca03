// Headerless raw heights (.r16, .raw, .f32): width x height samples of one type, north row
// first, laid out as a RawLayout says.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include <polder/result.hpp>
#include <polder/terrain/dem.hpp>

namespace polder::terrain {

// Bytes a file of this layout holds.
std::uint64_t rawByteSize(const RawLayout& layout);

// Decodes a whole file; `bytes` must be exactly rawByteSize(layout) long (InvalidData
// otherwise). Heights are stored * options.zScale; int16 -32768/-32767 are voids (filled)
// unless options.nodataEnabled is false. Spacing: options.spacingM, else 1 m (assumed).
Result<Dem> decodeRaw(std::span<const std::byte> bytes, const RawLayout& layout, const DemOptions& options);

}  // namespace polder::terrain
