// The LOD cache (lod_cache.hpp) and its block-level reuse test (lod_reuse.hpp): reuse under a
// still or slowly moving camera, rebuilds when the camera closes in or leaves a block behind,
// the projected-error bound on every frame's meshes (checked by brute force written here,
// independently of rtin_extract.cpp and lod_cache_reuse.cpp), the byte budget and LRU order,
// the count mode, and no heap allocation in steady state. Chuang 2001 part B (LOD caching) is what
// these tests hold the cache to.
#include <polder/cache/lod_cache.hpp>
#include <polder/cache/lod_reuse.hpp>
#include <polder/terrain/block_layout.hpp>
#include <polder/terrain/generator.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <new>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "geometry_reference.hpp"

// Heap allocations in this program, counted by replacing the global operator new: the
// replacement can only live at global scope, so this test-only counter does too.
namespace {
constinit std::uint64_t allocationCount = 0;
}  // namespace

void* operator new(std::size_t size) {
  ++allocationCount;
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) { return ::operator new(size); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }

namespace polder::cache {
namespace {

using terrain::BlockLayout;
using terrain::BlockLod;
using terrain::BlockMesh;
using terrain::GridVertex;
using terrain::Heightfield;
using terrain::LodView;
using terrain::NodeId;

// K of a 720-pixel-high view with a 60 degree vertical field of view.
const double kConstant = 720.0 / (2.0 * std::tan(std::numbers::pi / 6.0));

// Sums of sines: long hills plus a short ripple, so that meshes refine near the camera.
Heightfield sinesField(int width, int height, double spacing = 10.0) {
  Heightfield field(width, height, spacing, spacing);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      field.at(x, y) = float(40.0 * std::sin(0.05 * x + 0.3) + 25.0 * std::cos(0.083 * y - 0.5) +
                             6.0 * std::sin(0.31 * (x + y)) + 2.0 * std::sin(1.7 * x - 0.9 * y));
    }
  }
  return field;
}

// Repeats with the block pitch (33 samples), so every level-0 block has the same heights.
Heightfield periodicField(int blocksPerSide) {
  const int size = blocksPerSide * 33 + 1;
  Heightfield field(size, size, 10.0, 10.0);
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      const int u = x % 33, v = y % 33;
      field.at(x, y) = float(30.0 * std::sin(0.19 * u) * std::cos(0.23 * v) + 3.0 * std::sin(1.3 * u + 0.7 * v));
    }
  }
  return field;
}

// Flat ground with a few sharp bumps and pits: few large triangles reach from a bump into
// flat sub-regions, which is where a summary that forgets a triangle's reach goes wrong.
Heightfield bumpsField(int width, int height, unsigned seed) {
  Heightfield field(width, height, 10.0, 10.0);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  struct Bump {
    double x, y, radius, height;
  };
  std::vector<Bump> bumps;
  for (int b = 0; b < width * height / 400 + 2; ++b)
    bumps.push_back({unit(rng) * width, unit(rng) * height, 1.0 + 6.0 * unit(rng), (unit(rng) - 0.3) * 120.0});
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      double h = 0.0;
      for (const Bump& b : bumps) {
        const double d2 = ((x - b.x) * (x - b.x) + (y - b.y) * (y - b.y)) / (b.radius * b.radius);
        h += b.height * std::exp(-d2);
      }
      field.at(x, y) = float(h);
    }
  }
  return field;
}

struct Terrain {
  Heightfield field;
  std::vector<BlockLod> lods;
  std::vector<NodeId> nodes;
};

// Every node of quadtree level `level` (stride 2^level), blocks of 33 x 33 vertices.
Terrain makeTerrain(Heightfield field, int level = 0) {
  Terrain terrain;
  terrain.field = std::move(field);
  const BlockLayout layout = BlockLayout::create(terrain.field.width, terrain.field.height, 5).value();
  for (int by = 0; by < layout.nodesY(level); ++by) {
    for (int bx = 0; bx < layout.nodesX(level); ++bx) {
      const NodeId node{std::uint8_t(level), std::uint32_t(bx), std::uint32_t(by)};
      auto lod = BlockLod::build(terrain.field, layout.interior(node));
      if (!lod) continue;  // no whole cell of this node inside the field
      terrain.lods.push_back(std::move(lod.value()));
      terrain.nodes.push_back(node);
    }
  }
  return terrain;
}

LodView viewFor(const BlockLod& lod, const glm::dvec3& world, double tau = 1.0, double k = kConstant,
                double nearM = 1.0) {
  LodView view;
  view.camera = world - lod.origin();
  view.projectionConstant = k;
  view.tolerancePx = tau;
  view.nearM = nearM;
  return view;
}

// ---- independent checks -------------------------------------------------------------------

long long cross2(long long ox, long long oy, long long ax, long long ay, long long bx, long long by) {
  return (ax - ox) * (by - oy) - (ay - oy) * (bx - ox);
}

// Brute force: the largest vertical distance between the plane through the triangle's corner
// samples and every full-resolution sample in the closed triangle.
double bruteError(const Heightfield& field, const terrain::BlockFootprint& fp, GridVertex a, GridVertex b,
                  GridVertex c) {
  const long long px[3] = {fp.x0 + (long long)a.i * fp.stride, fp.x0 + (long long)b.i * fp.stride,
                           fp.x0 + (long long)c.i * fp.stride};
  const long long py[3] = {fp.y0 + (long long)a.j * fp.stride, fp.y0 + (long long)b.j * fp.stride,
                           fp.y0 + (long long)c.j * fp.stride};
  const double pz[3] = {field.at(int(px[0]), int(py[0])), field.at(int(px[1]), int(py[1])),
                        field.at(int(px[2]), int(py[2]))};
  const long long area2 = cross2(px[0], py[0], px[1], py[1], px[2], py[2]);
  double err = 0.0;
  for (long long y = std::min({py[0], py[1], py[2]}); y <= std::max({py[0], py[1], py[2]}); ++y) {
    for (long long x = std::min({px[0], px[1], px[2]}); x <= std::max({px[0], px[1], px[2]}); ++x) {
      const long long w0 = cross2(px[1], py[1], px[2], py[2], x, y);
      const long long w1 = cross2(px[2], py[2], px[0], py[0], x, y);
      const long long w2 = cross2(px[0], py[0], px[1], py[1], x, y);
      const bool inside = area2 > 0 ? (w0 >= 0 && w1 >= 0 && w2 >= 0) : (w0 <= 0 && w1 <= 0 && w2 <= 0);
      if (!inside) continue;
      const double plane = (w0 * pz[0] + w1 * pz[1] + w2 * pz[2]) / double(area2);
      err = std::max(err, std::fabs(double(field.at(int(x), int(y))) - plane));
    }
  }
  return err;
}

