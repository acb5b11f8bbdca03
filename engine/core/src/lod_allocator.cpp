// Triangle budget allocation: ASLOD's p_i = P * w_i^(1/alpha) / sum_j w_j^(1/alpha)
// (Schmalstieg and Fuhrmann 1999, section 3), clamped per region by water-filling and
// rounded by largest remainder so the counts sum to exactly P. The weights are projected
// areas (Schmalstieg & Tobler, JGT 1999; lod_projected_area.cpp).
#include <polder/lod/allocator.hpp>

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <functional>
#include <limits>

namespace polder::lod {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
// Newton passes over every region before the solver narrows its work to the regions whose
// clamps still matter; real weights usually finish within two or three. A pass that does
// not cut the distance to the budget by kNewtonProgress hands over to narrowing at once.
constexpr int kNewtonPasses = 6;
constexpr double kNewtonProgress = 0.25;
// Safety cap on the narrowing passes (they need about log2(2n)); were it ever reached, the
// rounding would still make the counts sum exactly to the budget.
constexpr int kMaxNarrowingPasses = 200;

// f(lambda) = sum_i clamp(lambda * s_i, min_i, max_i) at one lambda, with the slope of its
// linear piece there (sum of s_i over the unclamped regions) and how many regions sit at
// each clamp. As lambda grows regions only move min -> free -> max, so equal counts at two
// lambdas mean the same piece.
struct Piece {
  double value = 0.0;
  double freeShare = 0.0;
  std::size_t atMin = 0, atMax = 0;
};

double clampedShare(double lambda, double share, const RegionDemand& region) {
  const double t = lambda * share;  // lambda > 0, so an infinite share pins the region at max
  const double lo = double(region.minTriangles), hi = double(region.maxTriangles);
  return t <= lo ? lo : (t >= hi ? hi : t);
}

// share when keep, else 0, without a branch (and without 0 * inf = NaN for pinned regions).
double maskedShare(double share, bool keep) {
  return std::bit_cast<double>(std::bit_cast<std::uint64_t>(share) & (std::uint64_t{0} - std::uint64_t{keep}));
}

// Branch-free: whether a region is clamped is unpredictable, and mispredictions dominated.
void addToPiece(Piece& piece, double lambda, double share, const RegionDemand& region) {
  const double t = lambda * share;
  const double lo = double(region.minTriangles), hi = double(region.maxTriangles);
  const bool atMin = t <= lo, atMax = t >= hi;
  piece.value += std::min(std::max(t, lo), hi);
  piece.freeShare += maskedShare(share, !atMin & !atMax);
  piece.atMin += atMin;
  piece.atMax += atMax & !atMin;
}

// Solves f(lambda) = budget for lambda > 0, given f(0+) = atZero < budget < f(infinity).
//
// f is piecewise linear and non-decreasing, with a kink wherever a region meets its min or
// max (lambda = min/s or max/s). A Newton step on the current piece is exactly one round of
// "clamp, redistribute what the clamps free over the unclamped regions, repeat until
// stable", and it lands on the root once it is on the right piece: a few passes on real
// weights. When weights spread geometrically each step may cross only one more kink, so
// the solver then keeps a bracket, settles every region with no kink inside it (its
// contribution is linear across the bracket), and probes a median of the remaining kinks
// on every other step: the regions left to visit halve each time, O(n) work in all. With
// no kink left in the bracket the root follows from the settled sums.
class LevelSolver {
 public:
  LevelSolver(std::span<const RegionDemand> regions, const double* shares, std::uint32_t* undecided, double* kinks)
      : m_regions(regions), m_shares(shares), m_undecided(undecided), m_kinks(kinks) {}

  double solve(double budget, double atZero, double initial) {
    m_budget = budget;
    m_below = 0.0;
    m_atBelow = atZero;
    double lambda = initial;
    Piece previous;
    bool fromNewton = false;
    double newton = -1.0, previousGap = kInfinity;
    for (int pass = 0; pass < kNewtonPasses; ++pass) {
      Piece piece;
      for (std::size_t i = 0; i < m_regions.size(); ++i) addToPiece(piece, lambda, m_shares[i], m_regions[i]);
      const double value = piece.value;
      // Same piece as the one the Newton step was solved on: lambda is that piece's root.
      const bool samePiece = piece.atMin == previous.atMin && piece.atMax == previous.atMax;
      if (value == budget || (fromNewton && samePiece)) return lambda;
      narrowBracket(lambda, value);
      newton = piece.freeShare > 0.0 ? lambda + (budget - value) / piece.freeShare : -1.0;
      fromNewton = inside(newton);
      const double gap = std::abs(value - budget);
      if (!fromNewton || gap > kNewtonProgress * previousGap) break;
      previousGap = gap;
      previous = piece;
      lambda = newton;
    }
    return narrow(newton);
  }

