// The triangle budget allocator: splits a budget P over LOD regions (terrain blocks and
// mesh-object regions alike; docs/design.md "One frame", step 4).
//
// Follows ASLOD, D. Schmalstieg and A. Fuhrmann, "Coarse View-Dependent Levels of Detail for Hierarchical and
// Deformable Models", 1999, section 3 ("Level of detail selection"):
//     p_i = P * w_i^(1/alpha) / sum_j w_j^(1/alpha)
// where w_i grows with the region's projected area (Schmalstieg & Tobler, JGT 1999; see
// polder/lod/projected_area.hpp) and alpha attenuates it: alpha = 1 is proportional to
// the weights, larger alpha flattens the split towards equal shares (the paper's alpha = 3
// with w_i ~ projected area matches Funkhouser & Sequin's benefit heuristic).
//
// Regions cannot take any count: each has a [minTriangles, maxTriangles] range (its
// coarsest and finest LOD). The allocator therefore returns the clamped version of the
// formula, p_i = clamp(lambda * w_i^(1/alpha), min_i, max_i) with one common lambda
// chosen so the shares sum to P ("water-filling": what clamping frees or takes is spread
// over the unclamped regions in proportion to their shares), then rounds to integers by
// largest remainder so that the total is exactly P, never moving a count past its clamp.
//
// A pure function over caller-owned buffers: no state, no heap allocation in steady state.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace polder::lod {

// What one region asks for. weight must be finite and >= 0 (0: the region only gets its
// minimum, see allocateTriangles); minTriangles <= maxTriangles.
struct RegionDemand {
  double weight = 0.0;
  std::uint32_t minTriangles = 0;
  std::uint32_t maxTriangles = std::numeric_limits<std::uint32_t>::max();
};

struct AllocationResult {
  std::uint64_t totalAssigned = 0;  // sum of the counts written
  // True when totalAssigned == budget, i.e. sum(min) <= budget <= sum(max). When false
  // every region sits at its min (budget too small) or at its max (budget too large).
  bool feasible = true;
};

class AllocationScratch;

// Writes each region's triangle count to outTriangles (same size as regions) from the
// budget and the attenuation exponent alpha (finite, > 0).
//   - sum(min) <= budget <= sum(max): counts sum to exactly budget, each within its clamp,
//     within 1 of the clamped formula above.
//   - budget < sum(min): every region gets its min; feasible = false.
//   - budget > sum(max): every region gets its max; feasible = false.
//   - weight 0: the region gets its min, unless every weighted region already sits at its
//     max; only then is the rest shared evenly (water-filled) over the zero-weight regions,
//     so that the budget is still met exactly. All-zero weights therefore share evenly.
// Equal weights and clamps get counts within 1 of each other (ties in rounding go to the
// lower index); a higher weight never gets fewer triangles than a lower one with the same
// clamps. Cost: a few O(n) passes on real weights; when they do not settle (weights spread
// over many decades) the solver narrows to the regions whose clamps still matter, O(n)
// more work. Plus one std::pow per region when alpha is not 1 or 2.
// scratch is working memory the caller keeps between frames: it grows (allocates) only when
// a call brings more regions than its capacity, so a steady frame loop does not allocate;
// reserve() up front to keep even the first frames allocation-free. Mismatched sizes and
// invalid demands are programmer errors (asserted).
AllocationResult allocateTriangles(std::span<const RegionDemand> regions, std::uint64_t budget, double alpha,
                                   std::span<std::uint32_t> outTriangles, AllocationScratch& scratch);

// Working memory for allocateTriangles, 28 bytes per region. Not shareable between
// threads while a call runs; one per thread.
class AllocationScratch {
 public:
  AllocationScratch() = default;
  explicit AllocationScratch(std::size_t regionCount) { reserve(regionCount); }

  // Makes room for regionCount regions (the only place it allocates).
  void reserve(std::size_t regionCount) {
    if (regionCount <= capacity()) return;
    m_shares.resize(regionCount);
    m_keys.resize(2 * regionCount);
    m_undecided.resize(regionCount);
  }
  std::size_t capacity() const { return m_shares.size(); }

 private:
  friend AllocationResult allocateTriangles(std::span<const RegionDemand>, std::uint64_t, double,
                                            std::span<std::uint32_t>, AllocationScratch&);
  std::vector<double> m_shares;            // w_i^(1/alpha), then rounding remainders
  std::vector<double> m_keys;              // the solver's kinks, then rounding keys
  std::vector<std::uint32_t> m_undecided;  // regions the solver still visits
};

}  // namespace polder::lod
