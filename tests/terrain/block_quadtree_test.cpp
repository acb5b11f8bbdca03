#include <polder/terrain/block_quadtree.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <new>
#include <random>
#include <span>
#include <vector>

#include <gtest/gtest.h>
#include <glm/glm.hpp>

#include <polder/terrain/rtin.hpp>

// Allocation counting for the steady-state test: every operator new of this test program
// goes through here. Counting only; the behaviour is malloc's.
namespace {
std::atomic<std::size_t> g_allocations{0};
}  // namespace

void* operator new(std::size_t size) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  return std::malloc(size == 0 ? 1 : size);
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  return std::malloc(size == 0 ? 1 : size);
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }

namespace polder::terrain {
namespace {

// Rolling hills with ridges, a plateau, a flat lake and per-sample noise: enough variety
// that every level has real errors, and sizes that clip edge blocks.
Heightfield makeField(int width, int height, std::uint64_t seed, double spacing = 30.0) {
  Heightfield field(width, height, spacing, spacing);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> noise(-3.0, 3.0);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      double h =
          400.0 + 250.0 * std::sin(x * 0.031) * std::cos(y * 0.027) + 120.0 * std::abs(std::sin(0.011 * (x + 2 * y)));
      h += 40.0 * std::sin(x * 0.21 + y * 0.17) + noise(rng);
      if (x > width / 2 && y > height / 2) h = std::min(h, 520.0);  // a plateau
      if (x < width / 4 && y < height / 4) h = 300.0;               // a lake
      field.at(x, y) = float(h);
    }
  }
  return field;
}

BlockQuadtree buildTree(const Heightfield& field, const BlockLayout& layout, BlockQuadtreeOptions options = {}) {
  auto tree = BlockQuadtree::build(field, layout, options);
  EXPECT_TRUE(tree.ok()) << (tree.ok() ? "" : tree.error().message);
  return std::move(tree).value();
}

template <class F>
void forEachNode(const BlockLayout& layout, F&& f) {
  for (int level = 0; level <= layout.rootLevel(); ++level) {
    for (int by = 0; by < layout.nodesY(level); ++by) {
      for (int bx = 0; bx < layout.nodesX(level); ++bx)
        f(NodeId{std::uint8_t(level), std::uint32_t(bx), std::uint32_t(by)});
    }
  }
}

Camera randomCamera(std::mt19937_64& rng, const Heightfield& field) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Camera camera;
  const int sx = int(unit(rng) * (field.width - 1)), sy = int(unit(rng) * (field.height - 1));
  camera.position =
      glm::dvec3(sx * field.spacingX, sy * field.spacingY, field.at(sx, sy) + 2.0 + 400.0 * unit(rng) * unit(rng));
  // A few cameras off the DEM, looking at it or away.
  if (unit(rng) < 0.15) camera.position.x += (unit(rng) < 0.5 ? -1.0 : 1.0) * field.extentX() * 0.7;
  camera.yawDeg = 360.0 * unit(rng);
  camera.pitchDeg = -75.0 + 90.0 * unit(rng);
  camera.fovYDeg = 45.0 + 30.0 * unit(rng);
  camera.widthPx = 1280;
  camera.heightPx = 720;
  camera.nearM = 1.0;
  camera.farM = 5.0e4;
  return camera;
}

// Every level-0 block is covered by exactly one output node: the cut tiles the DEM.
void expectTiling(const BlockLayout& layout, const std::vector<SelectedNode>& cut) {
  const int nx = layout.nodesX(0), ny = layout.nodesY(0);
  std::vector<int> cover(std::size_t(nx) * std::size_t(ny), 0);
  for (const SelectedNode& s : cut) {
    ASSERT_TRUE(layout.exists(s.node));
    const int span = 1 << s.node.level;
    for (int by = int(s.node.by) * span; by < std::min(ny, int(s.node.by + 1) * span); ++by) {
      for (int bx = int(s.node.bx) * span; bx < std::min(nx, int(s.node.bx + 1) * span); ++bx) {
        ++cover[std::size_t(by) * std::size_t(nx) + std::size_t(bx)];
      }
    }
  }
  for (int by = 0; by < ny; ++by) {
    for (int bx = 0; bx < nx; ++bx) {
      ASSERT_EQ(cover[std::size_t(by) * std::size_t(nx) + std::size_t(bx)], 1) << "level-0 block " << bx << ", " << by;
    }
  }
}