using test::pointTriangleDistance;

// The largest K * e(T) / max(dist(camera, T), near) / tau over the mesh's triangles, leaving
// out the half cells of a strided block (no extraction can refine them). <= 1: within tau.
double worstProjectedRatio(const Heightfield& field, const BlockLod& lod, const BlockMesh& mesh, const LodView& view) {
  double worst = 0.0;
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    const GridVertex v[3] = {mesh.vertices[mesh.indices[3 * t]], mesh.vertices[mesh.indices[3 * t + 1]],
                             mesh.vertices[mesh.indices[3 * t + 2]]};
    // A half cell (its hypotenuse a cell diagonal) is the one bintree triangle inside one cell.
    const bool halfCell = std::max({v[0].i, v[1].i, v[2].i}) - std::min({v[0].i, v[1].i, v[2].i}) == 1 &&
                          std::max({v[0].j, v[1].j, v[2].j}) - std::min({v[0].j, v[1].j, v[2].j}) == 1;
    if (halfCell && lod.footprint().stride > 1) continue;
    const double err = bruteError(field, lod.footprint(), v[0], v[1], v[2]);
    const double distance = pointTriangleDistance(view.camera, lod.position(v[0].i, v[0].j),
                                                  lod.position(v[1].i, v[1].j), lod.position(v[2].i, v[2].j));
    worst = std::max(worst, view.projectionConstant * err / std::max(distance, view.nearM) / view.tolerancePx);
  }
  return worst;
}

bool sameMesh(const BlockMesh& a, const BlockMesh& b) {
  if (a.vertices.size() != b.vertices.size() || a.indices != b.indices) return false;
  for (std::size_t v = 0; v < a.vertices.size(); ++v)
    if (a.vertices[v].i != b.vertices[v].i || a.vertices[v].j != b.vertices[v].j) return false;
  return true;
}

void expectCountersAddUp(const LodCache& cache) {
  const LodCacheCounters& c = cache.counters();
  EXPECT_EQ(c.lookups, c.hits + c.rebuilds);
  EXPECT_EQ(c.rebuilds, c.built + c.tooCoarse + c.needlesslyFine + c.changed + c.pinned + c.uncached);
}

// ---- reuse ------------------------------------------------------------------------------

TEST(LodCache, StationaryCameraReusesEveryBlock) {
  const Terrain terrain = makeTerrain(sinesField(4 * 33 + 1, 4 * 33 + 1));
  LodCache cache;
  const glm::dvec3 camera{500.0, 400.0, 150.0};
  constexpr int kFrames = 20;
  for (int frame = 0; frame < kFrames; ++frame) {
    cache.beginFrame();
    for (std::size_t b = 0; b < terrain.lods.size(); ++b) {
      LodOutcome outcome{};
      cache.acquire(terrain.nodes[b], terrain.lods[b], viewFor(terrain.lods[b], camera), &outcome);
      EXPECT_EQ(outcome, frame == 0 ? LodOutcome::Built : LodOutcome::Reused) << "frame " << frame << " block " << b;
    }
  }
  const std::size_t blocks = terrain.lods.size();
  EXPECT_EQ(cache.counters().lookups, kFrames * blocks);
  EXPECT_EQ(cache.counters().rebuilds, blocks);
  EXPECT_DOUBLE_EQ(cache.reuseRate(), double(kFrames - 1) / kFrames);
  expectCountersAddUp(cache);
}

TEST(LodCache, SmallMovesMostlyReuseAndStayWithinTau) {
  const Terrain terrain = makeTerrain(sinesField(3 * 33 + 1, 3 * 33 + 1));
  LodCache cache;
  int reusedChecked = 0;
  for (int frame = 0; frame < 200; ++frame) {
    const glm::dvec3 camera{200.0 + 0.5 * frame, 300.0 + 0.2 * frame, 160.0};  // 0.54 m a frame
    cache.beginFrame();
    for (std::size_t b = 0; b < terrain.lods.size(); ++b) {
      const LodView view = viewFor(terrain.lods[b], camera);
      LodOutcome outcome{};
      const BlockMesh& mesh = cache.acquire(terrain.nodes[b], terrain.lods[b], view, &outcome);
      if (frame % 10 == 0) {
        ASSERT_LE(worstProjectedRatio(terrain.field, terrain.lods[b], mesh, view), 1.0 + 1e-9)
            << "frame " << frame << " block " << b;
        reusedChecked += outcome == LodOutcome::Reused;
      }
    }
  }
  EXPECT_GT(cache.reuseRate(), 0.9);
  EXPECT_GT(reusedChecked, 0);
  expectCountersAddUp(cache);
}

TEST(LodCache, FlyingTowardABlockRebuildsFiner) {
  const Terrain terrain = makeTerrain(sinesField(33 + 1, 33 + 1));
  ASSERT_EQ(terrain.lods.size(), 1u);
  const BlockLod& lod = terrain.lods[0];
  LodCache cache;
  const glm::dvec3 from{4000.0, 3000.0, 600.0}, to{160.0, 160.0, 70.0};
  std::size_t first = 0, last = 0;
  constexpr int kFrames = 200;
  for (int frame = 0; frame < kFrames; ++frame) {
    const glm::dvec3 camera = from + (to - from) * (double(frame) / (kFrames - 1));
    const LodView view = viewFor(lod, camera);
    cache.beginFrame();
    const BlockMesh& mesh = cache.acquire(terrain.nodes[0], lod, view);
    ASSERT_LE(worstProjectedRatio(terrain.field, lod, mesh, view), 1.0 + 1e-9) << "frame " << frame;
    (frame == 0 ? first : last) = mesh.triangleCount();
  }
  EXPECT_GT(cache.counters().tooCoarse, 5u);
  EXPECT_GT(cache.counters().hits, 0u);  // not every step of the approach needs a new mesh
  EXPECT_GT(last, 4 * first);
  expectCountersAddUp(cache);
}

