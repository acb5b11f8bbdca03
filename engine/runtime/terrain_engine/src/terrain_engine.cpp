#include <polder/terrain_engine.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include <polder/cache/lod_cache.hpp>
#include <polder/cache/lru_cache.hpp>
#include <polder/lod/allocator.hpp>
#include <polder/lod/projected_area.hpp>
#include <polder/terrain/block_quadtree.hpp>
#include <polder/terrain/normals.hpp>
#include <polder/terrain/rtin.hpp>
#include <polder/thread_pool.hpp>

#include <polder/terrain/dike_stage.hpp>
#include "block_lod_loader.hpp"
#include "dike_check.hpp"
#include "terrain_pieces.hpp"

namespace polder {

namespace {

using Clock = std::chrono::steady_clock;

double millisecondsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

std::uint64_t nodeKey(const terrain::NodeId& node) {
  return (std::uint64_t(node.level) << 56) | (std::uint64_t(node.bx) << 28) | std::uint64_t(node.by);
}

std::size_t heightfieldBytes(const terrain::Heightfield& field) { return field.heights.capacity() * sizeof(float); }

std::string megabytes(std::size_t bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f MB", double(bytes) / 1048576.0);
  return text;
}

cache::LodCacheOptions cacheOptions(const TerrainEngineOptions& options) {
  cache::LodCacheOptions cache;
  cache.budgetBytes = options.cacheBytes;
  cache.enabled = options.cacheEnabled;
  // In budget mode a reused mesh may fall short of its share by this fraction; keep it small
  // so frames land close to the budget.
  cache.countHysteresis = 0.02;
  return cache;
}

}  // namespace

struct TerrainEngine::Impl {
  std::shared_ptr<const terrain::Heightfield> field;
  terrain::BlockLayout layout;
  terrain::BlockQuadtree quadtree;
  TerrainEngineOptions options;
  std::unique_ptr<core::ThreadPool> pool;

  // Error hierarchies of the nodes frames have needed, least recently needed evicted (the
  // selection's residency test touches every node it visits). The root's is kept apart and
  // never evicted: the cut falls back to it at worst, so it never has a hole.
  cache::LruCache<std::uint64_t, terrain::BlockLod> lods;
  std::unique_ptr<terrain::BlockLod> rootLod;
  std::unique_ptr<BlockLodLoader> loader;  // BlockLoading::Background
  std::vector<BlockLodRequest> requests;   // this frame's, handed to the loader
  std::vector<LoadedBlockLod> arrived;     // collected from the loader
  std::vector<float> loadMs;
  TerrainLoadStats loadStats;
  // The camera's motion, for loading ahead of it.
  glm::dvec3 lastCameraPosition{0.0};
  bool haveLastCamera = false;
  std::vector<terrain::SelectedNode> predictedCut;
  cache::LodCache meshes;

  // Per-frame storage, reserved once.
  terrain::SelectionScratch selectionScratch;
  std::vector<terrain::SelectedNode> cut;
  std::vector<const terrain::BlockMesh*> cutMeshes;  // parallel to cut
  std::vector<lod::RegionDemand> demands;
  std::vector<std::uint32_t> allocation;
  std::vector<std::size_t> visibleInCut;  // indices into cut of the visible nodes
  lod::AllocationScratch allocationScratch{0};
  terrain::DikeStage dikes;
  DikeCheck dikeCheck;
  struct LastCheck {  // the dike check's last run, for a frame that repeats it exactly
    Camera camera;
    double tauPx = 0.0;
    DikeCheckResult result;
    bool clean = false;  // nothing to pin or split: the same frame would pass unchanged
  } lastCheck;
  static constexpr std::size_t kMaxForcedSplits = 64;
  std::vector<terrain::NodeId> forcedSplits;  // SelectionOptions::forcedSplits, reserved
  std::vector<double> forcedSplitDistances;   // camera distance when each was added
  std::size_t lastDikeTriangles = 0;
  bool dikesStitched = false;  // this frame: false while the last frame's dikes stand
  // The frame between beginFrame and finishFrame.
  Clock::time_point frameStart{};
  TerrainFrameStats frameStats;
  cache::LodCacheCounters countersBefore{};
  TerrainFrame frame;
  TerrainPieces pieces;
  std::vector<terrain::NodeId> cutNodes;  // parallel to cut, for the dike pieces' owners
  std::vector<MeshData> pieceMeshes;      // frameMeshes() storage, reused