// The output node whose footprint holds level-0 block (bx, by).
const SelectedNode* coveringNode(const std::vector<SelectedNode>& cut, int bx, int by) {
  for (const SelectedNode& s : cut) {
    if ((unsigned(bx) >> s.node.level) == s.node.bx && (unsigned(by) >> s.node.level) == s.node.by) return &s;
  }
  return nullptr;
}

TEST(BlockQuadtree, HeightRangesAreExactOverWholeFootprints) {
  const Heightfield field = makeField(230, 201, 1);
  for (int k : {3, 5}) {
    const BlockLayout layout = *BlockLayout::create(field.width, field.height, k);
    const BlockQuadtree tree = buildTree(field, layout);
    forEachNode(layout, [&](NodeId node) {
      const SampleRect area = layout.footprint(node);
      float lo = std::numeric_limits<float>::infinity(), hi = -lo;
      for (int y = area.y0; y <= area.y1; ++y) {
        for (int x = area.x0; x <= area.x1; ++x) {
          lo = std::min(lo, field.at(x, y));
          hi = std::max(hi, field.at(x, y));
        }
      }
      EXPECT_EQ(tree.info(node).minHeight, lo);
      EXPECT_EQ(tree.info(node).maxHeight, hi);
      const Aabb box = tree.box(node);
      EXPECT_DOUBLE_EQ(box.minCorner.x, area.x0 * field.spacingX);
      EXPECT_DOUBLE_EQ(box.maxCorner.y, area.y1 * field.spacingY);
    });
  }
}

TEST(BlockQuadtree, DeltaBoundsEveryNodesBlockLod) {
  const Heightfield field = makeField(230, 201, 2);
  for (int k : {3, 5}) {
    const BlockLayout layout = *BlockLayout::create(field.width, field.height, k);
    BlockQuadtreeOptions options;
    options.dikeErrorBound = [](NodeId node) { return node.level == 1 ? 1000.0f : 0.5f * float(node.level); };
    const BlockQuadtree tree = buildTree(field, layout, options);
    forEachNode(layout, [&](NodeId node) {
      const NodeInfo& data = tree.info(node);
      auto lod = BlockLod::build(field, layout.interior(node));
      if (!lod.ok()) {
        EXPECT_TRUE(std::isinf(data.delta())) << "an undrawable node is always refined";
        return;
      }
      EXPECT_EQ(data.lodError, lod->maxError());
      EXPECT_EQ(data.floorError, lod->floorError());
      EXPECT_LE(lod->maxError(), data.delta());
      EXPECT_LE(lod->floorError(), data.delta());
      EXPECT_LE(lod->floorError(), data.floorDelta());
      EXPECT_EQ(data.dikeError, node.level == 1 ? 1000.0f : 0.5f * float(node.level));
      EXPECT_GE(data.delta(), data.dikeError);
      if (node.level == 0) {
        EXPECT_EQ(data.floorError, 0.0f);
      }
    });
  }
}

TEST(BlockQuadtree, EdgeNodesWithoutAWholeStridedCellAreAlwaysRefined) {
  // 134 = 4 * 33 + 2: block 4 has a single cell, so the level-1 and level-2 nodes starting at
  // sample 132 have no whole cell at stride 2 and 4.
  const Heightfield field = makeField(134, 67, 3);
  const BlockLayout layout = *BlockLayout::create(field.width, field.height, 5);
  const BlockQuadtree tree = buildTree(field, layout);
  EXPECT_TRUE(std::isinf(tree.info(NodeId{2, 1, 0}).delta()));
  EXPECT_TRUE(std::isinf(tree.info(NodeId{1, 2, 0}).delta()));
  EXPECT_FALSE(std::isinf(tree.info(NodeId{0, 4, 0}).delta()));

  Camera camera;
  camera.position = glm::dvec3(-1.0e4, 0.5 * field.extentY(), 3.0e4);  // far away: everything coarse
  camera.yawDeg = 90.0;
  camera.pitchDeg = -60.0;
  SelectionScratch scratch;
  std::vector<SelectedNode> cut;
  tree.select(camera, SelectionOptions{64.0}, scratch, cut);
  expectTiling(layout, cut);
  for (const SelectedNode& s : cut) {
    if (s.visible) {
      EXPECT_FALSE(std::isinf(tree.info(s.node).delta()));
    }
  }
}

