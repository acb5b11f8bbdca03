// The triangle budget allocator (ASLOD, Schmalstieg and Fuhrmann 1999 section 3: p_i = P *
// w_i^(1/alpha) / sum_j w_j^(1/alpha), clamped and rounded to sum to exactly P; the weights
// are projected areas after Schmalstieg & Tobler, JGT 1999), checked against a slow
// reference that solves the clamped split by bisection.
#include <polder/lod/allocator.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace polder::lod {
namespace {

struct Allocation {
  std::vector<std::uint32_t> counts;
  AllocationResult result;
};

Allocation allocate(const std::vector<RegionDemand>& regions, std::uint64_t budget, double alpha) {
  Allocation allocation;
  allocation.counts.assign(regions.size(), 0xdeadbeef);
  AllocationScratch scratch;
  allocation.result = allocateTriangles(regions, budget, alpha, allocation.counts, scratch);
  return allocation;
}

std::uint64_t sumOf(const std::vector<std::uint32_t>& counts) {
  return std::accumulate(counts.begin(), counts.end(), std::uint64_t{0});
}

// The continuous answer: x_i = clamp(lambda * w_i^(1/alpha), min_i, max_i) with sum P, by
// bisection on log(lambda); zero weights take their min until the weighted regions are all
// at their max, then share the rest evenly.
std::vector<double> idealShares(const std::vector<RegionDemand>& regions, std::uint64_t budget, double alpha) {
  const std::size_t n = regions.size();
  std::vector<double> ideal(n);
  std::uint64_t sumMin = 0, sumMax = 0, sumPinned = 0;
  std::vector<double> shares(n);
  for (std::size_t i = 0; i < n; ++i) {
    sumMin += regions[i].minTriangles;
    sumMax += regions[i].maxTriangles;
    shares[i] = regions[i].weight > 0.0 ? std::pow(regions[i].weight, 1.0 / alpha) : 0.0;
    sumPinned += shares[i] > 0.0 ? regions[i].maxTriangles : regions[i].minTriangles;
  }
  const auto clampAt = [&](double lambda, std::size_t i, bool secondStage) {
    const double lo = regions[i].minTriangles, hi = regions[i].maxTriangles;
    if (secondStage && shares[i] > 0.0) return hi;
    const double t = lambda * (secondStage ? 1.0 : shares[i]);
    return std::clamp(t, lo, hi);
  };
  if (budget <= sumMin || budget >= sumMax) {
    for (std::size_t i = 0; i < n; ++i) ideal[i] = budget <= sumMin ? regions[i].minTriangles : regions[i].maxTriangles;
    return ideal;
  }
  const bool secondStage = budget >= sumPinned;
  double low = -2000.0, high = 2000.0;  // log2(lambda)
  for (int iteration = 0; iteration < 300; ++iteration) {
    const double middle = 0.5 * (low + high);
    double sum = 0.0;
    for (std::size_t i = 0; i < n; ++i) sum += clampAt(std::exp2(middle), i, secondStage);
    (sum < double(budget) ? low : high) = middle;
  }
  for (std::size_t i = 0; i < n; ++i) ideal[i] = clampAt(std::exp2(0.5 * (low + high)), i, secondStage);
  return ideal;
}

void expectValid(const std::vector<RegionDemand>& regions, std::uint64_t budget, double alpha,
                 const Allocation& allocation, const char* label) {
  std::uint64_t sumMin = 0, sumMax = 0;
  for (std::size_t i = 0; i < regions.size(); ++i) {
    sumMin += regions[i].minTriangles;
    sumMax += regions[i].maxTriangles;
    ASSERT_GE(allocation.counts[i], regions[i].minTriangles) << label << " region " << i;
    ASSERT_LE(allocation.counts[i], regions[i].maxTriangles) << label << " region " << i;
  }
  const std::uint64_t total = sumOf(allocation.counts);
  ASSERT_EQ(allocation.result.totalAssigned, total) << label;
  const bool feasible = sumMin <= budget && budget <= sumMax;
  ASSERT_EQ(allocation.result.feasible, feasible) << label;
  if (feasible) {
    ASSERT_EQ(total, budget) << label;
  }
  const std::vector<double> ideal = idealShares(regions, budget, alpha);
  for (std::size_t i = 0; i < regions.size(); ++i) {
    ASSERT_LT(std::abs(double(allocation.counts[i]) - ideal[i]), 1.0 + 1e-6 * (1.0 + ideal[i]))
        << label << " region " << i << " of " << regions.size() << ", budget " << budget << ", alpha " << alpha;
  }
}

TEST(Allocator, RandomCasesSumExactlyStayInClampsAndWithinOneOfTheIdealSplit) {
  std::mt19937_64 rng(20240601);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::lognormal_distribution<double> spread(0.0, 2.5);
  for (int trial = 0; trial < 5000; ++trial) {
    const std::size_t n = 1 + rng() % 64;
    std::vector<RegionDemand> regions(n);
    std::uint64_t sumMax = 0;
    for (RegionDemand& region : regions) {
      const double kind = unit(rng);
      region.weight = kind < 0.1 ? 0.0 : (kind < 0.5 ? unit(rng) * 1e4 : spread(rng));
      region.minTriangles = rng() % 4 == 0 ? 0u : std::uint32_t(rng() % 200);
      const std::uint32_t range = rng() % 8 == 0 ? 0u : std::uint32_t(rng() % 20000);
      region.maxTriangles = region.minTriangles + range;
      sumMax += region.maxTriangles;
    }
    const double alphas[] = {1.0, 2.0, 3.0, 0.3 + 8.0 * unit(rng)};
    const double alpha = alphas[rng() % 4];
    const std::uint64_t budget = std::uint64_t(unit(rng) * 1.15 * double(sumMax));
    expectValid(regions, budget, alpha, allocate(regions, budget, alpha), "random");
  }
}

TEST(Allocator, HandWorkedWaterFilling) {
  // alpha = 1, P = 100: raw shares 25, 25, 50; the heavy region is capped at 10, and the
  // 40 it frees go to the other two in proportion to their weights: 45 and 45.
  const std::vector<RegionDemand> capped = {{1.0, 0, 1000}, {1.0, 0, 1000}, {2.0, 0, 10}};
  EXPECT_EQ(allocate(capped, 100, 1.0).counts, (std::vector<std::uint32_t>{45, 45, 10}));
  // A floor works the other way: raw shares 10, 90; the light region needs 30, so the
  // heavy one gets 70.
  const std::vector<RegionDemand> floored = {{1.0, 30, 1000}, {9.0, 0, 1000}};
  EXPECT_EQ(allocate(floored, 100, 1.0).counts, (std::vector<std::uint32_t>{30, 70}));
  // Largest remainder: 10 over three equal regions is 3.33 each; the one extra goes to
  // the lowest index.
  const std::vector<RegionDemand> equal(3, RegionDemand{1.0, 0, 100});
  EXPECT_EQ(allocate(equal, 10, 1.0).counts, (std::vector<std::uint32_t>{4, 3, 3}));
}

TEST(Allocator, HigherWeightNeverGetsFewerTrianglesUnderEqualClamps) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int trial = 0; trial < 1000; ++trial) {
    const std::size_t n = 2 + rng() % 200;
    const std::uint32_t lo = rng() % 50, hi = lo + 1 + std::uint32_t(rng() % 3000);
    std::vector<RegionDemand> regions(n);
    for (std::size_t i = 0; i < n; ++i) {
      regions[i] = {unit(rng) < 0.05 ? 0.0 : std::exp(8.0 * unit(rng)), lo, hi};
      if (i > 0 && unit(rng) < 0.1) regions[i].weight = regions[i - 1].weight;  // some ties
    }
    const double alpha = 0.5 + 4.0 * unit(rng);
    const std::uint64_t budget = std::uint64_t(unit(rng) * double(n) * hi);
    const Allocation allocation = allocate(regions, budget, alpha);
    std::vector<std::size_t> order(n);
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(),
              [&](std::size_t a, std::size_t b) { return regions[a].weight < regions[b].weight; });
    for (std::size_t k = 1; k < n; ++k) {
      const std::size_t lighter = order[k - 1], heavier = order[k];
      if (regions[heavier].weight > regions[lighter].weight) {
        ASSERT_GE(allocation.counts[heavier], allocation.counts[lighter]) << "trial " << trial;
      } else {
        ASSERT_LE(std::abs(std::int64_t(allocation.counts[heavier]) - std::int64_t(allocation.counts[lighter])), 1);
      }
    }
  }
}

