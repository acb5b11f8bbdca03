// The LOD cache: one mesh per terrain block, reused across frames while the block-level
// reuse test allows (docs/design.md "One frame", step 2).
//
// Follows Chuang, "Level-of-Detail Modeling Technique for Virtual Reality (I)", 2001, part B: "a mechanism that caches
// the LOD of a block for the possible reuse in the following frames after it is generated";
// "the cached LOD can be reused if its projected error with respect to the new viewpoint is
// within a pre-specified error, or a new LOD should be re-generated if the test fails. The
// test is block-based, rather than vertex-based". The paper reports 92-98 % less LOD
// construction time and cached meshes with 2.2-8.7 % fewer triangles than fresh ones.
// lod_reuse.hpp holds the test and the proof that a reused mesh never exceeds tau.
//
// Dependency direction: cache -> terrain's plain data types (BlockLod, BlockMesh, LodView,
// NodeId) -> engine. Terrain never includes the cache; the engine's frame code owns both.
//
// Memory. The byte budget counts the cached meshes' vector capacities (meshBytes), not the
// per-block bookkeeping (about 1 KB a block, the LodSummary included). Least recently used
// blocks go first, but never one acquired in the current frame (see beginFrame), so the
// references a frame holds stay valid; a frame that needs more than the budget goes over it
// rather than drop meshes it is drawing. A rebuild extracts into the block's own mesh, and a
// new block takes over the memory of the block it evicts, so a warm cache in steady state
// allocates nothing (an extraction grows a mesh only past the largest it has held).
//
// Thread contract: not thread-safe. One owner, the frame thread, calls everything; the
// BlockLods it reads are immutable once built (rtin.hpp), so loaders may build the next ones
// meanwhile. Why the cache does not use LruCache: that class takes values by value and
// destroys what it evicts, where this one must recycle the evicted mesh's memory, update an
// entry's bytes when a rebuild grows it, and pin the current frame's entries.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include <polder/cache/lod_reuse.hpp>
#include <polder/terrain/block_layout.hpp>
#include <polder/terrain/block_mesh.hpp>
#include <polder/terrain/rtin.hpp>

namespace polder::cache {

struct LodCacheOptions {
  std::size_t budgetBytes = std::size_t(64) << 20;
  // false: every acquire rebuilds (the no-cache side of `polder bench --compare-cache`); the
  // meshes are still kept per block, so the comparison measures extraction, not allocation.
  bool enabled = true;
  LodReuseOptions reuse;
  // Meshes are built for tau / (1 + headroom): the slack lets the reuse test pass for a
  // while as the camera moves, at a few per cent more triangles. Measured on 33^2 blocks:
  // 0 -> 0.02 lifts reuse from 78 % to 96 % for a camera creeping 0.5 m a frame at 100-200 m
  // over sines, and from 95.6 % to 98.0 % on the flyover of lod_cache_test, whose triangle
  // ratio to fresh meshes goes from 1.035 to 1.051 (0.05: 97.6 %, 98.5 %, 1.075). >= 0.
  double headroom = 0.02;
  // acquireCount reuses a mesh built for t0 triangles while the target t stays within
  // [its triangle count, t0 * (1 + countHysteresis)]: below t0 the fresh mesh would be the same
  // one (greedy refinement stops at the same split), above it the block draws a little less
  // than it may.
  double countHysteresis = 0.1;
};

// What an acquire did.
enum class LodOutcome : std::uint8_t {
  Reused,                 // the cached mesh passed the reuse test
  Built,                  // the block was not cached
  RebuiltTooCoarse,       // the cached mesh could exceed tau from the new camera
  RebuiltNeedlesslyFine,  // within tau, but far finer than the new view needs
  RebuiltChanged,         // built for the other mode (view / count), another footprint, or
                          // a count target outside the hysteresis
  RebuiltPinned,          // side vertices were pinned since it was built (pin())
  RebuiltUncached,        // caching is disabled
};

inline bool isRebuild(LodOutcome outcome) { return outcome != LodOutcome::Reused; }

struct LodCacheCounters {
  std::uint64_t lookups = 0;         // acquire and acquireCount calls
  std::uint64_t hits = 0;            // Reused
  std::uint64_t rebuilds = 0;        // every extraction (= lookups - hits), by cause below
  std::uint64_t built = 0;           // Built
  std::uint64_t tooCoarse = 0;       // RebuiltTooCoarse
  std::uint64_t needlesslyFine = 0;  // RebuiltNeedlesslyFine
  std::uint64_t changed = 0;         // RebuiltChanged
  std::uint64_t pinned = 0;          // RebuiltPinned
  std::uint64_t uncached = 0;        // RebuiltUncached
  std::uint64_t evictions = 0;       // blocks dropped to stay within the budget
};

// Bytes of a mesh's storage: the capacities of its vectors.
std::size_t meshBytes(const terrain::BlockMesh& mesh);

class LodCache {
 public:
  explicit LodCache(const LodCacheOptions& options = {});
  ~LodCache();
  LodCache(const LodCache&) = delete;
  LodCache& operator=(const LodCache&) = delete;
  LodCache(LodCache&&) noexcept;
  LodCache& operator=(LodCache&&) noexcept;