  Impl(std::shared_ptr<const terrain::Heightfield> f, terrain::BlockLayout l, terrain::BlockQuadtree q,
       const TerrainEngineOptions& o, std::unique_ptr<core::ThreadPool> p)
      : field(std::move(f)),
        layout(l),
        quadtree(std::move(q)),
        options(o),
        pool(std::move(p)),
        lods(o.lodDataBytes),
        meshes(cacheOptions(o)),
        dikes(*field, layout),
        dikeCheck(*field, layout),
        pieces(*field, layout) {
    selectionScratch.reserve(quadtree);
    const std::size_t bound = quadtree.selectionBound();
    cut.reserve(bound);
    cutMeshes.reserve(bound);
    demands.reserve(bound);
    allocation.reserve(bound);
    visibleInCut.reserve(bound);
    allocationScratch.reserve(bound);
    frame.blocks.reserve(bound);
    pieces.reserve(2 * bound);
    cutNodes.reserve(bound);
    dikeCheck.reserve(bound);
    forcedSplits.reserve(kMaxForcedSplits);
    forcedSplitDistances.reserve(kMaxForcedSplits);
    predictedCut.reserve(bound);
    if (options.loading == BlockLoading::Background) {
      // A blocked node asks for at most its four children; culled nodes for themselves.
      const std::size_t most = 4 * bound;
      requests.reserve(most);
      arrived.reserve(most);
      // One core is the frame's; the rest build.
      loader = std::make_unique<BlockLodLoader>(
          pool->threadCount() - 1,
          [this](const terrain::NodeId& node) { return terrain::BlockLod::build(*field, layout.interior(node)); },
          most);
    }
  }
  ~Impl() { loader.reset(); }  // the workers' builds read the field

  // The node's hierarchy if resident; in Immediate mode built now if not. Null also for a
  // node with no whole cell inside the DEM, which selection never draws.
  const terrain::BlockLod* lodFor(const terrain::NodeId& node) {
    if (node == layout.root()) return rootLod.get();
    const std::uint64_t key = nodeKey(node);
    if (terrain::BlockLod* cached = lods.find(key)) return cached;
    if (loader) return nullptr;
    auto built = terrain::BlockLod::build(*field, layout.interior(node));
    if (!built) return nullptr;
    const std::size_t bytes = built->memoryBytes();
    return &lods.insert(key, std::move(*built), bytes);
  }

  bool drawable(const terrain::NodeId& node) const { return std::isfinite(quadtree.info(node).floorDelta()); }

  // Selection may refine into `node`: its hierarchy is resident, or it cannot be drawn at
  // its stride (a DEM-edge node) and the children it gives way to are.
  bool resident(const terrain::NodeId& node) {
    if (node == layout.root() || lods.find(nodeKey(node))) return true;
    if (drawable(node) || node.level == 0) return false;
    for (int quadrant = 0; quadrant < 4; ++quadrant) {
      const terrain::NodeId child = node.child(quadrant);
      if (layout.exists(child) && !resident(child)) return false;
    }
    return true;
  }

  // The resident error hierarchies, the root's included.
  std::size_t residentLodBytes() const { return lods.bytes() + (rootLod ? rootLod->memoryBytes() : 0); }

