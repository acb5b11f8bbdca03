// What makes a DEM acceptable: sane options, a size that fits in memory (checked before
// anything is allocated), and at least one valid, finite sample. Every reader ends with
// finishDem, so all formats fill voids and report ranges the same way.
#pragma once

#include <cstdint>
#include <optional>

#include <polder/result.hpp>
#include <polder/terrain/dem.hpp>
#include <polder/terrain/geo_spacing.hpp>

namespace polder::terrain {

// Rasters above this many samples are refused whatever the memory.
inline constexpr std::uint64_t kMaxDemSamples = std::uint64_t(1) << 31;

// Heights beyond this, in metres once scaled, are no terrain (the deepest trench and the
// highest volcano are tens of kilometres): a wrong height scale, refused before the single-
// precision geometry and camera paths built on them lose meaning.
inline constexpr double kMaxDemHeightM = 1e6;

// Fails (InvalidArgument) on options out of range: spacingM not positive and finite, zScale
// zero or not finite, a raw layout without samples.
Status checkDemOptions(const DemOptions& options);

// Bytes of physical memory in this machine, 0 if unknown.
std::uint64_t physicalMemoryBytes();

// Memory a reader needs per sample: what it reads, the float height, and void-filling scratch.
inline std::uint64_t demBytesPerSample(std::uint64_t storedBytesPerSample) { return storedBytesPerSample + 4 + 7; }

// One row or column spans no ground: nothing to draw, measure or query. InvalidData for
// fewer than 2 x 2 samples.
Status checkSpansGround(std::uint64_t width, std::uint64_t height);

// Fails before allocation when a width x height raster cannot be read: fewer than 2 x 2
// samples (InvalidData), more than kMaxDemSamples, or more than memoryLimitBytes (0: the machine's
// physical memory) at bytesPerSample (OutOfMemory).
Status checkRasterSize(std::uint64_t width, std::uint64_t height, std::uint64_t bytesPerSample,
                       std::uint64_t memoryLimitBytes);

// The last step of every reader. Sets the spacing (options.spacingM, else `fileSpacing`,
// else 1 m with info.spacingAssumed), fails (InvalidData) when no sample is valid or a height
// lies beyond kMaxDemHeightM, fills the voids (NaN samples) and records their count and the
// height range in info.
Result<Dem> finishDem(Heightfield field, DemInfo info, const DemOptions& options,
                      std::optional<GroundSpacing> fileSpacing);

}  // namespace polder::terrain
