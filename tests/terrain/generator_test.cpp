#include <polder/terrain/generator.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numeric>
#include <vector>

#include <gtest/gtest.h>

namespace polder::terrain {
namespace {

// 257 samples 60 m apart: 15 km, large enough for mountains and valleys, small enough to be fast.
GeneratorOptions smallOptions(std::uint64_t seed) {
  GeneratorOptions options;
  options.size = 257;
  options.spacingM = 60.0;
  options.seed = seed;
  return options;
}

GeneratorOptions reliefOnly(GeneratorOptions options) {
  options.fluvial.iterations = 0;
  options.thermal.iterations = 0;
  options.droplets.dropletsPerSample = 0.0;
  options.fillDepressions = false;
  return options;
}

Heightfield generate(const GeneratorOptions& options) {
  Result<Heightfield> result = generateTerrain(options);
  EXPECT_TRUE(result.ok()) << result.error().message;
  return result.ok() ? std::move(result).value() : Heightfield();
}

std::uint64_t fnv1a(const std::vector<float>& heights) {
  std::uint64_t hash = 0xcbf29ce484222325ULL;
  for (const float h : heights) {
    std::uint32_t bits;
    std::memcpy(&bits, &h, sizeof bits);
    for (int b = 0; b < 4; ++b) hash = (hash ^ ((bits >> (8 * b)) & 0xffu)) * 0x100000001b3ULL;
  }
  return hash;
}

// Interior samples with no strictly lower neighbour (of eight): where water has nowhere to go.
int countPits(const Heightfield& field) {
  int pits = 0;
  for (int y = 1; y + 1 < field.height; ++y)
    for (int x = 1; x + 1 < field.width; ++x) {
      bool lower = false;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) lower = lower || field.at(x + dx, y + dy) < field.at(x, y);
      pits += lower ? 0 : 1;
    }
  return pits;
}

// Share of the samples lying more than a metre below the level at which water could leave
// them: the closed basins (lakes, were they filled).
double lakeFraction(const Heightfield& field) {
  Heightfield filled = field;
  fillDepressions(filled);
  std::size_t lake = 0;
  for (std::size_t i = 0; i < field.heights.size(); ++i) lake += filled.heights[i] - field.heights[i] > 1.0f ? 1 : 0;
  return double(lake) / double(field.heights.size());
}

double meanSlope(const Heightfield& field) {
  double sum = 0.0;
  std::size_t n = 0;
  for (int y = 0; y < field.height; ++y)
    for (int x = 0; x < field.width; ++x) {
      if (x + 1 < field.width) sum += std::abs(field.at(x + 1, y) - field.at(x, y)) / field.spacingX, ++n;
      if (y + 1 < field.height) sum += std::abs(field.at(x, y + 1) - field.at(x, y)) / field.spacingY, ++n;
    }
  return sum / double(n);
}

// D8 flow accumulation (samples draining through each sample), highest sample first.
std::vector<double> flowAccumulation(const Heightfield& field) {
  std::vector<std::size_t> order(field.sampleCount());
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return field.heights[a] > field.heights[b] || (field.heights[a] == field.heights[b] && a < b);
  });
  std::vector<double> area(field.sampleCount(), 1.0);
  for (const std::size_t i : order) {
    const int x = int(i % std::size_t(field.width)), y = int(i / std::size_t(field.width));
    double steepest = 0.0;
    std::size_t receiver = i;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int nx = x + dx, ny = y + dy;
        if ((dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= field.width || ny >= field.height) continue;
        const double slope = (field.at(x, y) - field.at(nx, ny)) / std::hypot(dx * field.spacingX, dy * field.spacingY);
        if (slope > steepest) steepest = slope, receiver = field.index(nx, ny);
      }
    if (receiver != i) area[receiver] += area[i];
  }
  return area;
}

// How far rivers sit below their surroundings: over samples draining at least `minArea`
// samples, the mean of (7 x 7 neighbourhood mean - height), in metres.
double channelIncision(const Heightfield& field, double minArea) {
  const std::vector<double> area = flowAccumulation(field);
  double sum = 0.0;
  std::size_t n = 0;
  for (int y = 3; y + 3 < field.height; ++y)
    for (int x = 3; x + 3 < field.width; ++x) {
      if (area[field.index(x, y)] < minArea) continue;
      double mean = 0.0;
      for (int dy = -3; dy <= 3; ++dy)
        for (int dx = -3; dx <= 3; ++dx) mean += field.at(x + dx, y + dy);
      sum += mean / 49.0 - field.at(x, y);
      ++n;
    }
  return n > 0 ? sum / double(n) : 0.0;
}