TEST(LodCache, RecedingCameraRebuildsANeedlesslyFineMesh) {
  const Terrain terrain = makeTerrain(sinesField(33 + 1, 33 + 1));
  const BlockLod& lod = terrain.lods[0];
  // Straight up from low over the block's centre: every point of the block only gets farther.
  const glm::dvec3 from{160.0, 160.0, 90.0}, to{160.0, 160.0, 2000.0};
  constexpr int kFrames = 150;
  auto fly = [&](LodCache& cache) {
    std::size_t first = 0, last = 0;
    for (int frame = 0; frame < kFrames; ++frame) {
      const glm::dvec3 camera = from + (to - from) * (double(frame) / (kFrames - 1));
      const LodView view = viewFor(lod, camera);
      cache.beginFrame();
      const BlockMesh& mesh = cache.acquire(terrain.nodes[0], lod, view);
      EXPECT_LE(worstProjectedRatio(terrain.field, lod, mesh, view), 1.0 + 1e-9) << "frame " << frame;
      (frame == 0 ? first : last) = mesh.triangleCount();
    }
    return std::pair{first, last};
  };

  LodCache cache;
  const auto [first, last] = fly(cache);
  EXPECT_GT(cache.counters().needlesslyFine, 0u);
  EXPECT_EQ(cache.counters().tooCoarse, 0u);  // receding never needs finer: test (b) sees it
  EXPECT_LT(last, first / 2);
  // The last mesh is close to what a fresh extraction draws from the end of the path.
  BlockMesh fresh;
  terrain::RtinScratch scratch;
  lod.extractView(viewFor(lod, to), fresh, scratch);
  EXPECT_LE(double(last), 1.5 * double(fresh.triangleCount()));

  // Without the needlessly-fine test, the first mesh is kept all the way: within tau, but
  // with all the triangles of the close-up.
  LodCacheOptions keepAll;
  keepAll.reuse.fineFactor = std::numeric_limits<double>::infinity();
  LodCache keeping(keepAll);
  const auto [keptFirst, keptLast] = fly(keeping);
  EXPECT_EQ(keeping.counters().rebuilds, 1u);
  EXPECT_EQ(keptLast, keptFirst);
}

// Random camera paths (drifts, dives, jumps, changes of tau, K and near) over level-0 blocks,
// clipped edge blocks and level-1 blocks (stride 2): every mesh of every frame, reused or
// rebuilt, keeps the projected error bound.
TEST(LodCache, RandomPathsNeverExceedTau) {
  struct Case {
    int width, height, level;
    bool bumps;
  };
  for (const Case& c : {Case{3 * 33 + 1, 3 * 33 + 1, 0, false}, Case{2 * 33 + 20, 33 + 9, 0, false},
                        Case{4 * 33 + 1, 4 * 33 + 1, 1, false}, Case{3 * 33 + 1, 3 * 33 + 1, 0, true}}) {
    const Terrain terrain =
        makeTerrain(c.bumps ? bumpsField(c.width, c.height, 3u) : sinesField(c.width, c.height), c.level);
    ASSERT_FALSE(terrain.lods.empty());
    const double extentX = terrain.field.extentX(), extentY = terrain.field.extentY();
    for (unsigned seed = 1; seed <= 4; ++seed) {
      SCOPED_TRACE(std::string(c.bumps ? "bumps " : "sines ") + std::to_string(c.width) + "x" +
                   std::to_string(c.height) + " level " + std::to_string(c.level) + " seed " + std::to_string(seed));
      std::mt19937 rng(seed * 7919u + unsigned(c.level));
      std::uniform_real_distribution<double> unit(0.0, 1.0);
      LodCache cache;
      glm::dvec3 camera{unit(rng) * extentX, unit(rng) * extentY, 80.0 + unit(rng) * 200.0};
      glm::dvec3 velocity{0.0};
      double tau = 1.0, k = kConstant, nearM = 1.0;
      std::uint64_t reusedChecked = 0;
      for (int frame = 0; frame < 160; ++frame) {
        const double roll = unit(rng);
        if (roll < 0.03) {  // a jump
          camera = {(unit(rng) * 1.4 - 0.2) * extentX, (unit(rng) * 1.4 - 0.2) * extentY, 50.0 + unit(rng) * 800.0};
        } else if (roll < 0.06) {
          tau = std::array{0.5, 1.0, 2.0, 4.0}[rng() % 4];
        } else if (roll < 0.08) {
          k = kConstant * (0.5 + unit(rng));
        } else if (roll < 0.09) {
          nearM = std::array{0.0, 1.0, 20.0}[rng() % 3];
        } else if (roll < 0.2) {                                       // a new heading and speed, from creeping to fast
          const double speed = std::pow(10.0, unit(rng) * 3.0 - 1.0);  // 0.1 .. 100 m a frame
          velocity = glm::dvec3(unit(rng) - 0.5, unit(rng) - 0.5, 0.6 * (unit(rng) - 0.5));
          velocity *= speed / std::max(glm::length(velocity), 1e-9);
        }
        camera += velocity;
        camera.z = std::max(camera.z, 45.0);  // may dip into hills and bumps (below 85 m)
        cache.beginFrame();
        for (std::size_t b = 0; b < terrain.lods.size(); ++b) {
          const LodView view = viewFor(terrain.lods[b], camera, tau, k, nearM);
          LodOutcome outcome{};
          const BlockMesh& mesh = cache.acquire(terrain.nodes[b], terrain.lods[b], view, &outcome);
          const double worst = worstProjectedRatio(terrain.field, terrain.lods[b], mesh, view);
          ASSERT_LE(worst, 1.0 + 1e-9) << "frame " << frame << " block " << b << " outcome " << int(outcome);
          reusedChecked += outcome == LodOutcome::Reused;
        }
      }
      EXPECT_GT(reusedChecked, 100u);              // the bound was checked on many reused meshes ...
      EXPECT_GT(cache.counters().tooCoarse, 10u);  // ... and on rebuilt ones
      expectCountersAddUp(cache);
    }
  }
}

