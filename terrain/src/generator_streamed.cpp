// The streamed generator: an eroded base, interpolated, plus the fine octaves of the relief's
// ridged multifractal (generator_noise.hpp), scaled by the base's slope and erosion.
#include <polder/terrain/generator_streamed.hpp>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstddef>
#include <new>
#include <string>

#include <polder/thread_pool.hpp>

#include "generator_noise.hpp"
#include "generator_pipeline.hpp"

namespace polder::terrain {
namespace {

// Columns a tile of generateRows spans: the unit of parallel work, and of the noise caches.
constexpr int kTileColumns = 256;

// E[(1 - |n|)^2 w] of the ridged multifractal's octaves, the first with weight 1 (measured
// over 4 million samples): the detail subtracts them so it adds no mean height.
constexpr double kRidgeMean[] = {0.5994, 0.5241, 0.4811, 0.4519, 0.4301, 0.4130};
constexpr int kRidgeMeans = int(sizeof kRidgeMean / sizeof kRidgeMean[0]);

// The detail's slope per unit of base slope, and the erosion depth (in base samples' worth
// of height at slope 1) over which the detail fades. With these, a 1025^2 raster at 10 m over a
// 129^2 base has a mean slope of 0.15 where generateTerrain's full erosion gives 0.18, and the
// base alone 0.08.
constexpr double kDetailPerSlope = 2.0;
constexpr double kErosionFade = 0.05;

// Catmull-Rom weights of p[-1], p[0], p[1], p[2] at t in [0, 1): C1, and exact at the samples.
struct CubicWeights {
  double w[4];
};
CubicWeights catmullRom(double t) {
  const double t2 = t * t, t3 = t2 * t;
  return {{0.5 * (-t + 2.0 * t2 - t3), 0.5 * (2.0 - 5.0 * t2 + 3.0 * t3), 0.5 * (t + 4.0 * t2 - 3.0 * t3),
           0.5 * (t3 - t2)}};
}

// The base sample to the left of (or at) u, kept one short of the last so p[2] exists, and
// the weights at u.
struct CubicSpan {
  int first;  // index of p[0]
  CubicWeights weights;
};
CubicSpan cubicSpan(double u, int samples) {
  const int i = std::min(int(u), samples - 2);
  return {i, catmullRom(u - double(i))};
}

// Slope of the base per sample, with one-sided differences on its border.
double slopeAt(const Heightfield& f, int x, int y) {
  const int xl = std::max(x - 1, 0), xr = std::min(x + 1, f.width - 1);
  const int yl = std::max(y - 1, 0), yr = std::min(y + 1, f.height - 1);
  const double gx = (double(f.at(xr, y)) - f.at(xl, y)) / ((xr - xl) * f.spacingX);
  const double gy = (double(f.at(x, yr)) - f.at(x, yl)) / ((yr - yl) * f.spacingY);
  return std::sqrt(gx * gx + gy * gy);
}

// The detail's slope at each base sample: the base's slope, faded where erosion cut or
// filled (river beds, valley floors and lakes are smooth), then blurred by a 3x3 binomial so
// the amplitude varies as smoothly as the base.
std::vector<float> detailRoughness(const Heightfield& relief, const Heightfield& eroded) {
  const int w = eroded.width, h = eroded.height;
  std::vector<float> raw(eroded.sampleCount());
  const double fadeDepth = kErosionFade * eroded.spacingX;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t i = eroded.index(x, y);
      const double moved = (double(relief.heights[i]) - eroded.heights[i]) / fadeDepth;
      raw[i] = float(kDetailPerSlope * slopeAt(eroded, x, y) / (1.0 + moved * moved));
    }
  std::vector<float> rows(raw.size()), out(raw.size());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t i = eroded.index(x, y);
      rows[i] = 0.25f * (raw[eroded.index(std::max(x - 1, 0), y)] + raw[eroded.index(std::min(x + 1, w - 1), y)]) +
                0.5f * raw[i];
    }
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t i = eroded.index(x, y);
      out[i] = 0.25f * (rows[eroded.index(x, std::max(y - 1, 0))] + rows[eroded.index(x, std::min(y + 1, h - 1))]) +
               0.5f * rows[i];
    }
  return out;
}

}  // namespace