TEST(Generator, SameSeedGivesIdenticalHeightsAndOtherSeedsDiffer) {
  GeneratorOptions options = smallOptions(7);
  options.size = 129;
  const Heightfield a = generate(options), b = generate(options);
  ASSERT_EQ(a.heights.size(), b.heights.size());
  EXPECT_EQ(0, std::memcmp(a.heights.data(), b.heights.data(), a.heights.size() * sizeof(float)));

  options.seed = 8;
  const Heightfield c = generate(options);
  std::size_t differ = 0;
  for (std::size_t i = 0; i < a.heights.size(); ++i) differ += a.heights[i] != c.heights[i] ? 1 : 0;
  EXPECT_GT(differ, a.heights.size() * 9 / 10);
}

TEST(Generator, HeightsAreTheSameOnEveryMachine) {
  // The generator uses its own hash, PRNG and IEEE arithmetic only, so these heights are a
  // fixed function of the options. If this fails after a deliberate change to the generator,
  // update the value (and regenerate the bundled sample DEMs); otherwise something made the
  // output depend on the platform (a libm call, a std:: distribution, FMA contraction).
  GeneratorOptions options;
  options.size = 65;
  options.seed = 42;
  options.spacingM = 50.0;
  EXPECT_EQ(fnv1a(generate(options).heights), 0xef1ccf3738268391ULL);
}

TEST(Generator, HonoursSizeAndSpacing) {
  for (const int size : {2, 3, 17, 100}) {
    GeneratorOptions options = smallOptions(3);
    options.size = size;
    options.spacingM = 12.5;
    const Heightfield field = generate(options);
    EXPECT_EQ(field.width, size);
    EXPECT_EQ(field.height, size);
    EXPECT_EQ(field.spacingX, 12.5);
    EXPECT_EQ(field.spacingY, 12.5);
    ASSERT_EQ(field.heights.size(), std::size_t(size) * std::size_t(size));
    for (const float h : field.heights) ASSERT_TRUE(std::isfinite(h));
  }
}

TEST(Generator, RejectsAbsurdOptionsAndNamesThem) {
  auto expectRejected = [](const GeneratorOptions& options, const char* word) {
    const Result<Heightfield> result = generateTerrain(options);
    ASSERT_FALSE(result.ok()) << word;
    EXPECT_EQ(result.error().kind, ErrorKind::InvalidArgument) << word;
    EXPECT_NE(result.error().message.find(word), std::string::npos) << result.error().message;
  };
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  GeneratorOptions o;
  for (const int size : {-5, 0, 1, kMaxGeneratorSize + 1}) {
    o = GeneratorOptions{};
    o.size = size;
    expectRejected(o, "size");
  }
  for (const double spacing : {0.0, -30.0, nan, inf}) {
    o = GeneratorOptions{};
    o.spacingM = spacing;
    expectRejected(o, "spacing");
  }
  o = GeneratorOptions{};
  o.relief.reliefM = nan;
  expectRejected(o, "reliefM");
  o = GeneratorOptions{};
  o.relief.featureSizeM = 0.0;
  expectRejected(o, "featureSizeM");
  o = GeneratorOptions{};
  o.fluvial.iterations = -1;
  expectRejected(o, "fluvial.iterations");
  o = GeneratorOptions{};
  o.droplets.dropletsPerSample = -0.5;
  expectRejected(o, "dropletsPerSample");
  o = GeneratorOptions{};
  o.thermal.talusSlope = 0.0;
  expectRejected(o, "talusSlope");
}

TEST(Generator, ReportsProgressFromZeroToOne) {
  GeneratorOptions options = smallOptions(5);
  options.size = 129;
  std::vector<float> reports;
  ASSERT_TRUE(generateTerrain(options, [&](float f) { reports.push_back(f); }).ok());
  ASSERT_GE(reports.size(), 5u);
  EXPECT_GE(reports.front(), 0.0f);
  EXPECT_LT(reports.front(), 0.5f);
  EXPECT_EQ(reports.back(), 1.0f);
  EXPECT_TRUE(std::is_sorted(reports.begin(), reports.end()));
}

TEST(Generator, MakesMountainsOfPlausibleHeightAndSlope) {
  for (const std::uint64_t seed : {1u, 2u, 3u}) {
    const Heightfield field = generate(smallOptions(seed));
    const auto [lo, hi] = std::minmax_element(field.heights.begin(), field.heights.end());
    EXPECT_GT(*lo, 0.0f) << "seed " << seed;
    EXPECT_LT(*hi, 3000.0f) << "seed " << seed;
    EXPECT_GT(*hi - *lo, 800.0f) << "seed " << seed << ": too little relief for mountains";
    // Steep enough to be mountains, smooth enough not to be noise: white noise of this
    // range would average a slope of about 10 (1000 m per 60 m sample).
    const double slope = meanSlope(field);
    EXPECT_GT(slope, 0.05) << "seed " << seed;
    EXPECT_LT(slope, 0.5) << "seed " << seed;
  }
}