// The reuse test on its own: a summary passes at its own camera (margins are never negative)
// and fails when the same camera asks for half the tolerance.
TEST(LodReuse, PassesAtTheBuildCameraAndFailsForAStricterTolerance) {
  const Terrain terrain = makeTerrain(sinesField(33 + 1, 33 + 1));
  const BlockLod& lod = terrain.lods[0];
  BlockMesh mesh;
  terrain::RtinScratch scratch;
  LodSummary summary;
  for (const glm::dvec3& camera : {glm::dvec3{160, 160, 80}, glm::dvec3{-300, 50, 120}, glm::dvec3{600, 900, 400}}) {
    const LodView view = viewFor(lod, camera);
    lod.extractView(view, mesh, scratch);
    summarizeLod(lod, view, mesh, summary);
    EXPECT_EQ(testLodReuse(summary, view), LodVerdict::Reuse);
    EXPECT_EQ(summary.triangles, mesh.triangleCount());
    std::uint32_t counted = 0;
    for (const LodRegion& region : summary.regions) {
      counted += region.triangles;
      EXPECT_GE(region.marginM, 0.0);
    }
    EXPECT_EQ(counted, mesh.triangleCount());
    // Half the tolerance from the same place: the cached mesh is too coarse.
    LodView stricter = view;
    stricter.tolerancePx = 0.5;
    lod.extractView(stricter, mesh, scratch);
    if (mesh.triangleCount() > summary.triangles) {
      EXPECT_EQ(testLodReuse(summary, stricter), LodVerdict::TooCoarse);
    }
  }
}

// The premises of the proof in lod_reuse.hpp, checked triangle by triangle: for every drawn
// triangle T and every sub-region S its rectangle overlaps with positive area, E(S) >= e(T)
// (brute force), the drawn plane of T at every grid vertex of T ∩ S lies in B(S)'s z-range,
// and M(S) <= dist(c0, T) - K e(T) / tau (the margin never promises more than T has).
TEST(LodReuse, SummaryBoundsEveryDrawnTriangle) {
  struct Case {
    int width, height, level;
    bool bumps;
  };
  for (const Case& c : {Case{2 * 33 + 1, 2 * 33 + 1, 0, false}, Case{2 * 33 + 20, 33 + 9, 0, false},
                        Case{2 * 33 + 1, 2 * 33 + 1, 1, false}, Case{3 * 33 + 1, 3 * 33 + 1, 0, true},
                        Case{2 * 33 + 20, 33 + 9, 0, true}, Case{3 * 33 + 1, 3 * 33 + 1, 1, true}}) {
    const Terrain terrain = makeTerrain(
        c.bumps ? bumpsField(c.width, c.height, 5u + unsigned(c.width)) : sinesField(c.width, c.height), c.level);
    std::mt19937 rng(11u + unsigned(c.level));
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    BlockMesh mesh;
    terrain::RtinScratch scratch;
    LodSummary summary;
    for (int trial = 0; trial < 12; ++trial) {
      const glm::dvec3 camera{(unit(rng) * 1.6 - 0.3) * terrain.field.extentX(),
                              (unit(rng) * 1.6 - 0.3) * terrain.field.extentY(), 100.0 + unit(rng) * 1500.0};
      const double tau = trial % 3 == 0 ? 1.0 : (trial % 3 == 1 ? 3.0 : 10.0);
      for (std::size_t b = 0; b < terrain.lods.size(); ++b) {
        const BlockLod& lod = terrain.lods[b];
        const LodView view = viewFor(lod, camera, tau);
        lod.extractView(view, mesh, scratch);
        summarizeLod(lod, view, mesh, summary);
        const int w = summary.regionCells;
        for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
          const GridVertex v[3] = {mesh.vertices[mesh.indices[3 * t]], mesh.vertices[mesh.indices[3 * t + 1]],
                                   mesh.vertices[mesh.indices[3 * t + 2]]};
          const int iMin = std::min({v[0].i, v[1].i, v[2].i}), iMax = std::max({v[0].i, v[1].i, v[2].i});
          const int jMin = std::min({v[0].j, v[1].j, v[2].j}), jMax = std::max({v[0].j, v[1].j, v[2].j});
          if (iMax - iMin == 1 && jMax - jMin == 1) continue;  // half cells are outside the claim
          const double err = bruteError(terrain.field, lod.footprint(), v[0], v[1], v[2]);
          const glm::dvec3 p[3] = {lod.position(v[0].i, v[0].j), lod.position(v[1].i, v[1].j),
                                   lod.position(v[2].i, v[2].j)};
          const double distance = pointTriangleDistance(view.camera, p[0], p[1], p[2]);
          const long long area2 = cross2(v[0].i, v[0].j, v[1].i, v[1].j, v[2].i, v[2].j);
          for (int ry = 0; ry < summary.regionsY; ++ry) {
            for (int rx = 0; rx < summary.regionsX; ++rx) {
              const int i0 = rx * w, i1 = std::min(i0 + w, lod.cellsX());
              const int j0 = ry * w, j1 = std::min(j0 + w, lod.cellsY());
              if (std::min(iMax, i1) <= std::max(iMin, i0) || std::min(jMax, j1) <= std::max(jMin, j0)) continue;
              const LodRegion& region = summary.regions[std::size_t(ry * kLodRegionsPerSide + rx)];
              ASSERT_GE(double(region.errorM), err - 1e-5) << "block " << b << " triangle " << t;
              if (view.projectionConstant * err / tau > view.nearM + 1e-6) {
                ASSERT_LE(region.marginM, distance - view.projectionConstant * err / tau + 1e-6)
                    << "block " << b << " triangle " << t;
              }
              for (int j = std::max(jMin, j0); j <= std::min(jMax, j1); ++j) {
                for (int i = std::max(iMin, i0); i <= std::min(iMax, i1); ++i) {
                  const long long w0 = cross2(v[1].i, v[1].j, v[2].i, v[2].j, i, j);
                  const long long w1 = cross2(v[2].i, v[2].j, v[0].i, v[0].j, i, j);
                  const long long w2 = cross2(v[0].i, v[0].j, v[1].i, v[1].j, i, j);
                  const bool inside = area2 > 0 ? (w0 >= 0 && w1 >= 0 && w2 >= 0) : (w0 <= 0 && w1 <= 0 && w2 <= 0);
                  if (!inside) continue;
                  const double z = (w0 * p[0].z + w1 * p[1].z + w2 * p[2].z) / double(area2);
                  ASSERT_GE(z, region.minZ - 1e-6) << "block " << b << " triangle " << t << " at " << i << "," << j;
                  ASSERT_LE(z, region.maxZ + 1e-6) << "block " << b << " triangle " << t << " at " << i << "," << j;
                }
              }
            }
          }
        }
      }
    }
  }
}

// ---- budget, LRU and counters ---------------------------------------------------------------