 private:
  bool inside(double lambda) const { return lambda > m_below && lambda < m_above; }

  void narrowBracket(double lambda, double value) {
    if (value < m_budget) {
      m_below = lambda;
      m_atBelow = value;
    } else {
      m_above = lambda;
      m_atAbove = value;
    }
  }

  // Moves regions whose kinks all lie outside the open bracket into the settled sums;
  // keeps the others in m_undecided. Visits all regions (first call) or the undecided ones.
  // Branch-free past the first call's fixed regions, as in addToPiece.
  void settle(bool fromAll) {
    const std::size_t count = fromAll ? m_regions.size() : m_undecidedCount;
    std::size_t kept = 0;
    for (std::size_t k = 0; k < count; ++k) {
      const std::uint32_t i = fromAll ? std::uint32_t(k) : m_undecided[k];
      const double share = m_shares[i];
      const double lo = double(m_regions[i].minTriangles), hi = double(m_regions[i].maxTriangles);
      if (fromAll && (!(share > 0.0) || share == kInfinity || lo == hi)) {
        // Fixed at every lambda > 0 (an infinite share pins the region at max).
        m_settledFixed += share == kInfinity ? hi : lo;
        continue;
      }
      const double tBelow = m_below * share, tAbove = m_above * share;  // its share at the ends
      const bool atMax = tBelow >= hi, atMin = tAbove <= lo;
      const bool free = (tBelow >= lo) & (tAbove <= hi) & !atMax & !atMin;
      m_settledFixed += std::min(std::max(tBelow, lo), hi) * double(atMax | atMin);
      m_settledFree += maskedShare(share, free);
      m_undecided[kept] = i;
      kept += !(atMax | atMin | free);
    }
    m_undecidedCount = kept;
  }

  // A median of the kinks strictly inside the bracket, or the bracket's middle if rounding
  // left none. From an even sample of about kMedianSample regions (cheap, and as good on
  // any ordering that is not adversarial), or from all of them when sampling stalled.
  double medianKink(bool exact) {
    constexpr std::size_t kMedianSample = 64;
    const std::size_t stride = exact ? 1 : std::max<std::size_t>(1, m_undecidedCount / kMedianSample);
    std::size_t count = 0;
    for (std::size_t k = 0; k < m_undecidedCount; k += stride) {
      const std::uint32_t i = m_undecided[k];
      const double atMin = double(m_regions[i].minTriangles) / m_shares[i];
      const double atMax = double(m_regions[i].maxTriangles) / m_shares[i];
      if (inside(atMin)) m_kinks[count++] = atMin;
      if (inside(atMax)) m_kinks[count++] = atMax;
    }
    if (count > 0) {
      std::nth_element(m_kinks, m_kinks + count / 2, m_kinks + count);
      return m_kinks[count / 2];
    }
    if (m_above == kInfinity) return 2.0 * m_below;
    return m_below == 0.0 ? 0.5 * m_above : std::sqrt(m_below * m_above);  // shares span decades
  }

  double narrow(double newton) {
    settle(true);
    bool tryNewton = true, exactMedian = false;
    for (int pass = 0; pass < kMaxNarrowingPasses; ++pass) {
      if (m_undecidedCount == 0) {
        // f = settledFixed + lambda * settledFree across the whole bracket.
        if (m_settledFree > 0.0) {
          const double root = (m_budget - m_settledFixed) / m_settledFree;
          return std::clamp(root, m_below, m_above == kInfinity ? root : m_above);
        }
        return m_below;  // f flat: only reachable through rounding
      }
      const bool byNewton = tryNewton && inside(newton);
      const double lambda = byNewton ? newton : medianKink(exactMedian);
      const std::size_t undecidedBefore = m_undecidedCount;
      tryNewton = !tryNewton;
      if (!inside(lambda)) break;  // the bracket is as narrow as doubles allow
      Piece piece;
      for (std::size_t k = 0; k < m_undecidedCount; ++k) {
        const std::uint32_t i = m_undecided[k];
        addToPiece(piece, lambda, m_shares[i], m_regions[i]);
      }
      const double value = m_settledFixed + lambda * m_settledFree + piece.value;
      if (value == m_budget) return lambda;
      narrowBracket(lambda, value);
      const double slope = m_settledFree + piece.freeShare;
      newton = slope > 0.0 ? lambda + (m_budget - value) / slope : -1.0;
      settle(false);
      // A sampled median should cut the regions left by half; if it did not cut a quarter,
      // take the exact median next time, which halves the kinks whatever their order.
      if (!byNewton) exactMedian = 4 * m_undecidedCount > 3 * undecidedBefore;
    }
    if (m_above == kInfinity) return m_below;
    return m_below + (m_budget - m_atBelow) * (m_above - m_below) / (m_atAbove - m_atBelow);
  }