  // Takes in what the loaders finished since the last frame.
  void collectLoads(TerrainFrameStats& stats) {
    if (!loader) return;
    if (!loader->collect(arrived)) {
      ++loadStats.handoffsDeferred;
      return;
    }
    for (LoadedBlockLod& loaded : arrived) {
      if (!loaded.lod) {
        ++loadStats.failures;
        continue;
      }
      const std::size_t bytes = loaded.lod->memoryBytes();
      lods.insert(nodeKey(loaded.node), std::move(*loaded.lod), bytes);
      loadMs.push_back(float(loaded.buildMs));
      ++loadStats.loads;
      ++stats.loadsArrived;
    }
    arrived.clear();
    loadStats.evictions = lods.counters().evictions;
  }

  // Asks for `node`, or where it cannot be drawn, for the children it gives way to.
  void request(const terrain::NodeId& node, double priority) {
    if (requests.size() == requests.capacity()) return;
    if (node.level > 0 && !drawable(node)) {
      for (int quadrant = 0; quadrant < 4; ++quadrant) {
        const terrain::NodeId child = node.child(quadrant);
        if (layout.exists(child) && !resident(child)) request(child, priority);
      }
      return;
    }
    if (!lods.peek(nodeKey(node))) requests.push_back(BlockLodRequest{node, priority});
  }

  // The projected error a node's absence leaves: its own, seen from `distance`.
  double projectedError(const terrain::NodeId& node, double distance, const Camera& camera) const {
    const double error = quadtree.info(node).floorDelta();
    return camera.errorProjectionConstant() * error / std::max(distance, std::max(camera.nearM, 1e-3));
  }

  // Background mode: what this frame lacks, most visible error first, then what the camera
  // will need half a second ahead on its present course, then the culled nodes of the cut,
  // whose sides only shape the dikes.
  void requestLoads(const Camera& camera, TerrainFrameStats& stats) {
    if (!loader) return;
    requests.clear();
    for (const terrain::SelectedNode& selected : cut) {
      if (!selected.visible || !selected.refinementBlocked) continue;
      const double priority = projectedError(selected.node, selected.distanceM, camera);
      for (int quadrant = 0; quadrant < 4; ++quadrant) {
        const terrain::NodeId child = selected.node.child(quadrant);
        if (layout.exists(child) && !resident(child)) request(child, priority);
      }
    }
    if (haveLastCamera) {
      constexpr double kLookaheadFrames = 30.0;
      Camera ahead = camera;
      ahead.position += (camera.position - lastCameraPosition) * kLookaheadFrames;
      if (ahead.position != camera.position) {
        terrain::SelectionOptions selection;
        selection.tolerancePx = options.tauPx;
        selection.errorMeasure = terrain::NodeErrorMeasure::Floor;
        const auto residentAhead = [this](const terrain::NodeId& node) {
          return node == layout.root() || lods.peek(nodeKey(node)) != nullptr || !drawable(node);
        };
        quadtree.select(ahead, selection, selectionScratch, predictedCut, residentAhead);
        for (const terrain::SelectedNode& selected : predictedCut) {
          if (!selected.visible || !selected.refinementBlocked) continue;
          // Ranked below every need of the present frame.
          const double priority = 1e-3 * projectedError(selected.node, selected.distanceM, ahead);
          for (int quadrant = 0; quadrant < 4; ++quadrant) {
            const terrain::NodeId child = selected.node.child(quadrant);
            if (layout.exists(child)) request(child, priority);
          }
        }
      }
    }
    for (const terrain::SelectedNode& selected : cut)
      if (!selected.visible && selected.node != layout.root()) request(selected.node, 1e-9);
    lastCameraPosition = camera.position;
    haveLastCamera = true;
    // Duplicates (a node wanted now and ahead) are skipped by the loader; the list's order
    // decides which copy counts.
    stats.loadsRequested = requests.size();
    if (!loader->post(requests)) ++loadStats.handoffsDeferred;
  }