TEST(BlockQuadtree, BuildIsTheSameForAnyThreadCount) {
  const Heightfield field = makeField(300, 257, 4);
  const BlockLayout layout = *BlockLayout::create(field.width, field.height, 3);
  std::vector<float> progress;
  BlockQuadtreeOptions options;
  core::ThreadPool onePool(1);
  options.pool = &onePool;
  options.progress = [&](float f) { progress.push_back(f); };
  const BlockQuadtree one = buildTree(field, layout, options);
  ASSERT_GE(progress.size(), 2u);
  EXPECT_EQ(progress.front(), 0.0f);
  EXPECT_EQ(progress.back(), 1.0f);
  for (std::size_t i = 1; i < progress.size(); ++i) EXPECT_LE(progress[i - 1], progress[i]);

  for (int threads : {2, 3, 8}) {
    core::ThreadPool pool(threads);
    options.pool = &pool;
    progress.clear();
    const BlockQuadtree many = buildTree(field, layout, options);
    EXPECT_EQ(progress.back(), 1.0f);
    for (std::size_t i = 1; i < progress.size(); ++i) EXPECT_LE(progress[i - 1], progress[i]);
    forEachNode(layout, [&](NodeId node) {
      const NodeInfo& a = one.info(node);
      const NodeInfo& b = many.info(node);
      EXPECT_EQ(a.minHeight, b.minHeight);
      EXPECT_EQ(a.maxHeight, b.maxHeight);
      EXPECT_EQ(a.lodError, b.lodError);
      EXPECT_EQ(a.floorError, b.floorError);
    });
  }
}

TEST(BlockQuadtree, BadInputIsAnErrorNotACrash) {
  Heightfield field = makeField(100, 90, 5);
  const BlockLayout layout = *BlockLayout::create(field.width, field.height, 5);
  const BlockLayout other = *BlockLayout::create(101, 90, 5);
  auto mismatch = BlockQuadtree::build(field, other);
  ASSERT_FALSE(mismatch.ok());
  EXPECT_EQ(mismatch.error().kind, ErrorKind::InvalidArgument);

  BlockQuadtreeOptions negative;
  negative.dikeErrorBound = [](NodeId node) { return node.level == 1 ? -1.0f : 0.0f; };
  auto badBound = BlockQuadtree::build(field, layout, negative);
  ASSERT_FALSE(badBound.ok());
  EXPECT_EQ(badBound.error().kind, ErrorKind::InvalidArgument);

  field.at(70, 40) = std::numeric_limits<float>::quiet_NaN();
  auto noData = BlockQuadtree::build(field, layout);
  ASSERT_FALSE(noData.ok());
  EXPECT_EQ(noData.error().kind, ErrorKind::InvalidData);
}

TEST(BlockQuadtree, FlatTerrainIsOneNode) {
  Heightfield field(300, 300, 10.0, 10.0);
  const BlockLayout layout = *BlockLayout::create(field.width, field.height, 5);
  const BlockQuadtree tree = buildTree(field, layout);
  Camera camera;
  camera.position = glm::dvec3(1500.0, 1500.0, 0.0);  // on the ground, inside the root's box
  camera.pitchDeg = -10.0;
  SelectionScratch scratch;
  std::vector<SelectedNode> cut;
  tree.select(camera, SelectionOptions{1.0}, scratch, cut);
  ASSERT_EQ(cut.size(), 1u);
  EXPECT_EQ(cut[0].node, layout.root());
  EXPECT_TRUE(cut[0].visible);
  EXPECT_EQ(cut[0].distanceM, 0.0);
}