  std::span<const RegionDemand> m_regions;
  const double* m_shares;
  std::uint32_t* m_undecided;
  double* m_kinks;
  double m_budget = 0.0;
  double m_below = 0.0, m_atBelow = 0.0;
  double m_above = kInfinity, m_atAbove = kInfinity;
  double m_settledFixed = 0.0, m_settledFree = 0.0;
  std::size_t m_undecidedCount = 0;
};

// Moves `wanted` counts by step (+1 or -1) onto the eligible regions (below max for +1,
// above min for -1) with the largest (+1) or smallest (-1) remainders; ties go to the lower
// index. Returns how many moved (fewer than wanted only when too few are eligible).
std::uint64_t nudge(std::span<const RegionDemand> regions, std::span<std::uint32_t> out, const double* remainders,
                    double* keys, int step, std::uint64_t wanted) {
  const auto eligible = [&](std::size_t i) {
    return step > 0 ? out[i] < regions[i].maxTriangles : out[i] > regions[i].minTriangles;
  };
  const auto keyOf = [&](std::size_t i) { return step > 0 ? remainders[i] : -remainders[i]; };
  std::size_t count = 0;
  for (std::size_t i = 0; i < regions.size(); ++i) {
    if (eligible(i)) keys[count++] = keyOf(i);
  }
  if (count == 0 || wanted == 0) return 0;
  if (wanted >= count) {
    // Only after a solver miss: move in bulk so a large gap does not take one pass per count.
    const std::uint64_t each = wanted / count;
    std::uint64_t moved = 0;
    for (std::size_t i = 0; i < regions.size(); ++i) {
      if (!eligible(i)) continue;
      const std::uint64_t room = step > 0 ? regions[i].maxTriangles - out[i] : out[i] - regions[i].minTriangles;
      const std::uint64_t amount = std::min(each, room);
      out[i] = std::uint32_t(std::int64_t(out[i]) + step * std::int64_t(amount));
      moved += amount;
    }
    return moved;
  }
  std::nth_element(keys, keys + (wanted - 1), keys + count, std::greater<>());
  const double threshold = keys[wanted - 1];
  std::uint64_t moved = 0;
  for (std::size_t i = 0; i < regions.size(); ++i) {
    if (eligible(i) && keyOf(i) > threshold) {
      out[i] = std::uint32_t(std::int64_t(out[i]) + step);
      ++moved;
    }
  }
  for (std::size_t i = 0; i < regions.size() && moved < wanted; ++i) {
    if (eligible(i) && keyOf(i) == threshold) {
      out[i] = std::uint32_t(std::int64_t(out[i]) + step);
      ++moved;
    }
  }
  return moved;
}

AllocationResult fillAll(std::span<const RegionDemand> regions, std::span<std::uint32_t> out, bool atMax,
                         std::uint64_t budget) {
  std::uint64_t total = 0;
  for (std::size_t i = 0; i < regions.size(); ++i) {
    out[i] = atMax ? regions[i].maxTriangles : regions[i].minTriangles;
    total += out[i];
  }
  return AllocationResult{total, total == budget};
}

}  // namespace

