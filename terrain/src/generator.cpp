// The terrain generator's relief (fractal noise) and its pipeline; the noise lives in
// generator_noise.hpp, the erosion stages in generator_erosion.cpp.
//
// Relief: fBm for hills; Musgrave's ridged multifractal for mountain ranges; domain warping
// (Quilez, "Domain warping", 2002) to bend ridges out of the noise lattice's grain.
#include <polder/terrain/generator.hpp>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstddef>
#include <new>
#include <optional>
#include <string>

#include "generator_noise.hpp"
#include "generator_pipeline.hpp"

namespace polder::terrain {
namespace {

using noise::fbm;
using noise::octavesFor;
using noise::Point;
using noise::ridgedMultifractal;
using noise::smoothstep;
using noise::streamSeed;

bool finitePositive(double v) { return std::isfinite(v) && v > 0.0; }
bool finiteNonNegative(double v) { return std::isfinite(v) && v >= 0.0; }

}  // namespace

namespace pipeline {

std::optional<Error> validateOptions(const GeneratorOptions& o, int maxSize, const std::string& caller) {
  const auto invalid = [&](const std::string& what) {
    return makeError(ErrorKind::InvalidArgument, caller + ": " + what);
  };
  if (o.size < 2 || o.size > maxSize)
    return invalid("size must be between 2 and " + std::to_string(maxSize) + " samples, got " + std::to_string(o.size));
  if (!(o.spacingM >= 1.0e-3 && o.spacingM <= 1.0e6))
    return invalid("spacing must be between 0.001 and 1e6 metres, got " + std::to_string(o.spacingM));
  const ReliefOptions& r = o.relief;
  if (!std::isfinite(r.baseHeightM) || std::abs(r.baseHeightM) > 1.0e5)
    return invalid("relief.baseHeightM must be finite and within +-1e5 m, got " + std::to_string(r.baseHeightM));
  if (!finiteNonNegative(r.reliefM) || r.reliefM > 1.0e5)
    return invalid("relief.reliefM must be between 0 and 1e5 m, got " + std::to_string(r.reliefM));
  if (!(r.featureSizeM >= 1.0 && r.featureSizeM <= 1.0e7))  // keeps noise coordinates far from overflow
    return invalid("relief.featureSizeM must be between 1 and 1e7 m, got " + std::to_string(r.featureSizeM));
  if (!(r.mountainCoverage >= 0.0 && r.mountainCoverage <= 1.0))
    return invalid("relief.mountainCoverage must be between 0 and 1, got " + std::to_string(r.mountainCoverage));
  if (!finiteNonNegative(r.warp) || r.warp > 10.0)
    return invalid("relief.warp must be between 0 and 10, got " + std::to_string(r.warp));
  if (o.fluvial.iterations < 0 || o.fluvial.iterations > 1000)
    return invalid("fluvial.iterations must be between 0 and 1000, got " + std::to_string(o.fluvial.iterations));
  if (!finiteNonNegative(o.fluvial.strength))
    return invalid("fluvial.strength must be a non-negative number, got " + std::to_string(o.fluvial.strength));
  if (o.thermal.iterations < 0 || o.thermal.iterations > 1000)
    return invalid("thermal.iterations must be between 0 and 1000, got " + std::to_string(o.thermal.iterations));
  if (!finitePositive(o.thermal.talusSlope))
    return invalid("thermal.talusSlope must be a positive rise over run, got " + std::to_string(o.thermal.talusSlope));
  const DropletOptions& d = o.droplets;
  if (!finiteNonNegative(d.dropletsPerSample) || d.dropletsPerSample > 100.0)
    return invalid("droplets.dropletsPerSample must be between 0 and 100, got " + std::to_string(d.dropletsPerSample));
  if (d.maxSteps < 1 || d.maxSteps > 10000)
    return invalid("droplets.maxSteps must be between 1 and 10000, got " + std::to_string(d.maxSteps));
  if (!(d.erosionRate >= 0.0 && d.erosionRate <= 1.0))
    return invalid("droplets.erosionRate must be between 0 and 1, got " + std::to_string(d.erosionRate));
  if (!(d.depositionRate >= 0.0 && d.depositionRate <= 1.0))
    return invalid("droplets.depositionRate must be between 0 and 1, got " + std::to_string(d.depositionRate));
  return std::nullopt;
}

std::function<void(float)> subRange(const std::function<void(float)>& progress, float begin, float end) {
  if (!progress) return {};
  return [&progress, begin, end](float f) { progress(begin + (end - begin) * std::clamp(f, 0.0f, 1.0f)); };
}

}  // namespace pipeline

namespace {

using pipeline::subRange;

std::optional<Error> validate(const GeneratorOptions& options) {
  return pipeline::validateOptions(options, kMaxGeneratorSize, "generateTerrain");
}

// River incision on a grid of half the resolution, its lowering spread back bilinearly: four
// times cheaper, so rivers get enough iterations to breach basin rims, and valleys come out
// at least two samples wide instead of one-sample slots. (A last pass at full resolution
// changed little that the droplets do not redo, for a third more time.)
void erodeFluvialCoarse(Heightfield& field, const FluvialOptions& options, const std::function<void(float)>& progress) {
  const int cw = (field.width + 1) / 2, ch = (field.height + 1) / 2;
  if (cw < 3 || ch < 3 || options.iterations == 0) return erodeFluvial(field, options, progress);
  Heightfield coarse(cw, ch, field.spacingX * 2.0, field.spacingY * 2.0);
  for (int y = 0; y < ch; ++y)
    for (int x = 0; x < cw; ++x)
      coarse.at(x, y) = field.at(std::min(2 * x, field.width - 1), std::min(2 * y, field.height - 1));
  const std::vector<float> before = coarse.heights;
  erodeFluvial(coarse, options, progress);
  for (std::size_t i = 0; i < before.size(); ++i) coarse.heights[i] -= before[i];  // now the change
  for (int y = 0; y < field.height; ++y) {
    const int y0 = std::min(y / 2, ch - 1), y1 = std::min(y0 + 1, ch - 1);
    const float v = (y % 2) ? 0.5f : 0.0f;
    for (int x = 0; x < field.width; ++x) {
      const int x0 = std::min(x / 2, cw - 1), x1 = std::min(x0 + 1, cw - 1);
      const float u = (x % 2) ? 0.5f : 0.0f;
      const float south = coarse.at(x0, y0) + u * (coarse.at(x1, y0) - coarse.at(x0, y0));
      const float north = coarse.at(x0, y1) + u * (coarse.at(x1, y1) - coarse.at(x0, y1));
      field.at(x, y) += south + v * (north - south);
    }
  }
}

}  // namespace

Heightfield generateRelief(const GeneratorOptions& options, const std::function<void(float)>& progress) {
  assert(!validate(options) && "generateRelief: invalid options");
  const ReliefOptions& r = options.relief;
  const int n = options.size;
  Heightfield field(n, n, options.spacingM, options.spacingM);

  const std::uint64_t warpSeedX = streamSeed(options.seed, 0), warpSeedY = streamSeed(options.seed, 1);
  const std::uint64_t maskSeed = streamSeed(options.seed, 2), ridgeSeed = streamSeed(options.seed, 3);
  const std::uint64_t hillSeed = streamSeed(options.seed, 4);
  const int ridgeOctaves = octavesFor(r.featureSizeM, options.spacingM);
  const int hillOctaves = octavesFor(r.featureSizeM * 0.4, options.spacingM);
  const int warpOctaves = std::min(2, octavesFor(r.featureSizeM, options.spacingM));
  // The mask's fBm is about normally distributed with sigma ~0.2; shift its threshold so
  // roughly `mountainCoverage` of the map lies above it.
  const double maskCentre = (0.5 - r.mountainCoverage) * 0.6;
  const double toFeature = options.spacingM / r.featureSizeM;

  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      const Point p{x * toFeature, y * toFeature};
      const Point pw{p.x * 0.7, p.y * 0.7};
      const Point q{p.x + r.warp * fbm(pw, warpOctaves, warpSeedX), p.y + r.warp * fbm(pw, warpOctaves, warpSeedY)};
      const double mask = smoothstep(maskCentre - 0.2, maskCentre + 0.2, fbm({p.x * 0.3, p.y * 0.3}, 3, maskSeed));
      const double ridges = ridgedMultifractal(q, ridgeOctaves, ridgeSeed);
      const double hills = 0.5 + 0.5 * fbm({q.x * 2.5, q.y * 2.5}, hillOctaves, hillSeed);
      // Plains of low hills everywhere; ranges rise out of them where the mask allows, their
      // foothills (low ridge values) gentler than their crests.
      const double h = 0.10 * hills + mask * (0.9 * ridges * ridges + 0.05 * hills);
      field.at(x, y) = float(r.baseHeightM + r.reliefM * h);
    }
    if (progress && (y % 32 == 31 || y == n - 1)) progress(float(y + 1) / float(n));
  }
  return field;
}

void pipeline::erode(Heightfield& field, const GeneratorOptions& options, const std::function<void(float)>& progress) {
  // Shares of the erosion each stage takes, measured at the default options.
  erodeThermal(field, options.thermal);
  erodeFluvialCoarse(field, options.fluvial, subRange(progress, 0.0f, 0.5f));
  erodeDroplets(field, options.droplets, streamSeed(options.seed, 5), subRange(progress, 0.5f, 0.9375f));
  if (options.fillDepressions) fillDepressions(field);
  if (progress) progress(1.0f);
}

Result<Heightfield> generateTerrain(const GeneratorOptions& options, const std::function<void(float)>& progress) {
  if (auto error = validate(options)) return *error;
  try {
    // Shares of the run each stage takes, measured at the default options.
    Heightfield field = generateRelief(options, subRange(progress, 0.0f, 0.2f));
    pipeline::erode(field, options, subRange(progress, 0.2f, 1.0f));
    return field;
  } catch (const std::bad_alloc&) {
    const std::string size = std::to_string(options.size);
    return makeError(ErrorKind::OutOfMemory,
                     "generateTerrain: not enough memory for a " + size + " x " + size + " terrain");
  }
}

}  // namespace polder::terrain
