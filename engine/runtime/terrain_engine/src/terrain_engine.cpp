#include <polder/terrain_engine.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <unordered_set>

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
#include "cut_index.hpp"
#include "dike_check.hpp"
#include "pyramid_dike_bound.hpp"
#include "resident_block.hpp"
#include "sample_grid.hpp"
#include "terrain_pieces.hpp"

namespace polder {

namespace {

using Clock = std::chrono::steady_clock;

double millisecondsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

std::size_t heightfieldBytes(const terrain::Heightfield& field) { return field.heights.capacity() * sizeof(float); }

// A border of the DEM as a grid two samples wide, the border repeated: its normals slope only
// along the border, the one direction its samples show.
terrain::Heightfield borderGrid(std::span<const float> border, bool column, double spacingX, double spacingY) {
  terrain::Heightfield grid;
  grid.width = column ? 2 : int(border.size());
  grid.height = column ? int(border.size()) : 2;
  grid.spacingX = spacingX;
  grid.spacingY = spacingY;
  grid.heights.resize(2 * border.size());
  for (std::size_t i = 0; i < border.size(); ++i) {
    if (column) {
      grid.heights[2 * i] = grid.heights[2 * i + 1] = border[i];
    } else {
      grid.heights[i] = grid.heights[border.size() + i] = border[i];
    }
  }
  return grid;
}

std::string megabytes(std::size_t bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f MB", double(bytes) / 1048576.0);
  return text;
}

// The least the loaders may hold of built blocks not yet collected (see Impl's loader).
constexpr std::size_t kLeastHeldBuildBytes = std::size_t(16) << 20;

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
  // The height source: one of the two.
  std::shared_ptr<const terrain::Heightfield> field;
  std::shared_ptr<const terrain::Pyramid> pyramid;
  double spacingX = 1.0, spacingY = 1.0;
  terrain::Heightfield eastBorder, northBorder;  // a pyramid's borders as grids (sample_grid.hpp)
  terrain::BlockLayout layout;
  terrain::BlockQuadtree quadtree;
  TerrainEngineOptions options;
  std::unique_ptr<core::ThreadPool> pool;

  // Error hierarchies of the nodes frames have needed, least recently needed evicted (the
  // selection's residency test touches every node it visits). The root's is kept apart and
  // never evicted: the cut falls back to it at worst, so it never has a hole.
  cache::LruCache<std::uint64_t, ResidentBlock> lods;
  std::size_t lodBudgetBytes = 0;
  std::unique_ptr<ResidentBlock> root;
  std::unordered_set<std::uint64_t> failedNodes;  // loads that failed: never asked for again
  std::unique_ptr<BlockLodLoader> loader;         // BlockLoading::Background
  int loaderThreads = 0;
  std::vector<BlockLodRequest> requests;  // this frame's, handed to the loader
  std::vector<LoadedBlockLod> arrived;    // collected from the loader
  std::vector<float> loadMs;
  TerrainLoadStats loadStats;
  std::uint64_t frameNumber = 0;
  // A load was turned away last frame: the budget is full of blocks the cut needs.
  bool budgetFullOfNeeds = false;
  // The camera's motion, for loading ahead of it.
  glm::dvec3 lastCameraPosition{0.0};
  bool haveLastCamera = false;
  std::vector<terrain::SelectedNode> predictedCut;
  cache::LodCache meshes;

  // Per-frame storage, reserved once.
  terrain::SelectionScratch selectionScratch;
  std::vector<terrain::SelectedNode> cut;
  std::vector<const terrain::BlockMesh*> cutMeshes;  // parallel to cut
  std::vector<SampleGrid> cutGrids;                  // parallel to cut: where its heights are
  DikeVertexSamples dikeSamples;
  std::vector<lod::RegionDemand> demands;
  std::vector<std::uint32_t> allocation;
  std::vector<std::size_t> visibleInCut;  // indices into cut of the visible nodes
  lod::AllocationScratch allocationScratch{0};
  terrain::DikeStage dikes;
  CutIndex cutIndex;  // the frame's cut by node, for the dike check and the pyramid's bounds
  std::unique_ptr<terrain::ExactDikeError> exactDikeErrors;  // a heightfield's
  std::unique_ptr<PyramidDikeBound> pyramidDikeBounds;       // a pyramid's
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