  // K here bounds a vertical error's pixels anywhere in the view (Camera::errorProjectionConstant).
  terrain::LodView viewFor(const terrain::BlockLod& lod, const Camera& camera) const {
    return terrain::LodView{camera.position - lod.origin(), camera.errorProjectionConstant(), options.tauPx,
                            std::max(camera.nearM, 1e-3)};
  }

  void select(const Camera& camera) {
    terrain::SelectionOptions selection;
    selection.tolerancePx = options.mode == LodMode::PixelError ? options.tauPx : 1.0;
    selection.errorMeasure = terrain::NodeErrorMeasure::Floor;
    if (options.mode == LodMode::PixelError) selection.forcedSplits = forcedSplits;
    if (loader) {
      const auto isResident = [this](const terrain::NodeId& node) { return resident(node); };
      quadtree.select(camera, selection, selectionScratch, cut, isResident);
    } else {
      quadtree.select(camera, selection, selectionScratch, cut);
    }
    cutMeshes.assign(cut.size(), nullptr);
  }

  double distanceTo(const terrain::NodeId& node, const Camera& camera) const {
    const Aabb box = quadtree.box(node);
    return glm::length(glm::clamp(camera.position, box.minCorner, box.maxCorner) - camera.position);
  }

  // Adds nodes to split (dike_check.hpp); returns how many are new. Each is kept until the
  // camera is twice as far from it as when it was added.
  std::size_t forceSplits(std::span<const terrain::NodeId> nodes, const Camera& camera) {
    std::size_t added = 0;
    for (const terrain::NodeId& node : nodes) {
      if (std::find(forcedSplits.begin(), forcedSplits.end(), node) != forcedSplits.end()) continue;
      if (forcedSplits.size() == kMaxForcedSplits) {  // the oldest goes
        forcedSplits.erase(forcedSplits.begin());
        forcedSplitDistances.erase(forcedSplitDistances.begin());
      }
      forcedSplits.push_back(node);
      forcedSplitDistances.push_back(distanceTo(node, camera));
      ++added;
    }
    return added;
  }
  void expireForcedSplits(const Camera& camera) {
    for (std::size_t i = forcedSplits.size(); i-- > 0;) {
      if (distanceTo(forcedSplits[i], camera) <= 2.0 * forcedSplitDistances[i] + 1.0) continue;
      forcedSplits.erase(forcedSplits.begin() + std::ptrdiff_t(i));
      forcedSplitDistances.erase(forcedSplitDistances.begin() + std::ptrdiff_t(i));
    }
  }

  // Error mode: every node of the cut at tau (culled ones too: their sides feed the dikes).
  void extractForError(const Camera& camera) {
    for (std::size_t i = 0; i < cut.size(); ++i) acquireForError(i, camera);
  }
  void acquireForError(std::size_t i, const Camera& camera) {
    const terrain::BlockLod* lod = lodFor(cut[i].node);
    cutMeshes[i] = lod ? &meshes.acquire(cut[i].node, *lod, viewFor(*lod, camera)) : nullptr;
  }

  // Error mode: stitch, check the drawn dike triangles against tau (dike_check.hpp), and
  // while the check pins block sides, rebuild those blocks and stitch again.
  DikeCheckResult stitchWithinTolerance(const Camera& camera) {
    constexpr int kMaxRounds = 16;
    for (int round = 1;; ++round) {
      const bool stitched = dikes.stitch(cut, cutMeshes);
      dikesStitched |= stitched;
      // The same dikes seen from the same camera pass as they passed last time.
      if (!stitched && lastCheck.clean && camera == lastCheck.camera && options.tauPx == lastCheck.tauPx)
        return lastCheck.result;
      const DikeCheckResult result = dikeCheck.check(camera, options.tauPx, dikes, cut, cutMeshes, meshes);
      const bool settled = dikeCheck.repinned().empty();
      lastCheck = LastCheck{camera, options.tauPx, result, settled && dikeCheck.splits().empty()};
      if (settled || round == kMaxRounds) return result;
      for (const std::uint32_t i : dikeCheck.repinned()) acquireForError(i, camera);
    }
  }

