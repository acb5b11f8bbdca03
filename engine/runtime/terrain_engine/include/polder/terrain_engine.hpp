// polder::terrain_engine — one frame of terrain (docs/design.md "One frame"): select the block
// quadtree cut, get each visible block's mesh from the LOD cache (or rebuild it), stitch
// the dikes, and, in budget mode, split a triangle budget over the blocks first; then hand
// out the frame's pieces with their lifetimes (polder/terrain_frame.hpp).
//
//   auto engine = TerrainEngine::create(field, options);        // preprocessing, with progress
//   auto engine = TerrainEngine::create(pyramid, options);      // or streamed from a pyramid
//   const TerrainFrame& frame = (*engine)->update(camera);      // every frame
//   for (std::uint32_t i : frame.created) ... upload frame.pieces[i].mesh ...
//   for (std::uint32_t i : frame.changed) ... replace frame.pieces[i].mesh ...
//   for (TerrainPieceKey key : frame.retired) ... free ...
//   for (const TerrainPiece& piece : frame.pieces) ... draw ...
//
// Thread contract: update() and everything reading its frame run on one thread (the frame
// thread). In steady state (camera still, cache warm) update() does not allocate.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <polder/camera.hpp>
#include <polder/lod/allocator.hpp>
#include <polder/mesh_data.hpp>
#include <polder/result.hpp>
#include <polder/terrain/block_layout.hpp>
#include <polder/terrain/block_mesh.hpp>
#include <polder/terrain/dikes.hpp>
#include <polder/terrain/heightfield.hpp>
#include <polder/terrain/pyramid.hpp>
#include <polder/terrain/watertight.hpp>
#include <polder/terrain_frame.hpp>

namespace polder {

enum class LodMode {
  PixelError,      // every block within tauPx of measured screen-space error
  TriangleBudget,  // the allocator splits budgetTriangles over the visible blocks
};

// Where blocks' error hierarchies (BlockLod) are built when a frame first needs them.
enum class BlockLoading {
  // On the engine's loader threads (threads - 1 of them, at least one): the frame thread
  // never builds one. Until a block's is
  // ready the frame draws the block's resident ancestor instead (TerrainFrameStats::
  // blocksOnAncestor), never a hole. For flights.
  Background,
  // On the frame thread, at once: every frame is at its selected level, at the cost of
  // stalls while the view changes. For single pictures and exact comparisons.
  Immediate,
};

struct TerrainEngineOptions {
  int blockK = 5;  // blocks of 2^k + 1 samples: 17, 33, 65, 129
  LodMode mode = LodMode::PixelError;
  double tauPx = 1.0;
  std::uint64_t budgetTriangles = 200000;  // dike triangles count inside the budget
  double alpha = 3.0;                      // the allocator's attenuation exponent
  std::size_t cacheBytes = std::size_t(256) << 20;
  bool cacheEnabled = true;  // false: rebuild every block every frame (for comparisons)
  // Threads for create()'s preprocessing and each frame's parallel parts; the loaders are
  // one fewer. <= 0: one per hardware thread.
  int threads = 0;
  BlockLoading loading = BlockLoading::Background;
  // Resident error hierarchies (about 22 KB a 33^2 block), least recently needed evicted.
  std::size_t lodDataBytes = std::size_t(128) << 20;
  // One budget for what the engine holds, when non-zero: the height source (the heightfield,
  // or the pyramid's node table and borders) and the quadtree count first, and what they
  // leave is split evenly between the resident error hierarchies and the LOD cache, in place
  // of lodDataBytes and cacheBytes. create() refuses a budget that leaves less than
  // kLeastBlockMemoryBytes for them.
  std::size_t memoryBudgetBytes = 0;
};

// The least a memory budget must leave for block data after the height source and quadtree.
inline constexpr std::size_t kLeastBlockMemoryBytes = std::size_t(8) << 20;

// What the engine holds, by part, and the budgets of the parts that have one.
struct TerrainMemory {
  std::size_t sourceBytes = 0;  // the heightfield, or the pyramid's node table and borders
  std::size_t quadtreeBytes = 0;
  std::size_t lodDataBytes = 0;  // resident error hierarchies (with their tiles), the root's included
  std::size_t lodDataBudgetBytes = 0;
  std::size_t cacheBytes = 0;  // the LOD cache's meshes
  std::size_t cacheBudgetBytes = 0;
  std::size_t totalBytes() const { return sourceBytes + quadtreeBytes + lodDataBytes + cacheBytes; }
};

// The loads since the engine was made.
struct TerrainLoadStats {
  std::uint64_t loads = 0;  // hierarchies built
  // Loads that failed (a tile missing, short or corrupt, a read error): the block stays on its
  // ancestor and is not asked for again. The first failure's message, naming the file and node.
  std::uint64_t failures = 0;
  std::string firstFailure;
  std::uint64_t evictions = 0;
  // Built blocks turned away because the budget was full of blocks the last frame needed
  // (none of those is evicted for a new one): the cut stays on ancestors there.
  std::uint64_t turnedAway = 0;
  // Times the frame thread waited for the loaders: waitForLoads(), which updateSettled()
  // calls; update() never waits.
  std::uint64_t frameWaits = 0;
  // Hand-offs to or from the loaders put off to the next frame because a loader held them.
  std::uint64_t handoffsDeferred = 0;
  std::size_t residentBlocks = 0;
  std::size_t residentBytes = 0;
  std::span<const float> loadMs;  // per load, in order; valid until the next update()
};

class TerrainEngine {
 public:
  static Result<std::unique_ptr<TerrainEngine>> create(std::shared_ptr<const terrain::Heightfield> field,
                                                       const TerrainEngineOptions& options = {},
                                                       const std::function<void(float)>& progress = {});
  // Streams from a pyramid (docs/streaming.md): the quadtree from its node table, blocks from
  // their tiles on the loader threads, never the full resolution. options.blockK must be the
  // pyramid's. Fails when the root's tile cannot be read.
  static Result<std::unique_ptr<TerrainEngine>> create(std::shared_ptr<const terrain::Pyramid> pyramid,
                                                       const TerrainEngineOptions& options = {},
                                                       const std::function<void(float)>& progress = {});
  ~TerrainEngine();
  TerrainEngine(const TerrainEngine&) = delete;
  TerrainEngine& operator=(const TerrainEngine&) = delete;