TEST(Allocator, AlphaOneIsProportionalToWeight) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<RegionDemand> regions(500);
  double weightSum = 0.0;
  for (RegionDemand& region : regions) {
    region.weight = 1.0 + 1000.0 * unit(rng);
    weightSum += region.weight;
  }
  const std::uint64_t budget = 1'000'000;
  const Allocation allocation = allocate(regions, budget, 1.0);
  EXPECT_EQ(sumOf(allocation.counts), budget);
  for (std::size_t i = 0; i < regions.size(); ++i) {
    EXPECT_LT(std::abs(double(allocation.counts[i]) - double(budget) * regions[i].weight / weightSum), 1.0);
  }
}

TEST(Allocator, LargerAlphaFlattensTowardsEqualShares) {
  std::vector<RegionDemand> regions;
  for (int i = 0; i < 20; ++i) regions.push_back({std::pow(2.0, i), 0});
  const std::uint64_t budget = ((1u << 20) - 1) * 1000ull;  // alpha = 1: exactly 1000 * 2^i
  double previousRatio = std::numeric_limits<double>::infinity();
  for (double alpha : {1.0, 1.5, 2.0, 3.0, 5.0, 10.0, 100.0}) {
    const Allocation allocation = allocate(regions, budget, alpha);
    EXPECT_EQ(sumOf(allocation.counts), budget);
    const auto [least, most] = std::minmax_element(allocation.counts.begin(), allocation.counts.end());
    const double ratio = double(*most) / double(std::max<std::uint32_t>(*least, 1));
    EXPECT_LT(ratio, previousRatio) << "alpha " << alpha;
    // The heaviest over the lightest is 2^(19/alpha), within rounding.
    EXPECT_NEAR(ratio, std::pow(2.0, 19.0 / alpha), 0.01 * std::pow(2.0, 19.0 / alpha)) << "alpha " << alpha;
    previousRatio = ratio;
  }
  const Allocation uniform = allocate(regions, budget, 1e9);
  for (std::uint32_t count : uniform.counts) EXPECT_NEAR(double(count), double(budget) / regions.size(), 1.0);
}