  // Budget mode, once per frame: the visible blocks' weights (projected area of their boxes)
  // and the coarsest meshes of the culled nodes, which only their sides (for the dikes) need.
  void prepareBudget(const Camera& camera) {
    const lod::AreaView areaView = lod::makeAreaView(camera);
    demands.clear();
    visibleInCut.clear();
    const auto maxTriangles = std::uint32_t(terrain::blockMeshTriangleBound(layout.k()));
    for (std::size_t i = 0; i < cut.size(); ++i) {
      if (!cut[i].visible) {
        const terrain::BlockLod* lod = lodFor(cut[i].node);
        cutMeshes[i] = lod ? &meshes.acquireCount(cut[i].node, *lod, 0) : nullptr;
        continue;
      }
      const Aabb box = quadtree.box(cut[i].node);
      const double area = lod::visibleAreaPx(lod::orientedBoxFromAabb(box.minCorner, box.maxCorner), areaView);
      demands.push_back(lod::RegionDemand{std::max(area, 1e-9), 2, maxTriangles});
      visibleInCut.push_back(i);
    }
    allocation.resize(demands.size());
  }

  // Budget mode, per attempt: the allocator splits the blocks' share of the budget over the
  // visible blocks (ASLOD, Schmalstieg and Fuhrmann 1999, section 3) and each extracts its best mesh for its share.
  void extractForBudget(std::uint64_t blockBudget) {
    lod::allocateTriangles(demands, blockBudget, options.alpha, allocation, allocationScratch);
    for (std::size_t v = 0; v < visibleInCut.size(); ++v) {
      const std::size_t i = visibleInCut[v];
      const terrain::BlockLod* lod = lodFor(cut[i].node);
      if (lod) cutMeshes[i] = &meshes.acquireCount(cut[i].node, *lod, allocation[v]);
    }
  }

  void updatePieces() {
    pieces.beginFrame();
    for (const TerrainBlockDraw& block : frame.blocks) pieces.addBlock(block.node, *block.mesh);
    if (dikesStitched) {
      cutNodes.clear();
      for (const terrain::SelectedNode& selected : cut) cutNodes.push_back(selected.node);
      pieces.addDikes(dikes.mesh().vertices, dikes.visibleIndices(), dikes.visibleOwners(), cutNodes);
    } else {
      pieces.keepDikes();
    }
    pieces.finishFrame();
    frame.pieces = pieces.pieces();
    frame.created = pieces.created();
    frame.changed = pieces.changed();
    frame.retired = pieces.retired();
  }