TEST(LodCache, ByteBudgetEvictsTheLeastRecentlyUsedBlock) {
  const Terrain terrain = makeTerrain(periodicField(3));
  ASSERT_EQ(terrain.lods.size(), 9u);
  constexpr std::size_t kTarget = 300;
  // One block's bytes: every block has the same heights, so the same mesh and capacities.
  std::size_t blockBytes = 0;
  {
    LodCache probe;
    blockBytes = meshBytes(probe.acquireCount(terrain.nodes[0], terrain.lods[0], kTarget));
    ASSERT_EQ(probe.bytes(), blockBytes);
  }
  ASSERT_GT(blockBytes, 0u);
  LodCacheOptions options;
  options.budgetBytes = 3 * blockBytes + blockBytes / 2;  // room for three blocks
  LodCache cache(options);
  auto use = [&](std::size_t b) {
    cache.beginFrame();
    LodOutcome outcome{};
    cache.acquireCount(terrain.nodes[b], terrain.lods[b], kTarget, &outcome);
    return outcome;
  };
  EXPECT_EQ(use(0), LodOutcome::Built);
  EXPECT_EQ(use(1), LodOutcome::Built);
  EXPECT_EQ(use(2), LodOutcome::Built);
  EXPECT_EQ(use(0), LodOutcome::Reused);  // 0 is now more recent than 1
  EXPECT_EQ(use(3), LodOutcome::Built);   // over budget: 1 goes
  EXPECT_TRUE(cache.contains(terrain.nodes[0]));
  EXPECT_FALSE(cache.contains(terrain.nodes[1]));
  EXPECT_TRUE(cache.contains(terrain.nodes[2]));
  EXPECT_TRUE(cache.contains(terrain.nodes[3]));
  EXPECT_EQ(use(4), LodOutcome::Built);  // then 2
  EXPECT_FALSE(cache.contains(terrain.nodes[2]));
  EXPECT_EQ(cache.counters().evictions, 2u);
  EXPECT_EQ(cache.size(), 3u);
  EXPECT_LE(cache.bytes(), options.budgetBytes);

  std::size_t sum = 0;
  for (const NodeId& node : terrain.nodes)
    if (const BlockMesh* mesh = cache.find(node)) sum += meshBytes(*mesh);
  EXPECT_EQ(cache.bytes(), sum);
  EXPECT_EQ(cache.counters().lookups, 6u);
  EXPECT_EQ(cache.counters().hits, 1u);
  EXPECT_EQ(cache.counters().built, 5u);
  expectCountersAddUp(cache);

  // Shrinking the budget evicts down to it, oldest first.
  cache.beginFrame();
  cache.setBudget(blockBytes + blockBytes / 2);
  EXPECT_EQ(cache.size(), 1u);
  EXPECT_TRUE(cache.contains(terrain.nodes[4]));
  EXPECT_TRUE(cache.invalidate(terrain.nodes[4]));
  EXPECT_EQ(cache.size(), 0u);
  EXPECT_EQ(cache.bytes(), 0u);
}

TEST(LodCache, BlocksOfTheCurrentFrameAreNeverEvicted) {
  const Terrain terrain = makeTerrain(periodicField(3));
  constexpr std::size_t kTarget = 300;
  LodCacheOptions options;
  options.budgetBytes = 1;  // far too small for even one block
  LodCache cache(options);
  terrain::RtinScratch scratch;
  cache.beginFrame();
  std::vector<const BlockMesh*> meshes;
  for (std::size_t b = 0; b < terrain.lods.size(); ++b)
    meshes.push_back(&cache.acquireCount(terrain.nodes[b], terrain.lods[b], kTarget));
  // The frame needs all nine, so the cache holds them over budget and every reference holds.
  EXPECT_EQ(cache.size(), terrain.lods.size());
  EXPECT_EQ(cache.counters().evictions, 0u);
  BlockMesh fresh;
  for (std::size_t b = 0; b < terrain.lods.size(); ++b) {
    terrain.lods[b].extractCount(kTarget, fresh, scratch);
    EXPECT_TRUE(sameMesh(*meshes[b], fresh)) << "block " << b;
    EXPECT_EQ(meshes[b], cache.find(terrain.nodes[b]));
  }
  // The next frame releases them and the cache goes back under its budget; a block the new
  // frame asks for is kept, alone, even though it is larger than the whole budget.
  cache.beginFrame();
  EXPECT_EQ(cache.size(), 0u);
  EXPECT_EQ(cache.bytes(), 0u);
  EXPECT_EQ(cache.counters().evictions, terrain.lods.size());
  LodOutcome outcome{};
  cache.acquireCount(terrain.nodes[5], terrain.lods[5], kTarget, &outcome);
  EXPECT_EQ(outcome, LodOutcome::Built);
  EXPECT_EQ(cache.size(), 1u);
  expectCountersAddUp(cache);
}

// Many blocks through a small cache in random order, with random invalidations: membership
// always matches a plain LRU model of the same capacity (every block has the same bytes), so
// the slot recycling and the index's backward-shift deletion lose and resurrect nothing.
TEST(LodCache, RandomChurnMatchesAnLruModel) {
  const Terrain terrain = makeTerrain(periodicField(10));
  ASSERT_EQ(terrain.lods.size(), 100u);
  constexpr std::size_t kTarget = 120, kCapacity = 20;
  LodCache probe;
  const std::size_t blockBytes = meshBytes(probe.acquireCount(terrain.nodes[0], terrain.lods[0], kTarget));
  LodCacheOptions options;
  options.budgetBytes = kCapacity * blockBytes + blockBytes / 2;
  LodCache cache(options);
  std::vector<std::size_t> model;  // most recently used first
  std::mt19937 rng(2024u);
  for (int step = 0; step < 3000; ++step) {
    const std::size_t b = rng() % 3 == 0 ? rng() % 100 : rng() % 30;  // a hot set and a cold tail
    if (rng() % 10 == 0) {
      const auto it = std::find(model.begin(), model.end(), b);
      EXPECT_EQ(cache.invalidate(terrain.nodes[b]), it != model.end());
      if (it != model.end()) model.erase(it);
    } else {
      cache.beginFrame();
      LodOutcome outcome{};
      cache.acquireCount(terrain.nodes[b], terrain.lods[b], kTarget, &outcome);
      const auto it = std::find(model.begin(), model.end(), b);
      EXPECT_EQ(outcome, it != model.end() ? LodOutcome::Reused : LodOutcome::Built) << "step " << step;
      if (it != model.end())
        model.erase(it);
      else if (model.size() == kCapacity)
        model.pop_back();
      model.insert(model.begin(), b);
    }
    ASSERT_EQ(cache.size(), model.size()) << "step " << step;
    for (std::size_t other = 0; other < terrain.lods.size(); ++other) {
      ASSERT_EQ(cache.contains(terrain.nodes[other]), std::find(model.begin(), model.end(), other) != model.end())
          << "step " << step << " block " << other;
    }
  }
  EXPECT_EQ(cache.bytes(), model.size() * blockBytes);
  expectCountersAddUp(cache);
}