TEST(Allocator, BudgetBelowTheMinimumsGivesEveryRegionItsMinimum) {
  const std::vector<RegionDemand> regions = {{5.0, 100, 500}, {1.0, 50, 60}, {0.0, 10, 20}};
  const Allocation allocation = allocate(regions, 150, 2.0);
  EXPECT_EQ(allocation.counts, (std::vector<std::uint32_t>{100, 50, 10}));
  EXPECT_FALSE(allocation.result.feasible);
  EXPECT_EQ(allocation.result.totalAssigned, 160u);
  // Exactly the sum of the minimums is feasible.
  const Allocation exact = allocate(regions, 160, 2.0);
  EXPECT_TRUE(exact.result.feasible);
  EXPECT_EQ(exact.counts, (std::vector<std::uint32_t>{100, 50, 10}));
}

TEST(Allocator, BudgetAboveTheMaximumsGivesEveryRegionItsMaximum) {
  const std::vector<RegionDemand> regions = {{5.0, 100, 500}, {1.0, 50, 60}, {0.0, 10, 20}};
  const Allocation allocation = allocate(regions, 10'000, 3.0);
  EXPECT_EQ(allocation.counts, (std::vector<std::uint32_t>{500, 60, 20}));
  EXPECT_FALSE(allocation.result.feasible);
  EXPECT_EQ(allocation.result.totalAssigned, 580u);
  EXPECT_TRUE(allocate(regions, 580, 3.0).result.feasible);
}

TEST(Allocator, ZeroWeightsGetTheirMinimumWhileWeightedRegionsHaveRoom) {
  const std::vector<RegionDemand> regions = {{0.0, 7, 1000}, {3.0, 0, 1000}, {0.0, 0, 1000}, {1.0, 2, 1000}};
  const Allocation allocation = allocate(regions, 502, 1.0);
  // 495 left for weights 3 : 1 is 371.25 and 123.75; the larger remainder rounds up.
  EXPECT_EQ(allocation.counts, (std::vector<std::uint32_t>{7, 371, 0, 124}));
  EXPECT_TRUE(allocation.result.feasible);
}

TEST(Allocator, ZeroWeightsTakeTheRestOnlyOnceWeightedRegionsAreFull) {
  // Weighted regions hold at most 100 + 50; the other 50 of 200 are water-filled evenly
  // over the zero-weight regions (the second's minimum of 10 is below the level).
  const std::vector<RegionDemand> regions = {{4.0, 0, 100}, {0.0, 0, 1000}, {1.0, 0, 50}, {0.0, 10, 1000}};
  const Allocation allocation = allocate(regions, 200, 2.0);
  EXPECT_EQ(allocation.counts, (std::vector<std::uint32_t>{100, 25, 50, 25}));
  EXPECT_TRUE(allocation.result.feasible);
  // All weights zero: an even split.
  const std::vector<RegionDemand> unweighted(4, RegionDemand{0.0, 0, 1000});
  EXPECT_EQ(allocate(unweighted, 10, 3.0).counts, (std::vector<std::uint32_t>{3, 3, 2, 2}));
}

TEST(Allocator, SingleRegionTakesTheBudgetWithinItsClamp) {
  const std::vector<RegionDemand> region = {{2.5, 10, 90}};
  EXPECT_EQ(allocate(region, 50, 3.0).counts[0], 50u);
  EXPECT_EQ(allocate(region, 5, 3.0).counts[0], 10u);
  EXPECT_EQ(allocate(region, 500, 3.0).counts[0], 90u);
  const std::vector<RegionDemand> unweighted = {{0.0, 10, 90}};
  EXPECT_EQ(allocate(unweighted, 50, 3.0).counts[0], 50u);  // the budget is still met
}

TEST(Allocator, ZeroBudgetAndNoRegions) {
  const std::vector<RegionDemand> free = {{1.0, 0, 10}, {2.0, 0, 10}};
  const Allocation none = allocate(free, 0, 3.0);
  EXPECT_EQ(none.counts, (std::vector<std::uint32_t>{0, 0}));
  EXPECT_TRUE(none.result.feasible);
  const std::vector<RegionDemand> floored = {{1.0, 3, 10}, {2.0, 0, 10}};
  const Allocation short_ = allocate(floored, 0, 3.0);
  EXPECT_EQ(short_.counts, (std::vector<std::uint32_t>{3, 0}));
  EXPECT_FALSE(short_.result.feasible);
  EXPECT_TRUE(allocate({}, 0, 1.0).result.feasible);
  EXPECT_FALSE(allocate({}, 5, 1.0).result.feasible);
}

TEST(Allocator, WeightScaleDoesNotMatter) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<RegionDemand> regions(300);
  for (RegionDemand& region : regions) {
    region = {unit(rng), std::uint32_t(rng() % 20), 20 + std::uint32_t(rng() % 5000)};
  }
  const Allocation reference = allocate(regions, 400'000, 0.25);  // w^4: small alpha
  for (double scale : {1e-200, 1e-5, 1e5, 1e250}) {
    std::vector<RegionDemand> scaled = regions;
    for (RegionDemand& region : scaled) region.weight *= scale;
    const Allocation allocation = allocate(scaled, 400'000, 0.25);
    EXPECT_EQ(sumOf(allocation.counts), 400'000u);
    for (std::size_t i = 0; i < regions.size(); ++i) {
      EXPECT_LE(std::abs(std::int64_t(allocation.counts[i]) - std::int64_t(reference.counts[i])), 1) << scale;
    }
  }
}

TEST(Allocator, GeometricWeightsThatDefeatPlainRedistributionStillSolveExactly) {
  // Each clamp-and-redistribute step caps only the next-heaviest region here.
  std::vector<RegionDemand> regions;
  for (int i = 0; i < 3000; ++i) regions.push_back({std::pow(1.2, i % 1500), 0, 1000});
  for (double alpha : {1.0, 3.0}) {
    for (std::uint64_t budget : {std::uint64_t{5'000}, std::uint64_t{400'000}, std::uint64_t{2'999'000}}) {
      expectValid(regions, budget, alpha, allocate(regions, budget, alpha), "geometric");
    }
  }
}

TEST(Allocator, ManyRegionsWithWeightsOverManyDecadesMatchTheReference) {
  // Large, unsorted and spread wide: the solver's narrowing path with sampled medians.
  std::mt19937_64 rng(77);
  std::lognormal_distribution<double> spread(0.0, 2.5);
  std::vector<RegionDemand> regions(5000);
  std::uint64_t sumMax = 0;
  for (RegionDemand& region : regions) {
    region = {rng() % 10 == 0 ? 0.0 : spread(rng), std::uint32_t(rng() % 300), 0};
    region.maxTriangles = region.minTriangles + std::uint32_t(rng() % 4000);
    sumMax += region.maxTriangles;
  }
  for (double alpha : {0.5, 1.0, 3.0}) {
    for (double fraction : {0.1, 0.4, 0.8, 0.99}) {
      const std::uint64_t budget = std::uint64_t(fraction * double(sumMax));
      expectValid(regions, budget, alpha, allocate(regions, budget, alpha), "decades");
    }
  }
}

TEST(Allocator, CountsNearTheTopOfTheRange) {
  constexpr std::uint32_t kMax = std::numeric_limits<std::uint32_t>::max();
  std::vector<RegionDemand> regions;
  for (int i = 0; i < 1000; ++i) regions.push_back({1.0 + i, std::uint32_t(i), kMax});
  for (std::uint64_t budget : {std::uint64_t{1} << 40, std::uint64_t{999} * kMax, std::uint64_t{1000} * kMax - 1}) {
    expectValid(regions, budget, 3.0, allocate(regions, budget, 3.0), "large");
  }
}

TEST(Allocator, OneScratchServesCallsOfAnySizeAndGrowsOnlyToTheLargest) {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  AllocationScratch scratch(16);
  EXPECT_EQ(scratch.capacity(), 16u);
  std::size_t largest = 16;
  for (int trial = 0; trial < 50; ++trial) {
    std::vector<RegionDemand> regions(1 + rng() % 100);
    largest = std::max(largest, regions.size());
    for (RegionDemand& region : regions) region = {unit(rng), 1, 1 + std::uint32_t(rng() % 1000)};
    std::vector<std::uint32_t> counts(regions.size());
    const AllocationResult result = allocateTriangles(regions, 20'000, 3.0, counts, scratch);
    const Allocation expected = allocate(regions, 20'000, 3.0);  // fresh scratch
    EXPECT_EQ(counts, expected.counts);
    EXPECT_EQ(result.totalAssigned, expected.result.totalAssigned);
    EXPECT_EQ(result.feasible, expected.result.feasible);
    EXPECT_EQ(scratch.capacity(), largest);
  }
}

}  // namespace
}  // namespace polder::lod