  std::size_t visibleBlockTriangles() const {
    std::size_t triangles = 0;
    for (std::size_t i = 0; i < cut.size(); ++i)
      if (cut[i].visible && cutMeshes[i]) triangles += cutMeshes[i]->triangleCount();
    return triangles;
  }
};

Result<std::unique_ptr<TerrainEngine>> TerrainEngine::create(std::shared_ptr<const terrain::Heightfield> field,
                                                             const TerrainEngineOptions& options,
                                                             const std::function<void(float)>& progress) {
  if (!field) return makeError(ErrorKind::InvalidArgument, "TerrainEngine::create needs a heightfield");
  if (!(options.tauPx > 0.0) || !std::isfinite(options.tauPx))
    return makeError(ErrorKind::InvalidArgument, "the pixel tolerance must be positive");
  if (!(options.alpha > 0.0)) return makeError(ErrorKind::InvalidArgument, "the allocator's alpha must be positive");
  auto layout = terrain::BlockLayout::create(field->width, field->height, options.blockK);
  if (!layout) return layout.error();
  auto pool = std::make_unique<core::ThreadPool>(options.threads);
  terrain::BlockQuadtreeOptions treeOptions;
  treeOptions.progress = progress;
  treeOptions.pool = pool.get();
  auto quadtree = terrain::BlockQuadtree::build(*field, *layout, treeOptions);
  if (!quadtree) return quadtree.error();
  TerrainEngineOptions budgeted = options;
  if (options.memoryBudgetBytes > 0) {
    const std::size_t fixed = heightfieldBytes(*field) + quadtree->memoryBytes();
    if (options.memoryBudgetBytes < fixed + kLeastBlockMemoryBytes)
      return makeError(ErrorKind::InvalidArgument, "a memory budget of " + megabytes(options.memoryBudgetBytes) +
                                                       " leaves less than " + megabytes(kLeastBlockMemoryBytes) +
                                                       " for block data after the heightfield and its quadtree (" +
                                                       megabytes(fixed) + ")");
    const std::size_t blockData = options.memoryBudgetBytes - fixed;
    budgeted.lodDataBytes = blockData / 2;
    budgeted.cacheBytes = blockData - blockData / 2;
  }
  // The root's hierarchy, which every cut can fall back to. A root with no whole cell at its
  // stride is never drawn (selection refines it), so it needs none.
  std::unique_ptr<terrain::BlockLod> rootLod;
  if (std::isfinite(quadtree->info(layout->root()).floorDelta())) {
    auto built = terrain::BlockLod::build(*field, layout->interior(layout->root()));
    if (!built) return built.error();
    rootLod = std::make_unique<terrain::BlockLod>(std::move(*built));
  }
  auto impl = std::make_unique<Impl>(std::move(field), *layout, std::move(*quadtree), budgeted, std::move(pool));
  impl->rootLod = std::move(rootLod);
  return std::unique_ptr<TerrainEngine>(new TerrainEngine(std::move(impl)));
}

TerrainEngine::TerrainEngine(std::unique_ptr<Impl> impl) : m_impl(std::move(impl)) {}
TerrainEngine::~TerrainEngine() = default;

const TerrainFrame& TerrainEngine::update(const Camera& camera) {
  beginFrame(camera);
  return finishFrame(camera, m_impl->options.budgetTriangles);
}

const TerrainFrame& TerrainEngine::updateSettled(const Camera& camera) {
  // Each round loads at least the next level of what is missing; the dike check's splits
  // may add a few rounds.
  const int rounds = 4 * (m_impl->layout.root().level + 2);
  for (int round = 0; round < rounds; ++round) {
    const TerrainFrame& frame = update(camera);
    if (!m_impl->loader || (frame.stats.blocksOnAncestor == 0 && frame.stats.loadsRequested == 0)) return frame;
    waitForLoads();
  }
  return update(camera);
}

std::span<const lod::RegionDemand> TerrainEngine::beginFrame(const Camera& camera) {
  Impl& s = *m_impl;
  s.frameStart = Clock::now();
  s.frameStats = TerrainFrameStats{};
  s.dikesStitched = false;
  s.meshes.beginFrame();
  s.countersBefore = s.meshes.counters();

  // 1. Select: the cut of the block quadtree for this view. A node's error here is what it
  //    cannot refine (its stride's floor): the view-dependent extraction below holds
  //    everything else within tau.
  s.expireForcedSplits(camera);
  const auto start = Clock::now();
  s.collectLoads(s.frameStats);
  s.select(camera);
  s.requestLoads(camera, s.frameStats);
  if (s.options.mode == LodMode::TriangleBudget) s.prepareBudget(camera);
  s.frameStats.selectMs = millisecondsSince(start);
  if (s.options.mode == LodMode::TriangleBudget) return s.demands;
  return {};
}

const TerrainFrame& TerrainEngine::finishFrame(const Camera& camera, std::uint64_t budgetTriangles) {
  Impl& s = *m_impl;
  TerrainFrameStats& stats = s.frameStats;
  const cache::LodCacheCounters before = s.countersBefore;

  // 2. LOD per block, from the cache; 3. dikes between them.
  auto start = Clock::now();
  double dikesMs = 0.0;
  if (s.options.mode == LodMode::PixelError) {
    // Where the dike check finds coarse dike strips that pins cannot cure, split their nodes
    // and do the frame again (at most four passes; the splits stay, so the next frames start
    // with them).
    for (int pass = 1;; ++pass) {
      s.extractForError(camera);
      const auto dikesStart = Clock::now();
      const DikeCheckResult check = s.stitchWithinTolerance(camera);
      dikesMs += millisecondsSince(dikesStart);
      stats.dikeTrianglesOverTau = check.failing;
      stats.dikeErrorPx = check.worstPx;
      if (pass == 4) break;
      const std::size_t splits = s.forceSplits(s.dikeCheck.splits(), camera);
      stats.dikeSplits += splits;
      if (splits == 0) break;
      const auto selectStart = Clock::now();
      s.select(camera);
      stats.selectMs += millisecondsSince(selectStart);
    }
  } else {
    // The dikes count inside the budget: give the blocks what last frame's dikes left, then
    // correct (up to three times) while the frame misses 0.95P..P.
    const std::uint64_t budget = budgetTriangles;
    std::uint64_t blockBudget = budget > s.lastDikeTriangles ? budget - s.lastDikeTriangles : budget / 2;
    for (int attempt = 0; attempt < 4; ++attempt) {
      s.extractForBudget(blockBudget);
      const auto dikesStart = Clock::now();
      s.dikesStitched |= s.dikes.stitch(s.cut, s.cutMeshes);
      dikesMs += millisecondsSince(dikesStart);
      const std::uint64_t total = s.visibleBlockTriangles() + s.dikes.visibleTriangleCount();
      if (total <= budget && total >= budget - budget / 20) break;
      const std::int64_t correction = std::int64_t(budget) - std::int64_t(budget / 40) - std::int64_t(total);
      blockBudget = std::uint64_t(std::max<std::int64_t>(std::int64_t(blockBudget) + correction, 0));
    }
    s.lastDikeTriangles = s.dikes.visibleTriangleCount();
  }
  stats.lodMs = millisecondsSince(start) - dikesMs;
  stats.dikesMs = dikesMs;

  s.frame.blocks.clear();
  for (std::size_t i = 0; i < s.cut.size(); ++i) {
    if (!s.cut[i].visible) {
      ++stats.culledBlocks;
      continue;
    }
    if (!s.cutMeshes[i]) continue;
    ++stats.visibleBlocks;
    if (s.cut[i].refinementBlocked) ++stats.blocksOnAncestor;
    stats.blockTriangles += s.cutMeshes[i]->triangleCount();
    s.frame.blocks.push_back(TerrainBlockDraw{s.cut[i].node, s.cutMeshes[i]});
  }
  s.frame.dikes = TerrainDikes{s.dikes.mesh().vertices, s.dikes.visibleIndices()};
  stats.dikeTriangles = s.dikes.visibleTriangleCount();
  const cache::LodCacheCounters& after = s.meshes.counters();
  stats.cacheLookups = after.lookups - before.lookups;
  stats.cacheHits = after.hits - before.hits;
  stats.cacheRebuilds = after.rebuilds - before.rebuilds;

  // 5. Emit: the frame's pieces, with host-ready data for the new and changed ones.
  const auto piecesStart = Clock::now();
  s.updatePieces();
  stats.piecesMs = millisecondsSince(piecesStart);
  stats.dikesStitched = s.dikesStitched;
  stats.piecesCreated = s.frame.created.size();
  stats.piecesChanged = s.frame.changed.size();
  stats.piecesRetired = s.frame.retired.size();
  stats.pieceBytesProduced = s.pieces.bytesProduced();
  stats.totalMs = millisecondsSince(s.frameStart);
  s.frame.stats = stats;
  return s.frame;
}

std::span<const MeshData> TerrainEngine::frameMeshes() {
  Impl& s = *m_impl;
  const std::span<const TerrainPiece> pieces = s.frame.pieces;
  if (s.pieceMeshes.size() < pieces.size()) s.pieceMeshes.resize(pieces.size());
  // Every piece relative to one shared sample (the middle piece's anchor): a sample two pieces
  // share then becomes the same floats in both, so rays find no slivers between them.
  const GridAnchor shared = pieces.empty() ? GridAnchor{} : pieces[pieces.size() / 2].mesh.anchor;
  for (std::size_t p = 0; p < pieces.size(); ++p) {
    const GridMeshView& grid = pieces[p].mesh;
    MeshData& mesh = s.pieceMeshes[p];
    mesh.origin = glm::dvec3(double(shared.x) * grid.spacing.x, double(shared.y) * grid.spacing.y, 0.0);
    mesh.positions.clear();
    mesh.normals.clear();
    const double offsetX = double(grid.anchor.x - shared.x), offsetY = double(grid.anchor.y - shared.y);
    for (const GridMeshVertex& v : grid.vertices) {
      mesh.positions.emplace_back(float((offsetX + double(v.x)) * grid.spacing.x),
                                  float((offsetY + double(v.y)) * grid.spacing.y), v.z);
      mesh.normals.push_back(
          terrain::sampleNormal(*s.field, int(grid.anchor.x) + int(v.x), int(grid.anchor.y) + int(v.y)));
    }
    mesh.indices.assign(grid.indices.begin(), grid.indices.end());
  }
  return std::span<const MeshData>(s.pieceMeshes.data(), pieces.size());
}

terrain::WatertightReport TerrainEngine::checkWatertight() const { return m_impl->dikes.checkWatertight(); }

const TerrainFrame& TerrainEngine::frame() const { return m_impl->frame; }

const TerrainLoadStats& TerrainEngine::loadStats() const {
  Impl& s = *m_impl;
  s.loadStats.residentBlocks = s.lods.size() + (s.rootLod ? 1 : 0);
  s.loadStats.residentBytes = s.residentLodBytes();
  s.loadStats.loadMs = s.loadMs;
  return s.loadStats;
}

TerrainMemory TerrainEngine::memory() const {
  const Impl& s = *m_impl;
  TerrainMemory memory;
  memory.heightfieldBytes = heightfieldBytes(*s.field);
  memory.quadtreeBytes = s.quadtree.memoryBytes();
  memory.lodDataBytes = s.residentLodBytes();
  memory.lodDataBudgetBytes = s.lods.budgetBytes();
  memory.cacheBytes = s.meshes.bytes();
  memory.cacheBudgetBytes = s.meshes.budgetBytes();
  return memory;
}

void TerrainEngine::waitForLoads() {
  if (!m_impl->loader) return;
  ++m_impl->loadStats.frameWaits;
  m_impl->loader->waitIdle();
}
const terrain::Heightfield& TerrainEngine::field() const { return *m_impl->field; }
const terrain::BlockLayout& TerrainEngine::layout() const { return m_impl->layout; }
const TerrainEngineOptions& TerrainEngine::options() const { return m_impl->options; }

void TerrainEngine::setOptions(const TerrainEngineOptions& options) {
  Impl& s = *m_impl;
  s.options.tauPx = options.tauPx > 0.0 ? options.tauPx : s.options.tauPx;
  s.options.mode = options.mode;
  s.options.budgetTriangles = options.budgetTriangles;
  s.options.alpha = options.alpha > 0.0 ? options.alpha : s.options.alpha;
  s.options.cacheEnabled = options.cacheEnabled;
  s.meshes.setEnabled(options.cacheEnabled);
}

}  // namespace polder