TEST(LodCache, DisabledCacheAlwaysRebuilds) {
  const Terrain terrain = makeTerrain(sinesField(2 * 33 + 1, 2 * 33 + 1));
  LodCacheOptions options;
  options.enabled = false;
  LodCache cache(options);
  terrain::RtinScratch scratch;
  BlockMesh fresh;
  const glm::dvec3 camera{300.0, 200.0, 150.0};
  for (int frame = 0; frame < 5; ++frame) {
    cache.beginFrame();
    for (std::size_t b = 0; b < terrain.lods.size(); ++b) {
      const LodView view = viewFor(terrain.lods[b], camera);
      LodOutcome outcome{};
      const BlockMesh& mesh = cache.acquire(terrain.nodes[b], terrain.lods[b], view, &outcome);
      EXPECT_EQ(outcome, frame == 0 ? LodOutcome::Built : LodOutcome::RebuiltUncached);
      terrain.lods[b].extractView(view, fresh, scratch);
      EXPECT_TRUE(sameMesh(mesh, fresh));
    }
  }
  EXPECT_EQ(cache.counters().hits, 0u);
  EXPECT_EQ(cache.reuseRate(), 0.0);
  // Switching caching on: the uncached meshes carry no summary, so the first use rebuilds.
  cache.setEnabled(true);
  cache.beginFrame();
  LodOutcome outcome{};
  cache.acquire(terrain.nodes[0], terrain.lods[0], viewFor(terrain.lods[0], camera), &outcome);
  EXPECT_EQ(outcome, LodOutcome::RebuiltChanged);
  cache.acquire(terrain.nodes[0], terrain.lods[0], viewFor(terrain.lods[0], camera), &outcome);
  EXPECT_EQ(outcome, LodOutcome::Reused);
  expectCountersAddUp(cache);
}

TEST(LodCache, CountModeReusesWithinTheHysteresis) {
  const Terrain terrain = makeTerrain(sinesField(33 + 1, 33 + 1));
  const BlockLod& lod = terrain.lods[0];
  const NodeId node = terrain.nodes[0];
  LodCache cache;  // countHysteresis 0.1
  terrain::RtinScratch scratch;
  BlockMesh fresh;
  auto acquire = [&](std::size_t target) {
    LodOutcome outcome{};
    const BlockMesh& mesh = cache.acquireCount(node, lod, target, &outcome);
    EXPECT_LE(mesh.triangleCount(), std::max<std::size_t>(target, 2));
    return std::pair{outcome, mesh.triangleCount()};
  };
  const auto [built, count] = acquire(400);
  EXPECT_EQ(built, LodOutcome::Built);
  EXPECT_EQ(acquire(400).first, LodOutcome::Reused);
  // Any target from the reached count up to 400 gives the same greedy mesh: reusing is exact.
  for (std::size_t target : {count, (count + 400) / 2}) {
    EXPECT_EQ(acquire(target).first, LodOutcome::Reused) << target;
    lod.extractCount(target, fresh, scratch);
    EXPECT_TRUE(sameMesh(*cache.find(node), fresh)) << target;
  }
  EXPECT_EQ(acquire(440).first, LodOutcome::Reused);          // within 10 % above
  EXPECT_EQ(acquire(441).first, LodOutcome::RebuiltChanged);  // past it
  EXPECT_EQ(acquire(441).first, LodOutcome::Reused);
  EXPECT_EQ(acquire(200).first, LodOutcome::RebuiltChanged);  // below the mesh's count
  // Below the coarsest mesh: every target gives the two root triangles, so no rebuild loop.
  EXPECT_EQ(acquire(1).first, LodOutcome::RebuiltChanged);
  EXPECT_EQ(acquire(0).first, LodOutcome::Reused);
  EXPECT_EQ(acquire(1).first, LodOutcome::Reused);
  // Switching to view mode rebuilds; the footprint check catches another block's data.
  LodOutcome outcome{};
  cache.acquire(node, lod, viewFor(lod, {100.0, 100.0, 200.0}), &outcome);
  EXPECT_EQ(outcome, LodOutcome::RebuiltChanged);
  const Terrain other = makeTerrain(sinesField(2 * 33 + 1, 33 + 1));
  cache.acquire(node, other.lods[1], viewFor(other.lods[1], {100.0, 100.0, 200.0}), &outcome);
  EXPECT_EQ(outcome, LodOutcome::RebuiltChanged);
  expectCountersAddUp(cache);
}

// ---- pins (pin(), RebuiltPinned) ----------------------------------------------------------

// Positions along `side` of the mesh's side list: i on South and North, j on West and East.
std::vector<int> sidePositions(const BlockMesh& mesh, terrain::BlockEdge side) {
  std::vector<int> out;
  for (std::uint32_t v : mesh.edge(side)) {
    const GridVertex g = mesh.vertices[v];
    out.push_back(side == terrain::BlockEdge::South || side == terrain::BlockEdge::North ? g.i : g.j);
  }
  return out;
}

bool hasPosition(const BlockMesh& mesh, terrain::BlockEdge side, int position) {
  const std::vector<int> positions = sidePositions(mesh, side);
  return std::find(positions.begin(), positions.end(), position) != positions.end();
}

bool containsVertices(const BlockMesh& fine, const BlockMesh& coarse) {
  for (const GridVertex& c : coarse.vertices) {
    bool found = false;
    for (const GridVertex& f : fine.vertices) found |= f.i == c.i && f.j == c.j;
    if (!found) return false;
  }
  return true;
}