Result<StreamedTerrain> StreamedTerrain::create(const GeneratorOptions& options, int baseSize,
                                                const std::function<void(float)>& progress) {
  if (auto error = pipeline::validateOptions(options, kMaxStreamedGeneratorSize, "StreamedTerrain")) return *error;
  if (baseSize == 0) baseSize = kDefaultStreamedBaseSize;
  baseSize = std::min(baseSize, options.size);
  if (baseSize < 4 || baseSize > kMaxGeneratorSize)
    return makeError(ErrorKind::InvalidArgument, "StreamedTerrain: the base size must be between 4 and " +
                                                     std::to_string(kMaxGeneratorSize) + " samples, got " +
                                                     std::to_string(baseSize));
  GeneratorOptions baseOptions = options;
  baseOptions.size = baseSize;
  baseOptions.spacingM = options.spacingM * double(options.size - 1) / double(baseSize - 1);
  if (auto error = pipeline::validateOptions(baseOptions, kMaxGeneratorSize, "StreamedTerrain (base)")) return *error;

  StreamedTerrain terrain;
  terrain.m_options = options;
  try {
    const Heightfield relief = generateRelief(baseOptions, pipeline::subRange(progress, 0.0f, 0.2f));
    terrain.m_base = relief;
    pipeline::erode(terrain.m_base, baseOptions, pipeline::subRange(progress, 0.2f, 1.0f));
    terrain.m_roughness = detailRoughness(relief, terrain.m_base);
  } catch (const std::bad_alloc&) {
    const std::string size = std::to_string(baseSize);
    return makeError(ErrorKind::OutOfMemory,
                     "StreamedTerrain: not enough memory for a " + size + " x " + size + " eroded base");
  }
  terrain.m_toBase = double(baseSize - 1) / double(options.size - 1);
  // The relief's ridges run octaves down to four samples of its own spacing: the base holds
  // those down to four base samples, the detail the rest.
  terrain.m_firstOctave = noise::octavesFor(options.relief.featureSizeM, baseOptions.spacingM);
  terrain.m_endOctave = noise::octavesFor(options.relief.featureSizeM, options.spacingM);
  terrain.m_toFeature = options.spacingM / options.relief.featureSizeM;
  return terrain;
}

// A base value with linear extrapolation one sample beyond the border, so the interpolation
// keeps its slope up to the edge.
double StreamedTerrain::baseAt(const std::vector<float>& values, int i, int j) const {
  const int n = m_base.width;
  if (i < 0) return 2.0 * baseAt(values, 0, j) - baseAt(values, 1, j);
  if (i >= n) return 2.0 * baseAt(values, n - 1, j) - baseAt(values, n - 2, j);
  if (j < 0) return 2.0 * baseAt(values, i, 0) - baseAt(values, i, 1);
  if (j >= n) return 2.0 * baseAt(values, i, n - 1) - baseAt(values, i, n - 2);
  return values[std::size_t(j) * std::size_t(n) + std::size_t(i)];
}

