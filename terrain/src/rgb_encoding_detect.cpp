// Terrain-RGB and Terrarium put Earth's heights in disjoint parts of RGB space: Terrain-RGB
// keeps R in 0..2 for -10 km..+9 km, Terrarium keeps R in 85..163. Decoded the wrong way,
// heights land far outside -11..9 km, so the range alone decides for real data; smoothness
// (mean step between neighbours) breaks a tie should both look plausible.
#include <polder/terrain/rgb_encoding.hpp>

#include <cmath>
#include <initializer_list>
#include <string>

namespace polder::terrain {
namespace {

constexpr double kLowestEarthM = -11000.0;      // below the Challenger Deep
constexpr double kHighestEarthM = 9000.0;       // above Everest
constexpr double kPlausibleFraction = 0.99;     // allow for a few spikes
constexpr std::size_t kProbeSamples = 1 << 18;  // enough to decide; keeps 4096^2 tiles fast

struct Plausibility {
  double inRange = 0.0;    // fraction of probed samples within Earth's heights
  double roughness = 0.0;  // mean |step| to the right and down neighbours
};

const std::uint8_t* pixelAt(const RgbView& view, int x, int y) {
  return view.pixels + (std::size_t(y) * std::size_t(view.width) + std::size_t(x)) * std::size_t(view.channels);
}

// Transparent pixels carry no height (tiles often mark missing data so).
bool transparent(const RgbView& view, const std::uint8_t* p) { return view.channels == 4 && p[3] == 0; }

template <class Decode>
Plausibility measure(const RgbView& view, int stride, Decode decode) {
  std::size_t probed = 0, inRange = 0, steps = 0;
  double stepSum = 0.0;
  for (int y = 0; y < view.height; y += stride) {
    for (int x = 0; x < view.width; x += stride) {
      const std::uint8_t* p = pixelAt(view, x, y);
      if (transparent(view, p)) continue;
      const double h = decode(p[0], p[1], p[2]);
      ++probed;
      if (h >= kLowestEarthM && h <= kHighestEarthM) ++inRange;
      for (const std::uint8_t* q : {x + 1 < view.width ? pixelAt(view, x + 1, y) : nullptr,
                                    y + 1 < view.height ? pixelAt(view, x, y + 1) : nullptr}) {
        if (!q || transparent(view, q)) continue;
        stepSum += std::abs(decode(q[0], q[1], q[2]) - h);
        ++steps;
      }
    }
  }
  return {probed ? double(inRange) / double(probed) : 0.0, steps ? stepSum / double(steps) : 0.0};
}

bool isGrey(const RgbView& view) {
  const std::size_t count = std::size_t(view.width) * std::size_t(view.height);
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint8_t* p = view.pixels + i * std::size_t(view.channels);
    if (!transparent(view, p) && (p[0] != p[1] || p[1] != p[2])) return false;
  }
  return true;
}

}  // namespace

Result<HeightEncoding> detectRgbEncoding(const RgbView& view) {
  if (isGrey(view)) return HeightEncoding::Greyscale;
  const std::size_t count = std::size_t(view.width) * std::size_t(view.height);
  int stride = 1;
  while (count / (std::size_t(stride) * std::size_t(stride)) > kProbeSamples) ++stride;

  const Plausibility rgb = measure(view, stride, decodeTerrainRgb);
  const Plausibility terrarium = measure(view, stride, decodeTerrarium);
  const bool rgbPlausible = rgb.inRange >= kPlausibleFraction;
  const bool terrariumPlausible = terrarium.inRange >= kPlausibleFraction;
  if (rgbPlausible && terrariumPlausible)
    return rgb.roughness <= terrarium.roughness ? HeightEncoding::TerrainRgb : HeightEncoding::Terrarium;
  if (rgbPlausible) return HeightEncoding::TerrainRgb;
  if (terrariumPlausible) return HeightEncoding::Terrarium;
  const auto percent = [](double f) { return std::to_string(int(std::lround(f * 100.0))); };
  return makeError(ErrorKind::InvalidData, "RGB image is neither Terrain-RGB (" + percent(rgb.inRange) +
                                               "% of heights plausible) nor Terrarium (" + percent(terrarium.inRange) +
                                               "% plausible); pass the encoding explicitly");
}

}  // namespace polder::terrain