  const TerrainFrame& update(const Camera& camera);
  // update(), repeated after waiting for the loads each frame asks for until every visible
  // block is at its selected level: for a single picture, a test or a measurement of the
  // selected level, never in a flight (it waits). update() itself in Immediate mode.
  const TerrainFrame& updateSettled(const Camera& camera);
  // The last frame update() or finishFrame() returned (empty before the first).
  const TerrainFrame& frame() const;

  // update() in two halves, for a caller whose allocator splits one budget over the terrain
  // and other regions (polder::scene): beginFrame selects the cut and, in budget mode,
  // returns the visible blocks' demands (projected-area weights, triangle ranges);
  // finishFrame then extracts and stitches within `budgetTriangles` (the terrain's share,
  // dikes included; ignored in error mode). The span lives until finishFrame.
  std::span<const lod::RegionDemand> beginFrame(const Camera& camera);
  const TerrainFrame& finishFrame(const Camera& camera, std::uint64_t budgetTriangles);

  // The last frame's pieces as world-space meshes, one per entry of frame.pieces in the same
  // order (positions relative to one sample the pieces share, with normals): for Embree measurement
  // and export, not for drawing (draw the pieces, polder/terrain_frame.hpp). The storage is
  // reused, so once frames stop growing this allocates nothing; valid until the next call.
  std::span<const MeshData> frameMeshes();

  // Checks the last frame's whole cut, blocks and dikes together, on the integer sample
  // grid: open edges, T-junctions, overlaps, holes. Allocates; for tests and benchmarks.
  terrain::WatertightReport checkWatertight() const;

  const TerrainLoadStats& loadStats() const;
  TerrainMemory memory() const;
  // Blocks until the loads the last frame asked for are built (none in Immediate mode).
  void waitForLoads();

  // The heightfield the engine was made from; null when it streams from a pyramid.
  const terrain::Heightfield* field() const;
  const terrain::Pyramid* pyramid() const;  // null for a heightfield
  // The DEM's spacing, metres between samples.
  double spacingX() const;
  double spacingY() const;
  const terrain::BlockLayout& layout() const;
  const TerrainEngineOptions& options() const;
  void setOptions(const TerrainEngineOptions& options);  // tau, mode, budget, cache switch

 private:
  struct Impl;
  explicit TerrainEngine(std::unique_ptr<Impl> impl);
  static Result<std::unique_ptr<TerrainEngine>> assemble(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> m_impl;
};

}  // namespace polder
