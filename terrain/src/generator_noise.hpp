// The generator's noise: 2D gradient noise (Perlin 2002, quintic fade) over an integer-lattice
// hash (splitmix64's finaliser, Steele et al. 2014); fBm; Musgrave's ridged multifractal
// ("Texturing and Modeling: A Procedural Approach", ch. 16). Each octave is rotated by a
// fixed angle (cos 0.8, sin 0.6) so octave lattices never align. Shared by the relief
// (generator.cpp) and the streamed detail (generator_streamed.cpp); IEEE + - * / only, so
// every machine computes the same values.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <polder/mix_bits.hpp>

namespace polder::terrain::noise {

// Independent seeds for the noise layers (and the droplets), derived from the user's seed.
inline std::uint64_t streamSeed(std::uint64_t seed, std::uint64_t stream) {
  return mixBits(seed + 0x9e3779b97f4a7c15ULL * (stream + 1));
}

// Sixteen unit gradients at multiples of 22.5 degrees, as literals (no libm at run time).
inline constexpr double kGradX[16] = {1.0,         0.92387953,  0.70710678, 0.38268343,  0.0,         -0.38268343,
                                      -0.70710678, -0.92387953, -1.0,       -0.92387953, -0.70710678, -0.38268343,
                                      0.0,         0.38268343,  0.70710678, 0.92387953};
inline constexpr double kGradY[16] = {0.0,        0.38268343,  0.70710678,  0.92387953,  1.0,         0.92387953,
                                      0.70710678, 0.38268343,  0.0,         -0.38268343, -0.70710678, -0.92387953,
                                      -1.0,       -0.92387953, -0.70710678, -0.38268343};

inline unsigned gradientIndex(std::int64_t ix, std::int64_t iy, std::uint64_t seed) {
  const std::uint64_t h =
      mixBits(seed ^ (std::uint64_t(ix) * 0x9e3779b97f4a7c15ULL) ^ (std::uint64_t(iy) * 0xc2b2ae3d27d4eb4fULL));
  return unsigned(h >> 60);
}

inline double fade(double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }

// The noise inside one lattice cell, from its corners' gradients (south-west, south-east,
// north-west, north-east) and the position (tx, ty) in the cell.
inline double cellNoise(const unsigned k[4], double tx, double ty) {
  const double n00 = kGradX[k[0]] * tx + kGradY[k[0]] * ty;
  const double n10 = kGradX[k[1]] * (tx - 1.0) + kGradY[k[1]] * ty;
  const double n01 = kGradX[k[2]] * tx + kGradY[k[2]] * (ty - 1.0);
  const double n11 = kGradX[k[3]] * (tx - 1.0) + kGradY[k[3]] * (ty - 1.0);
  const double u = fade(tx), v = fade(ty);
  const double south = n00 + u * (n10 - n00);
  const double north = n01 + u * (n11 - n01);
  return 1.4 * (south + v * (north - south));
}

inline void cellGradients(std::int64_t ix, std::int64_t iy, std::uint64_t seed, unsigned k[4]) {
  k[0] = gradientIndex(ix, iy, seed);
  k[1] = gradientIndex(ix + 1, iy, seed);
  k[2] = gradientIndex(ix, iy + 1, seed);
  k[3] = gradientIndex(ix + 1, iy + 1, seed);
}

// Gradient noise, roughly in [-1, 1] (unit gradients reach about 0.7; scaled up).
inline double gradientNoise(double x, double y, std::uint64_t seed) {
  const double fx = std::floor(x), fy = std::floor(y);
  unsigned k[4];
  cellGradients(std::int64_t(fx), std::int64_t(fy), seed, k);
  return cellNoise(k, x - fx, y - fy);
}

// The same values as gradientNoise, for a run of nearby points: the corner gradients are
// hashed again only when a point falls in another lattice cell than the last one.
class CachedGradientNoise {
 public:
  explicit CachedGradientNoise(std::uint64_t seed) : m_seed(seed) {}
  double operator()(double x, double y) {
    // floor() for |x| < 2^62 without the libm call; the same value.
    auto ix = std::int64_t(x), iy = std::int64_t(y);
    ix -= double(ix) > x ? 1 : 0;
    iy -= double(iy) > y ? 1 : 0;
    if (ix != m_ix || iy != m_iy || !m_valid) {
      cellGradients(ix, iy, m_seed, m_k);
      m_ix = ix, m_iy = iy, m_valid = true;
    }
    return cellNoise(m_k, x - double(ix), y - double(iy));
  }

 private:
  std::uint64_t m_seed;
  std::int64_t m_ix = 0, m_iy = 0;
  bool m_valid = false;
  unsigned m_k[4] = {0, 0, 0, 0};
};

struct Point {
  double x, y;
};

// The next octave's coordinates: doubled frequency, rotated by atan2(0.6, 0.8).
inline Point nextOctave(Point p) { return {2.0 * (0.8 * p.x - 0.6 * p.y), 2.0 * (0.6 * p.x + 0.8 * p.y)}; }

// Fractional Brownian motion, normalised by its amplitude sum: about [-1, 1].
inline double fbm(Point p, int octaves, std::uint64_t seed) {
  double sum = 0.0, amplitude = 1.0, total = 0.0;
  for (int i = 0; i < octaves; ++i) {
    sum += amplitude * gradientNoise(p.x, p.y, seed + std::uint64_t(i));
    total += amplitude;
    amplitude *= 0.5;
    p = nextOctave(p);
  }
  return sum / total;
}

// The ridge signal of one octave, (1 - |n|)^2, before Musgrave's weighting.
inline double ridgeSignal(double n) {
  const double s = 1.0 - std::abs(n);
  return s * s;
}

// Musgrave's ridged multifractal with H = 1, lacunarity 2, offset 1, gain 2: each octave's
// ridge signal (1 - |n|)^2 is weighted by the previous one, so detail gathers on the ridges
// and valleys stay smooth. About [0, 1].
inline double ridgedMultifractal(Point p, int octaves, std::uint64_t seed) {
  double sum = 0.0, amplitude = 1.0, weight = 1.0;
  for (int i = 0; i < octaves; ++i) {
    double signal = 1.0 - std::abs(gradientNoise(p.x, p.y, seed + std::uint64_t(i)));
    signal *= signal * weight;
    sum += signal * amplitude;
    weight = std::clamp(signal * 2.0, 0.0, 1.0);
    amplitude *= 0.5;
    p = nextOctave(p);
  }
  return 0.5 * sum;
}

inline double smoothstep(double edge0, double edge1, double x) {
  const double t = std::clamp((x - edge0) / (edge1 - edge0), 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

// Octaves from `wavelengthM` down to no finer than two samples (finer ones would alias).
inline int octavesFor(double wavelengthM, double spacingM) {
  int octaves = 1;
  while (octaves < 16 && wavelengthM > 4.0 * spacingM) {
    wavelengthM *= 0.5;
    ++octaves;
  }
  return octaves;
}

}  // namespace polder::terrain::noise
