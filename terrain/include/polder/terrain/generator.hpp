// A synthetic terrain generator: the sample DEMs behind `polder gen --size N --seed S --spacing M`.
//
// The pipeline, in the order generateTerrain runs it:
//   1. relief   - domain-warped fractal noise: Musgrave's ridged multifractal for mountain
//                 ranges over fBm hills, a low-frequency mask deciding where ranges rise;
//   2. thermal  - talus relaxation: slopes steeper than the talus angle slump towards it;
//   3. fluvial  - stream-power incision (Braun & Willett 2013) routed over a Priority-Flood
//                 (Barnes et al. 2014), on a grid of half the resolution: rivers cut valleys,
//                 breach the rims of closed basins and silt up the lakes behind them;
//   4. droplets - particle hydraulic erosion (Beyer 2015, after Mei et al. 2007): gullies and
//                 sediment at the sample scale;
//   5. fill     - epsilon depression filling: every sample drains to the map's border.
//
// Features are sized in metres, not samples: the same seed and spacing give the same relief
// at every size (a larger size shows more of it), and slopes stay plausible at any spacing.
// The output is a pure function of the options: the generator uses its own hash and PRNG
// (never std:: distributions), IEEE arithmetic only (+ - * / sqrt, no libm transcendentals)
// and one thread, so a seed gives the same heights on every run and machine, with GCC or
// Clang at any optimisation level. Only fused multiply-adds change them: where the compiler
// may contract a*b+c (x86-64 with -march=native or -mfma, AArch64 by default), build these
// files with -ffp-contract=off to keep the heights identical.
#pragma once

#include <cstdint>
#include <functional>

#include <polder/result.hpp>
#include <polder/terrain/heightfield.hpp>

namespace polder::terrain {

struct ReliefOptions {
  double baseHeightM = 150.0;     // height of the lowest plains
  double reliefM = 2350.0;        // from the plains to the highest peaks (about)
  double featureSizeM = 12000.0;  // wavelength of the largest mountain ridges, 1..1e7 m
  double mountainCoverage = 0.5;  // 0..1: share of the map covered by mountain ranges
  double warp = 0.35;             // domain warp, in units of featureSizeM: bends ridges
};

struct FluvialOptions {
  int iterations = 8;     // 0 disables river incision (generateTerrain runs them at half resolution)
  double strength = 0.2;  // K*dt of the stream-power law, per sqrt(upstream samples)
};

struct ThermalOptions {
  int iterations = 12;       // 0 disables talus relaxation
  double talusSlope = 0.75;  // steepest stable slope, rise over run (about 37 degrees)
};

struct DropletOptions {
  double dropletsPerSample = 0.3;  // 0 disables droplet erosion
  int maxSteps = 32;               // lifetime of one droplet, in samples travelled
  double erosionRate = 0.3;        // share of the free capacity taken from the ground per step
  double depositionRate = 0.3;     // share of the excess sediment dropped per step
};

struct GeneratorOptions {
  int size = 1025;  // samples per side, 2..kMaxGeneratorSize
  std::uint64_t seed = 1;
  double spacingM = 30.0;  // metres between samples, 0.001..1e6
  ReliefOptions relief;
  FluvialOptions fluvial;
  ThermalOptions thermal;
  DropletOptions droplets;
  bool fillDepressions = true;  // leave no pit: every sample drains to the border
};

inline constexpr int kMaxGeneratorSize = 16385;

// A size x size heightfield in metres (spacing spacingM both ways, row 0 south). `progress`,
// when given, is called on the calling thread with a fraction rising from 0 to 1.
// InvalidArgument for options out of range (the message names the option); OutOfMemory when
// the working buffers cannot be allocated.
Result<Heightfield> generateTerrain(const GeneratorOptions& options, const std::function<void(float)>& progress = {});

// The stages generateTerrain runs, for tools that want some of them (or erode their own DEM),
// each at the resolution of the field it is given. They expect valid options (asserted), as
// generateTerrain checks them; `progress` reports 0..1 of the stage.
Heightfield generateRelief(const GeneratorOptions& options, const std::function<void(float)>& progress = {});
void erodeFluvial(Heightfield& field, const FluvialOptions& options, const std::function<void(float)>& progress = {});
void erodeThermal(Heightfield& field, const ThermalOptions& options);
void erodeDroplets(Heightfield& field, const DropletOptions& options, std::uint64_t seed,
                   const std::function<void(float)>& progress = {});
// Raises every sample that has no way down to the border until it has one, by a slope of
// a millimetre per sample (Priority-Flood+Epsilon, Barnes et al. 2014).
void fillDepressions(Heightfield& field);

}  // namespace polder::terrain