  Impl(std::shared_ptr<const terrain::Heightfield> f, std::shared_ptr<const terrain::Pyramid> source,
       terrain::BlockLayout l, terrain::BlockQuadtree q, const TerrainEngineOptions& o,
       std::unique_ptr<core::ThreadPool> p)
      : field(std::move(f)),
        pyramid(std::move(source)),
        spacingX(field ? field->spacingX : pyramid->header().spacingX),
        spacingY(field ? field->spacingY : pyramid->header().spacingY),
        layout(l),
        quadtree(std::move(q)),
        options(o),
        pool(std::move(p)),
        lods(o.lodDataBytes),
        lodBudgetBytes(o.lodDataBytes),
        meshes(cacheOptions(o)),
        dikes(layout),
        cutIndex(layout),
        exactDikeErrors(field ? std::make_unique<terrain::ExactDikeError>(*field) : nullptr),
        pyramidDikeBounds(field ? nullptr : std::make_unique<PyramidDikeBound>(*pyramid, cutIndex)),
        dikeCheck(field ? static_cast<const terrain::DikeTriangleMeasure&>(*exactDikeErrors) : *pyramidDikeBounds,
                  layout, cutIndex, spacingX, spacingY),
        pieces(GridSpacing{spacingX, spacingY}, layout) {
    if (field) {
      const SampleGrid whole{field.get(), 0, 0, 1};
      dikeSamples.eastBorder = dikeSamples.northBorder = whole;
    } else {
      eastBorder = borderGrid(pyramid->eastBorder(), true, spacingX, spacingY);
      northBorder = borderGrid(pyramid->northBorder(), false, spacingX, spacingY);
      dikeSamples.eastBorder = SampleGrid{&eastBorder, layout.width() - 2, 0, 1};
      dikeSamples.northBorder = SampleGrid{&northBorder, 0, layout.height() - 2, 1};
    }
    dikeSamples.eastX = layout.width() - 1;
    dikeSamples.stage = &dikes;
    selectionScratch.reserve(quadtree);
    const std::size_t bound = layout.reservedCutNodes();
    cut.reserve(bound);
    cutMeshes.reserve(bound);
    cutGrids.reserve(bound);
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
      loaderThreads = std::max(pool->threadCount() - 1, 1);
      // Built blocks wait outside the budget until a frame takes them (a budget full of needs
      // turns them away): at most an eighth of the hierarchies' budget of them, and no less
      // than kLeastHeldBuildBytes, so that a small budget still fills within a few frames.
      loader = std::make_unique<BlockLodLoader>(
          loaderThreads, [this](const terrain::NodeId& node) { return buildBlock(node); }, most,
          std::max(o.lodDataBytes / 8, kLeastHeldBuildBytes));
    }
  }
  ~Impl() { loader.reset(); }  // the workers' builds read the source

  // What a node needs to be drawn: its hierarchy, built from the heightfield or from the
  // node's tile (one read, checked) and its cells' residuals. Any thread.
  Result<ResidentBlock> buildBlock(const terrain::NodeId& node) const {
    ResidentBlock block;
    if (field) {
      auto lod = terrain::BlockLod::build(*field, layout.interior(node));
      if (!lod) return lod.error();
      block.lod = std::move(*lod);
      return block;
    }
    terrain::PyramidTile tile;
    if (Status read = pyramid->readTile(node, tile); !read) return read.error();
    auto lod = terrain::BlockLod::buildFromLevel(tile.samples, layout.interior(node), tile.cellResidual);
    if (!lod) return lod.error();
    block.lod = std::move(*lod);
    block.tile = std::move(tile);
    return block;
  }

  void noteFailure(const terrain::NodeId& node, const std::string& message) {
    ++loadStats.failures;
    if (loadStats.firstFailure.empty()) loadStats.firstFailure = message;
    failedNodes.insert(terrain::nodeKey(node));
  }

  // The resident block of `key`, marked as needed by this frame (collectLoads never evicts it
  // for a new one next frame), or null.
  ResidentBlock* findNeeded(std::uint64_t key) {
    ResidentBlock* cached = lods.find(key);
    if (cached) cached->lastNeededFrame = frameNumber;
    return cached;
  }

  // The node's block if resident; in Immediate mode built now if not. Null also for a node
  // with no whole cell inside the DEM, which selection never draws, and one whose load failed.
  const ResidentBlock* blockFor(const terrain::NodeId& node) {
    if (node == layout.root()) return root.get();
    const std::uint64_t key = terrain::nodeKey(node);
    if (ResidentBlock* cached = findNeeded(key)) return cached;
    if (loader || !drawable(node) || failedNodes.count(key)) return nullptr;
    auto built = buildBlock(node);
    if (!built) {
      noteFailure(node, built.error().message);
      return nullptr;
    }
    ++loadStats.loads;
    const std::size_t bytes = built->memoryBytes();
    return &lods.insert(key, std::move(*built), bytes);
  }
  const terrain::BlockLod* lodFor(const terrain::NodeId& node) {
    const ResidentBlock* block = blockFor(node);
    return block ? &block->lod : nullptr;
  }