TEST(BlockQuadtree, LookingAwayCullsTheRoot) {
  const Heightfield field = makeField(230, 201, 6);
  const BlockLayout layout = *BlockLayout::create(field.width, field.height, 3);
  const BlockQuadtree tree = buildTree(field, layout);
  Camera camera;
  camera.position = glm::dvec3(-500.0, 100.0, 600.0);
  camera.yawDeg = 270.0;  // west, away from the DEM
  SelectionScratch scratch;
  std::vector<SelectedNode> cut;
  const SelectionStats stats = tree.select(camera, SelectionOptions{1.0}, scratch, cut);
  ASSERT_EQ(cut.size(), 1u);
  EXPECT_FALSE(cut[0].visible);
  EXPECT_EQ(stats.culledNodes, 1u);
  EXPECT_EQ(stats.nodesVisited, 1u);
}

// The selection's properties, against brute force, over random cameras and tolerances.
TEST(BlockQuadtree, SelectionTilesTheDemCullsConservativelyAndMeetsTau) {
  const Heightfield field = makeField(230, 201, 7);
  for (int k : {3, 5}) {
    const BlockLayout layout = *BlockLayout::create(field.width, field.height, k);
    const BlockQuadtree tree = buildTree(field, layout);
    std::mt19937_64 rng(100 + k);
    SelectionScratch scratch;
    std::vector<SelectedNode> cut;
    std::size_t visibleSeen = 0, culledSeen = 0, coarseSeen = 0;
    for (int c = 0; c < 60; ++c) {
      const Camera camera = randomCamera(rng, field);
      const double tau = std::array<double, 4>{0.5, 1.0, 4.0, 16.0}[std::size_t(c % 4)];
      const NodeErrorMeasure measure = c % 3 == 2 ? NodeErrorMeasure::Floor : NodeErrorMeasure::Delta;
      const SelectionStats stats = tree.select(camera, SelectionOptions{tau, measure}, scratch, cut);
      SCOPED_TRACE("k " + std::to_string(k) + " camera " + std::to_string(c));
      expectTiling(layout, cut);
      EXPECT_LE(cut.size(), tree.selectionBound());
      EXPECT_EQ(stats.visibleNodes + stats.culledNodes, cut.size());

      const double K = camera.errorProjectionConstant();
      for (const SelectedNode& s : cut) {
        const Aabb world = tree.box(s.node);
        EXPECT_EQ(s.distanceM,
                  distanceToOrigin(Aabb{world.minCorner - camera.position, world.maxCorner - camera.position}));
        const double error =
            measure == NodeErrorMeasure::Floor ? tree.info(s.node).floorDelta() : tree.info(s.node).delta();
        if (s.visible) {
          ++visibleSeen;
          coarseSeen += s.node.level > 0;
          // Taken: fine enough, or as fine as it gets.
          EXPECT_TRUE(s.node.level == 0 || K * error <= tau * s.distanceM) << "level " << int(s.node.level);
        } else {
          ++culledSeen;
        }
        // Reached: the parent was visible and too coarse.
        if (s.node.level < layout.rootLevel()) {
          const NodeId parent = s.node.parent();
          const Aabb pw = tree.box(parent);
          const double pd = distanceToOrigin(Aabb{pw.minCorner - camera.position, pw.maxCorner - camera.position});
          const double pe =
              measure == NodeErrorMeasure::Floor ? tree.info(parent).floorDelta() : tree.info(parent).delta();
          EXPECT_GT(K * pe, tau * pd);
          EXPECT_TRUE(Frustum::fromCamera(camera).intersects(pw));
        }
      }

      // No block with a point in the view volume is culled: a lattice of each level-0 block's
      // box, projected the renderer's way.
      const glm::dmat4 viewProjection = camera.projection() * camera.viewRotation();
      for (int by = 0; by < layout.nodesY(0); ++by) {
        for (int bx = 0; bx < layout.nodesX(0); ++bx) {
          const Aabb box = tree.box(NodeId{0, std::uint32_t(bx), std::uint32_t(by)});
          bool seen = false;
          constexpr int kSteps = 4;
          for (int i = 0; i <= kSteps && !seen; ++i) {
            for (int j = 0; j <= kSteps && !seen; ++j) {
              for (int l = 0; l <= kSteps && !seen; ++l) {
                const glm::dvec3 t(double(i) / kSteps, double(j) / kSteps, double(l) / kSteps);
                const glm::dvec3 p = box.minCorner + t * (box.maxCorner - box.minCorner) - camera.position;
                const glm::dvec4 clip = viewProjection * glm::dvec4(p, 1.0);
                seen = clip.w > 0.0 && std::abs(clip.x) <= clip.w && std::abs(clip.y) <= clip.w &&
                       std::abs(clip.z) <= clip.w;
              }
            }
          }
          if (!seen) continue;
          const SelectedNode* owner = coveringNode(cut, bx, by);
          ASSERT_NE(owner, nullptr);
          EXPECT_TRUE(owner->visible) << "block " << bx << ", " << by << " culled at level " << int(owner->node.level);
        }
      }
    }
    // The cameras exercised every kind of output.
    EXPECT_GT(visibleSeen, 100u);
    EXPECT_GT(culledSeen, 100u);
    EXPECT_GT(coarseSeen, 20u);
  }
}