// pin() on an uncached node fails; pinned positions make the next acquire rebuild
// (RebuiltPinned) with those side vertices, later acquires keep them and reuse the mesh, pinning
// what is pinned already changes nothing, and a camera receding far enough for a needlessly-fine
// rebuild drops the pins.
TEST(LodCache, PinsRebuildOnceAreKeptAndDroppedWhenTheCameraRecedes) {
  const Terrain terrain = makeTerrain(sinesField(33 + 1, 33 + 1));
  ASSERT_EQ(terrain.lods.size(), 1u);
  const BlockLod& lod = terrain.lods[0];
  const NodeId node = terrain.nodes[0];
  const terrain::BlockEdge south = terrain::BlockEdge::South, east = terrain::BlockEdge::East;
  LodCache cache;
  const double headroom = LodCacheOptions{}.headroom;
  terrain::RtinScratch scratch;
  BlockMesh fresh;
  // What the cache builds for `view` with `pins`: the extraction it promises.
  auto expectBuiltFor = [&](const BlockMesh& mesh, const LodView& view, const terrain::BoundaryPins* pins) {
    LodView build = view;
    build.tolerancePx = view.tolerancePx / (1.0 + headroom);
    lod.extractView(build, fresh, scratch, pins);
    EXPECT_TRUE(sameMesh(mesh, fresh));
  };

  EXPECT_FALSE(cache.pin(node, south, 0, 32));  // not cached
  EXPECT_EQ(cache.pins(node), nullptr);
  EXPECT_FALSE(cache.contains(node));

  // High over the block's north-east corner: the south side, farther away, stays coarser.
  const glm::dvec3 near{300.0, 300.0, 600.0};
  const LodView view = viewFor(lod, near);
  LodOutcome outcome{};
  const BlockMesh& first = cache.acquire(node, lod, view, &outcome);
  ASSERT_EQ(outcome, LodOutcome::Built);
  ASSERT_NE(cache.pins(node), nullptr);
  EXPECT_FALSE(cache.pins(node)->any());
  const BlockMesh unpinned = first;
  // Pin a run of south positions the mesh lacks.
  int from = -1;
  for (int p = 1; p < 32 && from < 0; ++p) {
    if (!hasPosition(unpinned, south, p)) from = p;
  }
  ASSERT_GE(from, 0) << "the south side is at full detail already";
  const int to = std::min(from + 3, 32);

  EXPECT_TRUE(cache.pin(node, south, from, to));
  ASSERT_NE(cache.pins(node), nullptr);
  EXPECT_TRUE(cache.pins(node)->any());
  for (int p = from; p <= to; ++p) EXPECT_TRUE(cache.pins(node)->pinned(south, p));
  EXPECT_FALSE(cache.pins(node)->pinned(south, from - 1));
  EXPECT_TRUE(sameMesh(*cache.find(node), unpinned));  // nothing rebuilt before the next acquire

  const BlockMesh& pinned = cache.acquire(node, lod, view, &outcome);
  EXPECT_EQ(outcome, LodOutcome::RebuiltPinned);
  EXPECT_EQ(cache.counters().pinned, 1u);
  for (int p = from; p <= to; ++p) EXPECT_TRUE(hasPosition(pinned, south, p)) << "pinned position " << p;
  EXPECT_TRUE(containsVertices(pinned, unpinned));
  EXPECT_GT(pinned.vertices.size(), unpinned.vertices.size());
  EXPECT_LE(worstProjectedRatio(terrain.field, lod, pinned, view), 1.0 + 1e-9);
  expectBuiltFor(pinned, view, cache.pins(node));
  const BlockMesh pinnedCopy = pinned;

  // Later acquires from the same camera keep the pins and reuse the mesh.
  for (int frame = 0; frame < 3; ++frame) {
    cache.beginFrame();
    const BlockMesh& mesh = cache.acquire(node, lod, view, &outcome);
    EXPECT_EQ(outcome, LodOutcome::Reused) << "frame " << frame;
    EXPECT_TRUE(sameMesh(mesh, pinnedCopy));
  }
  // Pinning what is pinned already: nothing new, no rebuild.
  EXPECT_FALSE(cache.pin(node, south, from, to));
  EXPECT_FALSE(cache.pin(node, south, from + 1, to));
  cache.acquire(node, lod, view, &outcome);
  EXPECT_EQ(outcome, LodOutcome::Reused);
  EXPECT_EQ(cache.counters().pinned, 1u);

  // One more position, on another side: one more pinned rebuild, keeping the old pins too.
  int eastPosition = -1;
  for (int p = 1; p < 32 && eastPosition < 0; ++p) {
    if (!hasPosition(pinnedCopy, east, p)) eastPosition = p;
  }
  ASSERT_GE(eastPosition, 0) << "the east side is at full detail already";
  EXPECT_TRUE(cache.pin(node, east, eastPosition, eastPosition));
  ASSERT_LT(to, 32);
  EXPECT_TRUE(cache.pin(node, south, from, to + 1));  // overlapping, one new position
  const BlockMesh& twice = cache.acquire(node, lod, view, &outcome);
  EXPECT_EQ(outcome, LodOutcome::RebuiltPinned);
  EXPECT_EQ(cache.counters().pinned, 2u);
  EXPECT_TRUE(hasPosition(twice, east, eastPosition));
  for (int p = from; p <= to + 1; ++p) EXPECT_TRUE(hasPosition(twice, south, p)) << p;
  expectBuiltFor(twice, view, cache.pins(node));

  // Closing in: a too-coarse rebuild keeps the pins.
  const LodView closer = viewFor(lod, {250.0, 250.0, 150.0});
  const BlockMesh& close = cache.acquire(node, lod, closer, &outcome);
  EXPECT_EQ(outcome, LodOutcome::RebuiltTooCoarse);
  EXPECT_TRUE(cache.pins(node)->any());
  EXPECT_TRUE(cache.pins(node)->pinned(east, eastPosition));
  for (int p = from; p <= to; ++p) EXPECT_TRUE(hasPosition(close, south, p)) << p;
  EXPECT_LE(worstProjectedRatio(terrain.field, lod, close, closer), 1.0 + 1e-9);

  // Receding straight up: at some point the mesh is needlessly fine, and that rebuild drops
  // the pins.
  bool dropped = false;
  int reusedWhilePinned = 0;
  for (int frame = 1; frame <= 200 && !dropped; ++frame) {
    const LodView up = viewFor(lod, {250.0, 250.0, 150.0 + 2.0 * frame * frame});
    cache.beginFrame();
    const BlockMesh& mesh = cache.acquire(node, lod, up, &outcome);
    EXPECT_LE(worstProjectedRatio(terrain.field, lod, mesh, up), 1.0 + 1e-9) << "frame " << frame;
    if (outcome == LodOutcome::RebuiltNeedlesslyFine) {
      dropped = true;
      ASSERT_NE(cache.pins(node), nullptr);
      EXPECT_FALSE(cache.pins(node)->any());
      expectBuiltFor(mesh, up, nullptr);  // built without pins
    } else {
      EXPECT_TRUE(cache.pins(node)->any()) << "frame " << frame << " outcome " << int(outcome);
      for (int p = from; p <= to + 1; ++p) EXPECT_TRUE(hasPosition(mesh, south, p)) << "frame " << frame;
      reusedWhilePinned += outcome == LodOutcome::Reused;
    }
  }
  EXPECT_TRUE(dropped);
  EXPECT_GT(reusedWhilePinned, 0);
  EXPECT_GT(cache.counters().needlesslyFine, 0u);

  // Pins may come back after the drop; invalidate forgets them with the mesh.
  EXPECT_TRUE(cache.pin(node, south, from, to));
  EXPECT_TRUE(cache.invalidate(node));
  EXPECT_EQ(cache.pins(node), nullptr);
  EXPECT_FALSE(cache.pin(node, south, from, to));
  cache.acquire(node, lod, view, &outcome);
  EXPECT_EQ(outcome, LodOutcome::Built);
  EXPECT_FALSE(cache.pins(node)->any());
  EXPECT_TRUE(sameMesh(*cache.find(node), unpinned));
  expectCountersAddUp(cache);
}