  // Where the heights of cut node `i` are: the whole heightfield, or the node's tile.
  SampleGrid gridOf(const terrain::NodeId& node) const {
    if (field) return SampleGrid{field.get(), 0, 0, 1};
    const ResidentBlock* block = node == layout.root() ? root.get() : lods.peek(terrain::nodeKey(node));
    if (!block) return SampleGrid{};
    const terrain::SampleRect footprint = layout.footprint(node);
    return SampleGrid{&block->tile.samples, footprint.x0, footprint.y0, layout.stride(node), block->tile.cellResidual};
  }

  bool drawable(const terrain::NodeId& node) const { return std::isfinite(quadtree.info(node).floorDelta()); }

  // Selection may refine into `node`: its hierarchy is resident, or it cannot be drawn at
  // its stride (a DEM-edge node) and the children it gives way to are.
  bool resident(const terrain::NodeId& node) {
    if (node == layout.root() || findNeeded(terrain::nodeKey(node))) return true;
    if (drawable(node)) return !loader && blockFor(node);  // Immediate: built now
    if (node.level == 0) return false;
    for (int quadrant = 0; quadrant < 4; ++quadrant) {
      const terrain::NodeId child = node.child(quadrant);
      if (layout.exists(child) && !resident(child)) return false;
    }
    return true;
  }

  // The resident error hierarchies, the root's included.
  std::size_t residentLodBytes() const { return lods.bytes() + (root ? root->memoryBytes() : 0); }