void StreamedTerrain::generateTile(int x0, int x1, int y0, int count, std::span<float> out) const {
  const int n = m_base.width, columns = x1 - x0, size = m_options.size;
  // The base rows under the band, each interpolated along x to the tile's columns; then every
  // row is a cubic of four of them. Each value depends on its own column and row only, so
  // bands and tiles of any size give the same samples.
  const int jFirst = cubicSpan(double(y0) * m_toBase, n).first - 1;
  const int jLast = cubicSpan(double(y0 + count - 1) * m_toBase, n).first + 2;
  const int baseRows = jLast - jFirst + 1;
  std::vector<double> heights(std::size_t(baseRows) * std::size_t(columns));
  std::vector<double> roughness(heights.size());
  std::vector<CubicSpan> spans(std::size_t(columns), CubicSpan{});
  for (int c = 0; c < columns; ++c) spans[std::size_t(c)] = cubicSpan(double(x0 + c) * m_toBase, n);
  for (int r = 0; r < baseRows; ++r)
    for (int c = 0; c < columns; ++c) {
      const CubicSpan& s = spans[std::size_t(c)];
      double h = 0.0, k = 0.0;
      for (int t = 0; t < 4; ++t) {
        h += s.weights.w[t] * baseAt(m_base.heights, s.first - 1 + t, jFirst + r);
        k += s.weights.w[t] * baseAt(m_roughness, s.first - 1 + t, jFirst + r);
      }
      heights[std::size_t(r) * std::size_t(columns) + std::size_t(c)] = h;
      roughness[std::size_t(r) * std::size_t(columns) + std::size_t(c)] = k;
    }

  // The detail octaves: their noise coordinates as linear maps of the sample's (x, y), and
  // their wavelengths in metres.
  struct Octave {
    noise::Point alongX, alongY;  // coordinates per sample east and per sample north
    double wavelengthM;
    double mean;
  };
  std::vector<Octave> octaves;
  std::vector<noise::CachedGradientNoise> noises;
  {
    noise::Point ex{m_toFeature, 0.0}, ey{0.0, m_toFeature};
    double wavelength = m_options.relief.featureSizeM;
    const std::uint64_t ridgeSeed = noise::streamSeed(m_options.seed, 3);
    for (int i = 0; i < m_endOctave; ++i) {
      if (i >= m_firstOctave) {
        const int chain = std::min(i - m_firstOctave, kRidgeMeans - 1);
        octaves.push_back({ex, ey, wavelength, kRidgeMean[chain]});
        noises.emplace_back(ridgeSeed + std::uint64_t(i));
      }
      ex = noise::nextOctave(ex);
      ey = noise::nextOctave(ey);
      wavelength *= 0.5;
    }
  }

  for (int row = 0; row < count; ++row) {
    const int y = y0 + row;
    const CubicSpan s = cubicSpan(double(y) * m_toBase, n);
    const std::size_t r0 = std::size_t(s.first - 1 - jFirst) * std::size_t(columns);
    float* line = out.data() + std::size_t(row) * std::size_t(size) + std::size_t(x0);
    for (int c = 0; c < columns; ++c) {
      double h = 0.0, k = 0.0;
      for (int t = 0; t < 4; ++t) {
        const std::size_t at = r0 + std::size_t(t) * std::size_t(columns) + std::size_t(c);
        h += s.weights.w[t] * heights[at];
        k += s.weights.w[t] * roughness[at];
      }
      if (k > 0.0) {
        const int x = x0 + c;
        double detail = 0.0, weight = 1.0;
        for (std::size_t o = 0; o < octaves.size(); ++o) {
          const Octave& octave = octaves[o];
          const double px = x * octave.alongX.x + y * octave.alongY.x;
          const double py = x * octave.alongX.y + y * octave.alongY.y;
          const double signal = noise::ridgeSignal(noises[o](px, py)) * weight;
          detail += octave.wavelengthM * (signal - octave.mean);
          weight = std::clamp(signal * 2.0, 0.0, 1.0);
        }
        h += k * detail;
      }
      line[c] = float(h);
    }
  }
}

Status StreamedTerrain::generateRows(int y0, int count, std::span<float> out, core::ThreadPool* pool) const {
  const int size = m_options.size;
  if (y0 < 0 || count < 0 || y0 > size - count)
    return makeError(ErrorKind::InvalidArgument, "StreamedTerrain: rows " + std::to_string(y0) + " + " +
                                                     std::to_string(count) + " outside the " + std::to_string(size) +
                                                     " rows");
  if (out.size() != std::size_t(count) * std::size_t(size))
    return makeError(ErrorKind::InvalidArgument, "StreamedTerrain: row buffer of the wrong size");
  if (count == 0) return {};
  const std::size_t tiles = std::size_t((size + kTileColumns - 1) / kTileColumns);
  const auto run = [&](std::size_t begin, std::size_t end) {
    for (std::size_t t = begin; t < end; ++t) {
      const int x0 = int(t) * kTileColumns;
      generateTile(x0, std::min(x0 + kTileColumns, size), y0, count, out);
    }
  };
  try {
    if (pool)
      pool->forRanges(tiles, 1, run);
    else
      run(0, tiles);
  } catch (const std::bad_alloc&) {
    return makeError(ErrorKind::OutOfMemory,
                     "StreamedTerrain: not enough memory for a band of " + std::to_string(count) + " rows");
  }
  return {};
}

}  // namespace polder::terrain