// ---- steady state -----------------------------------------------------------------------

TEST(LodCache, SteadyStateAllocatesNothing) {
  const Terrain terrain = makeTerrain(sinesField(3 * 33 + 1, 3 * 33 + 1));
  LodCache cache;
  auto frame = [&](const glm::dvec3& camera) {
    cache.beginFrame();
    for (std::size_t b = 0; b < terrain.lods.size(); ++b)
      cache.acquire(terrain.nodes[b], terrain.lods[b], viewFor(terrain.lods[b], camera));
  };
  // Still camera, warm cache.
  const glm::dvec3 still{400.0, 500.0, 120.0};
  frame(still);
  std::uint64_t before = allocationCount;
  for (int f = 0; f < 50; ++f) frame(still);
  EXPECT_EQ(allocationCount - before, 0u);

  // A camera shuttling between two places: every switch rebuilds blocks (closer ones too
  // coarse, farther ones needlessly fine) in their own memory, which after the first round
  // trips is large enough.
  const glm::dvec3 other{700.0, 300.0, 90.0};
  for (int round = 0; round < 3; ++round) {
    frame(other);
    frame(still);
  }
  const std::uint64_t rebuildsBefore = cache.counters().rebuilds;
  before = allocationCount;
  for (int round = 0; round < 10; ++round) {
    frame(other);
    frame(still);
  }
  EXPECT_EQ(allocationCount - before, 0u);
  EXPECT_GT(cache.counters().rebuilds - rebuildsBefore, 20u);

  // Caching off (the --compare-cache baseline) rebuilds every block every frame, in place.
  cache.setEnabled(false);
  frame(still);
  before = allocationCount;
  for (int f = 0; f < 10; ++f) frame(still);
  EXPECT_EQ(allocationCount - before, 0u);
  cache.setEnabled(true);

  // A full cache on the move: each new block takes over the evicted block's slot and memory.
  const Terrain big = makeTerrain(periodicField(4));
  LodCacheOptions options;
  LodCache probe;
  options.budgetBytes = 4 * meshBytes(probe.acquireCount(big.nodes[0], big.lods[0], 300)) + 100;
  LodCache full(options);
  auto sweep = [&] {
    for (std::size_t b = 0; b < big.lods.size(); ++b) {
      full.beginFrame();
      full.acquireCount(big.nodes[b], big.lods[b], 300);
    }
  };
  sweep();
  sweep();
  before = allocationCount;
  const std::uint64_t evictionsBefore = full.counters().evictions;
  sweep();
  EXPECT_EQ(allocationCount - before, 0u);
  EXPECT_EQ(full.counters().evictions - evictionsBefore, big.lods.size());
}

// ---- a flyover ----------------------------------------------------------------------------

// Over a generated DEM (the sample terrain's generator), a loop flight at 20 m a frame with
// every block drawn: the cache reuses most meshes, and draws at most 15 % more triangles than
// rebuilding every block every frame would (Chuang 2001 reports 2.2-8.7 % fewer; here receding
// blocks count too, with no culling).
TEST(LodCache, FlyoverReusesMostMeshesWithFewExtraTriangles) {
  terrain::GeneratorOptions generator;
  generator.size = 12 * 33 + 1;
  generator.seed = 7;
  generator.spacingM = 40.0;
  const Terrain terrain = makeTerrain(terrain::generateTerrain(generator).value());
  float top = -std::numeric_limits<float>::infinity();
  for (const BlockLod& lod : terrain.lods) top = std::max(top, lod.maxHeight());
  const double k = 800.0 / (2.0 * std::tan(std::numbers::pi / 9.0));  // the paper's 40 degrees, 800 px
  const double extent = terrain.field.extentX();
  LodCache cache;
  terrain::RtinScratch scratch;
  BlockMesh fresh;
  std::uint64_t cachedTriangles = 0, freshTriangles = 0;
  for (int frame = 0; frame < 400; ++frame) {
    const double travelled = 20.0 * frame, angle = travelled / (0.35 * extent);
    const glm::dvec3 camera{extent / 2 + 0.35 * extent * std::cos(angle), extent / 2 + 0.3 * extent * std::sin(angle),
                            top + 300.0 + 200.0 * std::sin(travelled / 2000.0)};
    cache.beginFrame();
    for (std::size_t b = 0; b < terrain.lods.size(); ++b) {
      const LodView view = viewFor(terrain.lods[b], camera, 1.0, k);
      cachedTriangles += cache.acquire(terrain.nodes[b], terrain.lods[b], view).triangleCount();
      terrain.lods[b].extractView(view, fresh, scratch);
      freshTriangles += fresh.triangleCount();
    }
  }
  const double ratio = double(cachedTriangles) / double(freshTriangles);
  RecordProperty("triangle_ratio", std::to_string(ratio));
  RecordProperty("reuse_rate", std::to_string(cache.reuseRate()));
  EXPECT_LE(ratio, 1.15);
  EXPECT_GT(cache.reuseRate(), 0.85);
  EXPECT_GT(cache.counters().needlesslyFine, 0u);
  expectCountersAddUp(cache);
}

}  // namespace
}  // namespace polder::cache