  // Takes in what the loaders finished since the last frame.
  void collectLoads(TerrainFrameStats& stats) {
    if (!loader) return;
    if (!loader->collect(arrived)) {
      ++loadStats.handoffsDeferred;
      return;
    }
    // A block the last frame needed is never evicted for a new one: when the budget holds
    // no less, the new block is turned away and the cut stays where it is, coarser than tau
    // asks but steady, instead of trading blocks with the loaders every frame.
    const auto notNeededLastFrame = [this](const ResidentBlock& block) {
      return block.lastNeededFrame + 1 < frameNumber;
    };
    budgetFullOfNeeds = false;
    for (LoadedBlockLod& loaded : arrived) {
      if (!loaded.lod) {
        noteFailure(loaded.node, loaded.error);
        continue;
      }
      const std::size_t bytes = loaded.lod->memoryBytes();
      if (!lods.fitsEvicting(bytes, notNeededLastFrame)) {
        ++loadStats.turnedAway;
        budgetFullOfNeeds = true;
        continue;
      }
      lods.insert(terrain::nodeKey(loaded.node), std::move(*loaded.lod), bytes);
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
    const std::uint64_t key = terrain::nodeKey(node);
    if (!lods.peek(key) && !failedNodes.count(key)) requests.push_back(BlockLodRequest{node, priority});
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
    if (budgetFullOfNeeds) {
      // Only the present frame's most wanted few, one per loader: one may be worth more than
      // a block the cut leaves behind next frame, and the rest would be turned away.
      const std::size_t few = std::min(requests.size(), std::size_t(loaderThreads));
      std::partial_sort(requests.begin(), requests.begin() + std::ptrdiff_t(few), requests.end(),
                        [](const BlockLodRequest& a, const BlockLodRequest& b) { return a.priority > b.priority; });
      requests.resize(few);
      return postRequests(camera, stats);
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
          return node == layout.root() || lods.peek(terrain::nodeKey(node)) != nullptr || !drawable(node);
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
    // A split the dike check asked for happens once the node's children are resident.
    for (std::size_t i = 0; i < forcedSplits.size(); ++i) {
      const terrain::NodeId& node = forcedSplits[i];
      const double priority = projectedError(node, forcedSplitDistances[i], camera);
      for (int quadrant = 0; quadrant < 4; ++quadrant) {
        const terrain::NodeId child = node.child(quadrant);
        if (layout.exists(child) && !resident(child)) request(child, priority);
      }
    }
    postRequests(camera, stats);
  }
  void postRequests(const Camera& camera, TerrainFrameStats& stats) {
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
    // A pyramid's heights are only in resident tiles: the whole cut must be resident.
    selection.culledNeedResidency = pyramid != nullptr;
    if (loader || pyramid) {
      const auto isResident = [this](const terrain::NodeId& node) { return resident(node); };
      quadtree.select(camera, selection, selectionScratch, cut, isResident);
    } else {
      quadtree.select(camera, selection, selectionScratch, cut);
    }
    cutMeshes.assign(cut.size(), nullptr);
    cutGrids.clear();
    for (const terrain::SelectedNode& selected : cut) cutGrids.push_back(gridOf(selected.node));
    dikeSamples.cut = cutGrids;
    cutIndex.setCut(cut);
    if (pyramidDikeBounds) pyramidDikeBounds->setFrame(cut, dikeSamples);
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
    for (std::size_t i = 0; i < cut.size(); ++i)
      if (cut[i].visible && cutMeshes[i]) pieces.addBlock(cut[i].node, *cutMeshes[i], cutGrids[i]);
    if (dikesStitched) {
      cutNodes.clear();
      for (const terrain::SelectedNode& selected : cut) cutNodes.push_back(selected.node);
      pieces.addDikes(dikes.mesh().vertices, dikes.visibleIndices(), dikes.visibleOwners(), cutNodes, dikeSamples);
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

namespace {

Status checkOptions(const TerrainEngineOptions& options) {
  if (!(options.tauPx > 0.0) || !std::isfinite(options.tauPx))
    return makeError(ErrorKind::InvalidArgument, "the pixel tolerance must be positive");
  if (!(options.alpha > 0.0)) return makeError(ErrorKind::InvalidArgument, "the allocator's alpha must be positive");
  return {};
}

// The options with the memory budget split (TerrainEngineOptions::memoryBudgetBytes) once
// `fixed` bytes, the source and the quadtree, are counted.
Result<TerrainEngineOptions> withinBudget(const TerrainEngineOptions& options, std::size_t fixed) {
  TerrainEngineOptions budgeted = options;
  if (options.memoryBudgetBytes == 0) return budgeted;
  if (options.memoryBudgetBytes < fixed + kLeastBlockMemoryBytes)
    return makeError(ErrorKind::InvalidArgument, "a memory budget of " + megabytes(options.memoryBudgetBytes) +
                                                     " leaves less than " + megabytes(kLeastBlockMemoryBytes) +
                                                     " for block data after the height source and its quadtree (" +
                                                     megabytes(fixed) + ")");
  const std::size_t blockData = options.memoryBudgetBytes - fixed;
  budgeted.lodDataBytes = blockData / 2;
  budgeted.cacheBytes = blockData - blockData / 2;
  return budgeted;
}

}  // namespace

Result<std::unique_ptr<TerrainEngine>> TerrainEngine::assemble(std::unique_ptr<Impl> impl) {
  // The root's block, which every cut can fall back to. A root with no whole cell at its
  // stride is never drawn (selection refines it), so it needs none.
  const terrain::NodeId root = impl->layout.root();
  if (impl->drawable(root)) {
    auto built = impl->buildBlock(root);
    if (!built) return built.error();
    impl->root = std::make_unique<ResidentBlock>(std::move(*built));
  } else if (impl->pyramid) {
    return makeError(
        ErrorKind::InvalidData,
        impl->pyramid->path().string() + ": the DEM is too narrow to stream (its root block has no whole cell)");
  }
  return std::unique_ptr<TerrainEngine>(new TerrainEngine(std::move(impl)));
}

Result<std::unique_ptr<TerrainEngine>> TerrainEngine::create(std::shared_ptr<const terrain::Heightfield> field,
                                                             const TerrainEngineOptions& options,
                                                             const std::function<void(float)>& progress) {
  if (!field) return makeError(ErrorKind::InvalidArgument, "TerrainEngine::create needs a heightfield");
  if (Status valid = checkOptions(options); !valid) return valid.error();
  auto layout = terrain::BlockLayout::create(field->width, field->height, options.blockK);
  if (!layout) return layout.error();
  auto pool = std::make_unique<core::ThreadPool>(options.threads);
  terrain::BlockQuadtreeOptions treeOptions;
  treeOptions.progress = progress;
  treeOptions.pool = pool.get();
  auto quadtree = terrain::BlockQuadtree::build(*field, *layout, treeOptions);
  if (!quadtree) return quadtree.error();
  auto budgeted = withinBudget(options, heightfieldBytes(*field) + quadtree->memoryBytes());
  if (!budgeted) return budgeted.error();
  return assemble(
      std::make_unique<Impl>(std::move(field), nullptr, *layout, std::move(*quadtree), *budgeted, std::move(pool)));
}

Result<std::unique_ptr<TerrainEngine>> TerrainEngine::create(std::shared_ptr<const terrain::Pyramid> pyramid,
                                                             const TerrainEngineOptions& options,
                                                             const std::function<void(float)>& progress) {
  if (!pyramid) return makeError(ErrorKind::InvalidArgument, "TerrainEngine::create needs a pyramid");
  if (Status valid = checkOptions(options); !valid) return valid.error();
  const terrain::PyramidHeader& header = pyramid->header();
  if (options.blockK != header.k)
    return makeError(ErrorKind::InvalidArgument, pyramid->path().string() + " has blocks of " +
                                                     std::to_string((1 << header.k) + 1) + " samples, not " +
                                                     std::to_string((1 << options.blockK) + 1));
  if (progress) progress(0.0f);
  std::vector<terrain::NodeInfo> nodes;
  nodes.reserve(pyramid->nodes().size());
  for (const terrain::PyramidNode& node : pyramid->nodes())
    nodes.push_back(terrain::NodeInfo{node.minHeight, node.maxHeight, node.lodError, node.floorError, 0.0f});
  auto quadtree =
      terrain::BlockQuadtree::fromNodes(pyramid->layout(), header.spacingX, header.spacingY, std::move(nodes));
  if (!quadtree) return Error{quadtree.error().kind, pyramid->path().string() + ": " + quadtree.error().message};
  const std::size_t borders = 2 * (pyramid->eastBorder().size() + pyramid->northBorder().size()) * sizeof(float);
  auto budgeted = withinBudget(options, pyramid->memoryBytes() + borders + quadtree->memoryBytes());
  if (!budgeted) return budgeted.error();
  auto pool = std::make_unique<core::ThreadPool>(options.threads);
  const terrain::BlockLayout layout = pyramid->layout();
  auto engine = assemble(
      std::make_unique<Impl>(nullptr, std::move(pyramid), layout, std::move(*quadtree), *budgeted, std::move(pool)));
  if (progress) progress(1.0f);
  return engine;
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
  if (!s.loader) {
    // Immediate mode builds during the frame: evict to the budget now, and nothing until the
    // next frame, so that no block the frame has taken goes while the frame still uses it.
    s.lods.setBudget(s.lodBudgetBytes);
    s.lods.setBudget(std::numeric_limits<std::size_t>::max());
  }

  // 1. Select: the cut of the block quadtree for this view. A node's error here is what it
  //    cannot refine (its stride's floor): the view-dependent extraction below holds
  //    everything else within tau.
  s.expireForcedSplits(camera);
  ++s.frameNumber;
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
      mesh.normals.push_back(glm::normalize(normalOf(v)));
    }
    mesh.indices.assign(grid.indices.begin(), grid.indices.end());
  }
  return std::span<const MeshData>(s.pieceMeshes.data(), pieces.size());
}

terrain::WatertightReport TerrainEngine::checkWatertight() const { return m_impl->dikes.checkWatertight(); }

const TerrainFrame& TerrainEngine::frame() const { return m_impl->frame; }

const TerrainLoadStats& TerrainEngine::loadStats() const {
  Impl& s = *m_impl;
  s.loadStats.residentBlocks = s.lods.size() + (s.root ? 1 : 0);
  s.loadStats.residentBytes = s.residentLodBytes();
  s.loadStats.loadMs = s.loadMs;
  return s.loadStats;
}

TerrainMemory TerrainEngine::memory() const {
  const Impl& s = *m_impl;
  TerrainMemory memory;
  memory.sourceBytes =
      s.field ? heightfieldBytes(*s.field)
              : s.pyramid->memoryBytes() + heightfieldBytes(s.eastBorder) + heightfieldBytes(s.northBorder);
  memory.quadtreeBytes = s.quadtree.memoryBytes();
  memory.lodDataBytes = s.residentLodBytes();
  memory.lodDataBudgetBytes = s.lodBudgetBytes;
  memory.cacheBytes = s.meshes.bytes();
  memory.cacheBudgetBytes = s.meshes.budgetBytes();
  return memory;
}

void TerrainEngine::waitForLoads() {
  if (!m_impl->loader) return;
  ++m_impl->loadStats.frameWaits;
  m_impl->loader->waitIdle();
}
const terrain::Heightfield* TerrainEngine::field() const { return m_impl->field.get(); }
const terrain::Pyramid* TerrainEngine::pyramid() const { return m_impl->pyramid.get(); }
double TerrainEngine::spacingX() const { return m_impl->spacingX; }
double TerrainEngine::spacingY() const { return m_impl->spacingY; }
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