TEST(BlockQuadtree, FallsBackToTheResidentAncestorNeverAHole) {
  const Heightfield field = makeField(230, 201, 8);
  const BlockLayout layout = *BlockLayout::create(field.width, field.height, 3);
  const BlockQuadtree tree = buildTree(field, layout);
  Camera camera;
  camera.position = glm::dvec3(0.3 * field.extentX(), 0.2 * field.extentY(), 700.0);
  camera.yawDeg = 30.0;
  camera.pitchDeg = -25.0;
  SelectionScratch scratch;
  std::vector<SelectedNode> full, cut;
  const SelectionOptions options{1.0};
  tree.select(camera, options, scratch, full);
  std::size_t fineVisible = 0;
  for (const SelectedNode& s : full) fineVisible += s.visible && s.node.level < 2;
  ASSERT_GT(fineVisible, 0u);

  // Only levels >= 2 resident: nothing finer is drawn, and the cut still tiles.
  auto coarseOnly = [](NodeId node) { return node.level >= 2; };
  const SelectionStats stats = tree.select(camera, options, scratch, cut, coarseOnly);
  expectTiling(layout, cut);
  EXPECT_GT(stats.blockedNodes, 0u);
  for (const SelectedNode& s : cut) {
    if (!s.visible) continue;
    EXPECT_GE(s.node.level, 2);
    if (s.refinementBlocked) {
      EXPECT_EQ(s.node.level, 2);
    }
  }

  // One missing block: its parent is drawn instead, flagged; everything else is unchanged.
  const SelectedNode* target = nullptr;
  for (const SelectedNode& s : full) {
    if (s.visible && s.node.level == 0) {
      target = &s;
      break;
    }
  }
  ASSERT_NE(target, nullptr);
  const NodeId missing = target->node;
  auto allButOne = [&](NodeId node) { return !(node == missing); };
  tree.select(camera, options, scratch, cut, allButOne);
  expectTiling(layout, cut);
  bool parentTaken = false;
  for (const SelectedNode& s : cut) {
    EXPECT_FALSE(s.visible && s.node == missing);
    if (s.node == missing.parent()) {
      parentTaken = true;
      EXPECT_TRUE(s.visible);
      EXPECT_TRUE(s.refinementBlocked);
    }
  }
  EXPECT_TRUE(parentTaken);
  EXPECT_EQ(
      cut.size(), full.size() - [&] {
        std::size_t siblings = 0;  // the parent's children in the full cut, replaced by the parent
        for (const SelectedNode& s : full) siblings += s.node.level == 0 && s.node.parent() == missing.parent();
        return siblings - 1;
      }());

  // Random residency: visible nodes are always resident (or the root), and the cut tiles.
  std::mt19937_64 rng(9);
  for (int trial = 0; trial < 20; ++trial) {
    const std::uint64_t salt = rng();
    auto randomResidency = [&](NodeId node) {
      const std::uint64_t h = (std::uint64_t(node.level) * 0x9E3779B97F4A7C15ull) ^
                              (std::uint64_t(node.bx) * 0xBF58476D1CE4E5B9ull) ^
                              (std::uint64_t(node.by) * 0x94D049BB133111EBull) ^ salt;
      return ((h >> 29) ^ h) % 10 < 7;
    };
    const Camera moving = randomCamera(rng, field);
    tree.select(moving, options, scratch, cut, randomResidency);
    expectTiling(layout, cut);
    for (const SelectedNode& s : cut) {
      if (s.visible && !(s.node == layout.root())) {
        EXPECT_TRUE(randomResidency(s.node));
      }
    }
  }
}