AllocationResult allocateTriangles(std::span<const RegionDemand> regions, std::uint64_t budget, double alpha,
                                   std::span<std::uint32_t> outTriangles, AllocationScratch& scratch) {
  assert(outTriangles.size() == regions.size() && "allocateTriangles: outTriangles must have one entry per region");
  assert(regions.size() <= std::numeric_limits<std::uint32_t>::max() && "allocateTriangles: at most 2^32 - 1 regions");
  assert(alpha > 0.0 && std::isfinite(alpha) && "allocateTriangles: alpha must be finite and > 0");
  const std::size_t n = regions.size();
  if (n == 0) return AllocationResult{0, budget == 0};

  std::uint64_t sumMin = 0, sumMax = 0;
  double maxWeight = 0.0;
  for (const RegionDemand& region : regions) {
    assert(region.minTriangles <= region.maxTriangles &&
           "allocateTriangles: RegionDemand::minTriangles exceeds maxTriangles");
    assert(region.weight >= 0.0 && std::isfinite(region.weight) &&
           "allocateTriangles: RegionDemand::weight must be finite and >= 0");
    sumMin += region.minTriangles;
    sumMax += region.maxTriangles;
    if (region.weight > maxWeight && region.weight <= std::numeric_limits<double>::max()) maxWeight = region.weight;
  }
  if (budget <= sumMin) return fillAll(regions, outTriangles, false, budget);
  if (budget >= sumMax) return fillAll(regions, outTriangles, true, budget);

  // Shares s_i = (w_i / w_max)^(1/alpha): the formula is scale-free, and dividing first
  // keeps w^(1/alpha) finite for small alpha. A share that underflows counts as weight 0.
  scratch.reserve(n);
  double* shares = scratch.m_shares.data();
  double* keys = scratch.m_keys.data();
  const double invMaxWeight = maxWeight > 0.0 ? 1.0 / maxWeight : 0.0;
  const double exponent = 1.0 / alpha;
  double shareSum = 0.0;
  std::uint64_t sumPinned = 0;  // f(infinity): weighted regions at max, the others at min
  std::size_t zeroWeightCount = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double weight = regions[i].weight;
    const bool usable = weight > 0.0 && weight <= std::numeric_limits<double>::max();  // NaN, inf -> 0
    const double ratio = usable ? weight * invMaxWeight : 0.0;
    double share;
    if (alpha == 1.0)
      share = ratio;
    else if (alpha == 2.0)
      share = std::sqrt(ratio);  // a third of pow's cost
    else
      share = std::pow(ratio, exponent);
    shares[i] = share;
    shareSum += share;
    if (share > 0.0) {
      sumPinned += regions[i].maxTriangles;
    } else {
      sumPinned += regions[i].minTriangles;
      ++zeroWeightCount;
    }
  }

  const double budgetReal = double(budget);
  double lambda;
  if (budget < sumPinned) {
    lambda = LevelSolver(regions, shares, scratch.m_undecided.data(), keys)
                 .solve(budgetReal, double(sumMin), budgetReal / shareSum);
  } else {
    // Every weighted region fits at its max and budget is left: spread it evenly over the
    // zero-weight regions (the limit of giving them equal, vanishing weights).
    for (std::size_t i = 0; i < n; ++i) shares[i] = shares[i] > 0.0 ? kInfinity : 1.0;
    lambda = budget == sumPinned ? 0.0
                                 : LevelSolver(regions, shares, scratch.m_undecided.data(), keys)
                                       .solve(budgetReal, double(sumPinned), budgetReal / double(zeroWeightCount));
  }

  // Integer parts, remainders kept in `shares` (no longer needed) for the rounding.
  std::uint64_t total = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double share = shares[i];
    double ideal;
    if (lambda > 0.0)
      ideal = clampedShare(lambda, share, regions[i]);
    else
      ideal = share == kInfinity ? double(regions[i].maxTriangles) : double(regions[i].minTriangles);
    outTriangles[i] = std::uint32_t(ideal);  // 0 <= ideal < 2^32: truncation is floor
    shares[i] = ideal - double(outTriangles[i]);
    total += outTriangles[i];
  }

  // Largest remainders first. In exact arithmetic one round moves fewer counts than there
  // are fractional regions; the loops only repeat if rounding error pushed the sum astray.
  while (total < budget) {
    const std::uint64_t moved = nudge(regions, outTriangles, shares, keys, +1, budget - total);
    if (moved == 0) break;
    total += moved;
  }
  while (total > budget) {
    const std::uint64_t moved = nudge(regions, outTriangles, shares, keys, -1, total - budget);
    if (moved == 0) break;
    total -= moved;
  }
  return AllocationResult{total, total == budget};
}

}  // namespace polder::lod
