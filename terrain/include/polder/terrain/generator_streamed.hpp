// The terrain generator for rasters larger than memory: synthesised detail over a coarser
// eroded base, produced a band of rows at a time.
//
// generateTerrain (generator.hpp) erodes the whole raster at once, which needs it all in
// memory and grows as size^2 in time. StreamedTerrain runs that pipeline once on a base of
// baseSize^2 samples covering the same extent (spacing spacingM * (size - 1) / (baseSize - 1)),
// then makes any rows of the full raster on demand: a C1 interpolation of the base
// (Catmull-Rom, Catmull & Rom 1974) plus the octaves of Musgrave's ridged multifractal that
// the base is too coarse to hold, with the relief's own noise. Their amplitude follows the
// base: proportional to its slope and falling where erosion moved ground, so valley floors
// and river beds stay smooth while the ridges and steep flanks get rough. Unlike
// generateTerrain's output, the full resolution is not depression-filled: the detail leaves
// small pits; the base drains to the border.
//
// Determinism: every sample is a pure function of the options, the base size and its own
// coordinates, under the same rules as generator.hpp (own hash, IEEE + - * / sqrt, same
// heights on every machine): rows come out the same whichever bands they are asked in, on
// any number of threads.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include <polder/result.hpp>
#include <polder/terrain/generator.hpp>
#include <polder/terrain/heightfield.hpp>

namespace polder::core {
class ThreadPool;
}

namespace polder::terrain {

// The largest size StreamedTerrain makes (a float raster of this size is 69 GB).
inline constexpr int kMaxStreamedGeneratorSize = 131073;
// The base it erodes by default: about a minute and 400 MB.
inline constexpr int kDefaultStreamedBaseSize = 4097;

class StreamedTerrain {
 public:
  // Erodes the base (the long part: generateTerrain at baseSize). `baseSize` 0 means
  // kDefaultStreamedBaseSize; it is capped at options.size, and must be at least 4.
  // `progress` as generateTerrain's. InvalidArgument for options out of range (the message
  // names the option; sizes up to kMaxStreamedGeneratorSize), OutOfMemory when the base does
  // not fit.
  static Result<StreamedTerrain> create(const GeneratorOptions& options, int baseSize = 0,
                                        const std::function<void(float)>& progress = {});

  int size() const { return m_options.size; }
  double spacingM() const { return m_options.spacingM; }
  // The eroded base, spacing base().spacingX, the same extent as the full raster.
  const Heightfield& base() const { return m_base; }

  // Rows [y0, y0 + count) of the size x size raster (row 0 south) into `out`, count * size()
  // metres, row y0 first, each row west to east. Columns are split into tiles that run on
  // `pool` when given (on the calling thread otherwise). InvalidArgument for rows outside
  // the raster or an `out` of another size.
  Status generateRows(int y0, int count, std::span<float> out, core::ThreadPool* pool = nullptr) const;

 private:
  StreamedTerrain() = default;
  void generateTile(int x0, int x1, int y0, int count, std::span<float> out) const;
  double baseAt(const std::vector<float>& values, int i, int j) const;

  GeneratorOptions m_options;
  Heightfield m_base;
  std::vector<float> m_roughness;  // per base sample: the detail's slope, rise over run
  double m_toBase = 1.0;           // base samples per full-resolution sample
  int m_firstOctave = 0;           // the ridged multifractal's octaves the detail adds
  int m_endOctave = 0;
  double m_toFeature = 1.0;  // full-resolution samples to the relief's noise coordinates
};

}  // namespace polder::terrain