// ---- forced splits (SelectionOptions::forcedSplits) ---------------------------------------

bool isAncestorOrSelf(const NodeId& ancestor, const NodeId& node) {
  if (ancestor.level < node.level) return false;
  const int up = ancestor.level - node.level;
  return (node.bx >> up) == ancestor.bx && (node.by >> up) == ancestor.by;
}

bool sameSelection(const std::vector<SelectedNode>& a, const std::vector<SelectedNode>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (!(a[i].node == b[i].node) || a[i].visible != b[i].visible || a[i].distanceM != b[i].distanceM ||
        a[i].refinementBlocked != b[i].refinementBlocked)
      return false;
  }
  return true;
}

// The cut without the nodes inside `node`'s footprint (in order).
std::vector<SelectedNode> outside(const std::vector<SelectedNode>& cut, const NodeId& node) {
  std::vector<SelectedNode> out;
  for (const SelectedNode& s : cut)
    if (!isAncestorOrSelf(node, s.node)) out.push_back(s);
  return out;
}

// A node the plain selection takes (visible) or culls, listed in forcedSplits, gives way to its
// children (culled children stay culled); the rest of the cut is unchanged and the cut still
// tiles the DEM. An empty list, or one of level-0 nodes only, gives the plain selection.
TEST(BlockQuadtree, ForcedSplitsReplaceListedNodesByTheirChildren) {
  const Heightfield field = makeField(230, 201, 14);
  const BlockLayout layout = *BlockLayout::create(field.width, field.height, 3);
  const BlockQuadtree tree = buildTree(field, layout);
  std::mt19937_64 rng(31);
  SelectionScratch scratch;
  std::vector<SelectedNode> plain, forcedCut, again;
  int takenForced = 0, culledForced = 0, deepForced = 0;
  for (int c = 0; c < 40; ++c) {
    const Camera camera = randomCamera(rng, field);
    const double tau = std::array<double, 3>{1.0, 4.0, 16.0}[std::size_t(c % 3)];
    const NodeErrorMeasure measure = c % 2 ? NodeErrorMeasure::Floor : NodeErrorMeasure::Delta;
    SCOPED_TRACE("camera " + std::to_string(c));
    const SelectionStats plainStats = tree.select(camera, SelectionOptions{tau, measure}, scratch, plain);
    expectTiling(layout, plain);

    // Empty lists: the plain selection.
    const std::array<NodeId, 0> none{};
    SelectionOptions empty{tau, measure};
    empty.forcedSplits = none;
    const SelectionStats emptyStats = tree.select(camera, empty, scratch, again);
    EXPECT_TRUE(sameSelection(again, plain));
    EXPECT_EQ(emptyStats.nodesVisited, plainStats.nodesVisited);
    const std::array<NodeId, 2> leaves{NodeId{0, 0, 0},
                                       plain.front().node.level == 0 ? plain.front().node : NodeId{0, 1, 1}};
    SelectionOptions levelZero{tau, measure};
    levelZero.forcedSplits = leaves;
    tree.select(camera, levelZero, scratch, again);
    EXPECT_TRUE(sameSelection(again, plain)) << "level-0 entries are ignored";

    // Each coarse node of the plain cut, forced on its own.
    for (const SelectedNode& s : plain) {
      if (s.node.level == 0) continue;
      const std::array<NodeId, 1> list{s.node};
      SelectionOptions options{tau, measure};
      options.forcedSplits = list;
      const SelectionStats stats = tree.select(camera, options, scratch, forcedCut);
      SCOPED_TRACE("forced level " + std::to_string(int(s.node.level)) + (s.visible ? " visible" : " culled"));
      expectTiling(layout, forcedCut);
      EXPECT_EQ(stats.visibleNodes + stats.culledNodes, forcedCut.size());
      EXPECT_TRUE(sameSelection(outside(forcedCut, s.node), outside(plain, s.node))) << "the rest of the cut changed";
      std::size_t inside = 0, directChildren = 0, existingChildren = 0;
      for (int q = 0; q < 4; ++q) existingChildren += layout.exists(s.node.child(q));
      for (const SelectedNode& f : forcedCut) {
        if (!isAncestorOrSelf(s.node, f.node)) continue;
        ++inside;
        EXPECT_LT(f.node.level, s.node.level) << "the forced node is still in the cut";
        directChildren += f.node.level + 1 == s.node.level;
        if (!s.visible) {
          EXPECT_FALSE(f.visible) << "a child of a culled node became visible";
        }
      }
      EXPECT_GE(inside, existingChildren);
      if (!s.visible) {
        // Culled children are never refined further (unless not drawable at their stride).
        std::size_t drawableChildren = 0;
        for (int q = 0; q < 4; ++q) {
          const NodeId child = s.node.child(q);
          drawableChildren += layout.exists(child) && std::isfinite(tree.info(child).delta());
        }
        EXPECT_GE(directChildren, drawableChildren);
        ++culledForced;
      } else {
        ++takenForced;
      }
    }

    // A node below the plain cut: its ancestors and itself are refined.
    const SelectedNode& coarse =
        *std::max_element(plain.begin(), plain.end(),
                          [](const SelectedNode& a, const SelectedNode& b) { return a.node.level < b.node.level; });
    if (coarse.node.level >= 2) {
      NodeId deep = coarse.node;
      while (deep.level > 1) {
        const NodeId child = deep.child(int(rng() % 4));
        if (!layout.exists(child)) break;
        deep = child;
      }
      if (deep.level < coarse.node.level) {
        const std::array<NodeId, 2> list{deep, NodeId{0, 2, 2}};
        SelectionOptions options{tau, measure};
        options.forcedSplits = list;
        tree.select(camera, options, scratch, forcedCut);
        expectTiling(layout, forcedCut);
        for (const SelectedNode& f : forcedCut) {
          EXPECT_FALSE(isAncestorOrSelf(f.node, deep)) << "an ancestor of a forced node (or itself) is in the cut";
        }
        EXPECT_TRUE(sameSelection(outside(forcedCut, coarse.node), outside(plain, coarse.node)));
        ++deepForced;
      }
    }
  }
  EXPECT_GT(takenForced, 20);
  EXPECT_GT(culledForced, 5);
  EXPECT_GT(deepForced, 5);
}

TEST(BlockQuadtree, SteadyStateSelectionAllocatesNothing) {
  const Heightfield field = makeField(230, 201, 10);
  const BlockLayout layout = *BlockLayout::create(field.width, field.height, 3);
  const BlockQuadtree tree = buildTree(field, layout);
  std::mt19937_64 rng(12);
  std::vector<Camera> cameras;
  for (int c = 0; c < 50; ++c) cameras.push_back(randomCamera(rng, field));

  SelectionScratch scratch;
  std::vector<SelectedNode> cut;
  scratch.reserve(tree);
  cut.reserve(tree.selectionBound());
  auto resident = [](NodeId node) { return node.level >= 1 || (node.bx + node.by) % 3 != 0; };
  const std::size_t before = g_allocations.load();
  std::size_t selected = 0;
  for (const Camera& camera : cameras) {
    tree.select(camera, SelectionOptions{1.0}, scratch, cut);
    selected += cut.size();
    tree.select(camera, SelectionOptions{0.5, NodeErrorMeasure::Floor}, scratch, cut, resident);
    selected += cut.size();
  }
  EXPECT_EQ(g_allocations.load() - before, 0u);
  EXPECT_GT(selected, 100u);
}

}  // namespace
}  // namespace polder::terrain