TEST(Generator, EveryInteriorSampleDrainsToTheBorder) {
  const Heightfield field = generate(smallOptions(4));
  EXPECT_EQ(countPits(field), 0);
  // The relief alone holds closed basins that the pipeline had to drain.
  EXPECT_GT(countPits(generate(reliefOnly(smallOptions(4)))), 50);
}

TEST(Generator, ErosionDrainsClosedBasinsAndCarvesValleys) {
  for (const std::uint64_t seed : {1u, 2u, 5u}) {
    const Heightfield relief = generate(reliefOnly(smallOptions(seed)));
    GeneratorOptions noFill = smallOptions(seed);
    noFill.fillDepressions = false;
    const Heightfield eroded = generate(noFill);
    // Erosion itself (before the final fill) breaches basin rims and silts lakes up.
    const double reliefLakes = lakeFraction(relief), erodedLakes = lakeFraction(eroded);
    EXPECT_GT(reliefLakes, 0.03) << "seed " << seed;
    EXPECT_LT(erodedLakes, 0.5 * reliefLakes) << "seed " << seed;

    // Rivers run in valleys: samples draining 100+ samples lie well below their
    // surroundings, far more than on the relief with its basins merely filled.
    Heightfield filledRelief = relief;
    fillDepressions(filledRelief);
    const Heightfield final = generate(smallOptions(seed));
    EXPECT_GT(channelIncision(final, 100.0), 1.8 * channelIncision(filledRelief, 100.0)) << "seed " << seed;
    EXPECT_GT(channelIncision(final, 100.0), 5.0) << "seed " << seed;
  }
}

TEST(FillDepressions, RaisesABasinToItsRimAndLeavesTheRestAlone) {
  // A slope down to the south with a bowl in the middle.
  Heightfield field(21, 21, 10.0, 10.0);
  for (int y = 0; y < 21; ++y)
    for (int x = 0; x < 21; ++x) {
      const double r = std::hypot(x - 10.0, y - 10.0);
      field.at(x, y) = float(2.0 * y - (r < 5.0 ? 30.0 * (1.0 - r / 5.0) : 0.0));
    }
  const Heightfield before = field;
  ASSERT_GT(countPits(before), 0);
  fillDepressions(field);
  EXPECT_EQ(countPits(field), 0);
  for (std::size_t i = 0; i < field.heights.size(); ++i) EXPECT_GE(field.heights[i], before.heights[i]);
  EXPECT_GT(field.at(10, 10), before.at(10, 10) + 10.0f);  // the bowl's bottom came up
  EXPECT_LT(field.at(10, 10), 2.0f * 10 + 1.0f);           // but not above its rim, plus epsilons
  EXPECT_EQ(field.at(10, 18), before.at(10, 18));          // outside the bowl: untouched
  EXPECT_EQ(field.at(3, 4), before.at(3, 4));
}

TEST(ErodeFluvial, RiversBreachADamAcrossTheirValley) {
  // A valley sloping to the south, dammed by a ridge across it: a lake forms behind.
  Heightfield field(65, 65, 30.0, 30.0);
  for (int y = 0; y < 65; ++y)
    for (int x = 0; x < 65; ++x)
      field.at(x, y) = float(3.0 * y + 0.2 * std::abs(x - 32) * 30.0 + 90.0 * std::exp(-std::pow((y - 20) / 3.0, 2.0)));
  const double lakesBefore = lakeFraction(field);
  ASSERT_GT(lakesBefore, 0.05);
  FluvialOptions options;
  options.iterations = 20;
  erodeFluvial(field, options);
  EXPECT_LT(lakeFraction(field), 0.3 * lakesBefore);
}

TEST(ErodeThermal, LowersSlopesSteeperThanTalusAndKeepsTheVolume) {
  Heightfield field(15, 15, 1.0, 1.0);
  field.at(7, 7) = 50.0f;  // a needle on a plain
  const double volumeBefore = std::accumulate(field.heights.begin(), field.heights.end(), 0.0);
  ThermalOptions options;
  options.iterations = 200;
  erodeThermal(field, options);
  EXPECT_LT(field.at(7, 7), 20.0f);
  EXPECT_GT(field.at(8, 7), 1.0f);
  EXPECT_NEAR(std::accumulate(field.heights.begin(), field.heights.end(), 0.0), volumeBefore, 1e-3);
  double steepest = 0.0;
  for (int y = 0; y < 15; ++y)
    for (int x = 0; x + 1 < 15; ++x)
      steepest = std::max(steepest, std::abs(double(field.at(x + 1, y)) - field.at(x, y)));
  EXPECT_LT(steepest, options.talusSlope * 1.5);
}

}  // namespace
}  // namespace polder::terrain
