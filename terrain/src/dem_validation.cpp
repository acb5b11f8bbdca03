#include <polder/terrain/dem_validation.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include <unistd.h>

#include <polder/terrain/void_fill.hpp>

namespace polder::terrain {
namespace {

std::string formatBytes(double bytes) {
  const char* units[] = {"bytes", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  int unit = 0;
  while (bytes >= 1024.0 && unit < 6) bytes /= 1024.0, ++unit;
  char text[32];
  std::snprintf(text, sizeof text, unit == 0 ? "%.0f %s" : "%.1f %s", bytes, units[unit]);
  return text;
}

}  // namespace

Status checkDemOptions(const DemOptions& options) {
  if (options.spacingM && !(*options.spacingM > 0.0 && std::isfinite(*options.spacingM)))
    return makeError(ErrorKind::InvalidArgument,
                     "spacing " + std::to_string(*options.spacingM) + " m is not a positive, finite number");
  if (!(options.zScale != 0.0 && std::isfinite(options.zScale)))
    return makeError(ErrorKind::InvalidArgument,
                     "height scale " + std::to_string(options.zScale) + " is not a finite, non-zero number");
  if (options.raw && (options.raw->width <= 0 || options.raw->height <= 0))
    return makeError(ErrorKind::InvalidArgument, "raw layout " + std::to_string(options.raw->width) + "x" +
                                                     std::to_string(options.raw->height) + " has no samples");
  return {};
}

std::uint64_t physicalMemoryBytes() {
  const long pages = ::sysconf(_SC_PHYS_PAGES);
  const long pageSize = ::sysconf(_SC_PAGESIZE);
  return pages > 0 && pageSize > 0 ? std::uint64_t(pages) * std::uint64_t(pageSize) : 0;
}

Status checkSpansGround(std::uint64_t width, std::uint64_t height) {
  if (width < 2 || height < 2)
    return makeError(ErrorKind::InvalidData, "a DEM needs at least 2 x 2 samples, this one has " +
                                                 std::to_string(width) + " x " + std::to_string(height));
  return {};
}

Status checkRasterSize(std::uint64_t width, std::uint64_t height, std::uint64_t bytesPerSample,
                       std::uint64_t memoryLimitBytes) {
  if (Status spans = checkSpansGround(width, height); !spans) return spans;
  const std::string size = std::to_string(width) + " x " + std::to_string(height) + " samples";
  // Both come from 32-bit fields at most, so the product does not overflow.
  const std::uint64_t samples = width * height;
  if (width > std::uint64_t(kMaxDemSamples) || height > std::uint64_t(kMaxDemSamples) || samples > kMaxDemSamples)
    return makeError(ErrorKind::OutOfMemory,
                     size + " is more than the " + std::to_string(kMaxDemSamples) + " samples a DEM may have");
  const double needed = double(samples) * double(bytesPerSample);
  const std::uint64_t limit = memoryLimitBytes ? memoryLimitBytes : physicalMemoryBytes();
  if (limit && needed > double(limit))
    return makeError(ErrorKind::OutOfMemory,
                     size + " need " + formatBytes(needed) + " to read, more than the " +
                         (memoryLimitBytes ? "memory limit of " : "machine's physical memory of ") +
                         formatBytes(double(limit)));
  return {};
}

Result<Dem> finishDem(Heightfield field, DemInfo info, const DemOptions& options,
                      std::optional<GroundSpacing> fileSpacing) {
  if (Status spans = checkSpansGround(std::uint64_t(field.width), std::uint64_t(field.height)); !spans)
    return spans.error();
  info.spacingAssumed = false;
  if (options.spacingM) {
    field.spacingX = field.spacingY = *options.spacingM;
  } else if (fileSpacing) {
    field.spacingX = fileSpacing->x;
    field.spacingY = fileSpacing->y;
  } else {
    field.spacingX = field.spacingY = 1.0;
    info.spacingAssumed = true;
  }

  info.voids = fillVoids(field);
  if (info.voids == std::int64_t(field.sampleCount()))
    return makeError(ErrorKind::InvalidData, "all " + std::to_string(info.voids) + " samples are no-data (voids)");
  const auto [low, high] = field.heightRange();
  if (!(std::abs(low) <= kMaxDemHeightM && std::abs(high) <= kMaxDemHeightM)) {
    char range[96];
    std::snprintf(range, sizeof range, "heights reach %.6g .. %.6g m, beyond the +-%.0g m of any terrain", double(low),
                  double(high), kMaxDemHeightM);
    return makeError(ErrorKind::InvalidData, std::string(range) + " (is the height scale right?)");
  }
  info.minM = low;
  info.maxM = high;
  return Dem{std::move(field), std::move(info)};
}

}  // namespace polder::terrain