  // Starts a frame: unpins the previous frame's blocks and evicts down to the budget, so
  // references returned before this call may now be invalid. Until the first call, only the
  // block being acquired is protected, so a returned reference lasts until the next acquire.
  void beginFrame();

  // The mesh of block `node` for `view` (camera relative to lod.origin()): the cached one if
  // it passes the reuse test (lod_reuse.hpp), else a new lod.extractView for view.tolerancePx
  // / (1 + headroom), stored. Either way every triangle keeps K e / max(d, near) <= tau (the
  // bound extractView promises). `lod` must be the node's; call invalidate(node) when its
  // data change (the footprint is checked, the heights are not). The reference stays valid
  // until the next beginFrame (see above), invalidate(node) or clear().
  const terrain::BlockMesh& acquire(terrain::NodeId node, const terrain::BlockLod& lod, const terrain::LodView& view,
                                    LodOutcome* outcome = nullptr);
  // Budget mode (docs/design.md step 4): lod.extractCount(targetTriangles), reused while the
  // target stays within the hysteresis (LodCacheOptions::countHysteresis).
  const terrain::BlockMesh& acquireCount(terrain::NodeId node, const terrain::BlockLod& lod,
                                         std::size_t targetTriangles, LodOutcome* outcome = nullptr);

  // Pins side positions from..to (inclusive) of `node`'s mesh (terrain::BoundaryPins): the
  // next acquire rebuilds it keeping them, and later ones keep them until the camera has
  // receded enough for a needlessly-fine rebuild, which drops them. false when nothing new
  // was pinned or the node is not cached. Pins do not apply to acquireCount.
  bool pin(terrain::NodeId node, terrain::BlockEdge side, int from, int to);
  const terrain::BoundaryPins* pins(terrain::NodeId node) const;  // nullptr when not cached

  // The cached mesh of `node`, or nullptr; does not count as a use.
  const terrain::BlockMesh* find(terrain::NodeId node) const;
  bool contains(terrain::NodeId node) const { return find(node) != nullptr; }
  // Drops `node` (its data changed); false when it was not cached.
  bool invalidate(terrain::NodeId node);
  // Drops every block and frees their memory; keeps the counters.
  void clear();

  void setEnabled(bool enabled) { m_options.enabled = enabled; }
  bool enabled() const { return m_options.enabled; }
  void setReuseOptions(const LodReuseOptions& reuse);
  void setBudget(std::size_t budgetBytes);
  std::size_t budgetBytes() const { return m_options.budgetBytes; }

  std::size_t bytes() const { return m_bytes; }  // sum of meshBytes over the cached blocks
  std::size_t size() const { return m_size; }    // cached blocks
  const LodCacheCounters& counters() const { return m_counters; }
  void resetCounters() { m_counters = LodCacheCounters{}; }
  // Share of lookups that reused the cached mesh (0 before any lookup).
  double reuseRate() const;

 private:
  struct Slot;
  static constexpr std::uint32_t kNone = 0xffffffffu;  // no slot

  std::uint32_t findSlot(terrain::NodeId node) const;
  // Counts the lookup; the node's slot, marked most recently used (cached = true), or a
  // fresh slot for it.
  std::uint32_t lookUp(terrain::NodeId node, bool& cached);
  std::uint32_t takeSlot(terrain::NodeId node);
  void indexInsert(std::uint32_t slot);
  void indexErase(std::uint32_t slot);
  void growIndex(std::size_t blocks);
  void linkFront(std::uint32_t slot);
  void unlink(std::uint32_t slot);
  void touch(std::uint32_t slot);
  void drop(std::uint32_t slot, bool keepMemory);
  bool evictable(std::uint32_t slot, std::uint32_t protect) const;
  void evictToBudget(std::uint32_t protect);
  void finishBuild(std::uint32_t slot, LodOutcome outcome);

  LodCacheOptions m_options;
  std::vector<std::unique_ptr<Slot>> m_slots;  // stable addresses: callers hold &mesh
  std::vector<std::uint32_t> m_free;           // unused slots
  std::vector<std::uint32_t> m_index;          // open addressing, linear probing: slot or empty
  std::uint32_t m_head = kNone;                // most recently used
  std::uint32_t m_tail = kNone;                // least recently used
  std::size_t m_size = 0;
  std::size_t m_bytes = 0;
  std::uint64_t m_frame = 0;
  LodCacheCounters m_counters;
  std::uint64_t m_builds = 0;  // numbers each build (BlockMesh::revision)
  terrain::RtinScratch m_scratch;
};

}  // namespace polder::cache
