// Dikes (dikes.hpp): watertight together with the block meshes on random quadtree cuts and
// random per-block LODs (checked by watertight.hpp, itself tested in watertight_test.cpp),
// exact dike errors (against brute force written here) within the a-priori bound, every
// triangle inside its owner's bound region, no reallocation in steady state, and errors for
// inputs that are not a cut.
//
// Steady state is checked through capacities and data pointers: block_quadtree_test.cpp in
// the same program already replaces the global operator new, so this file cannot count
// allocations itself; buildDikes uses no memory but DikeMesh's and DikeScratch's vectors.
#include <polder/terrain/dikes.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include <polder/terrain/block_layout.hpp>
#include <polder/terrain/dike_errors.hpp>
#include <polder/terrain/rtin.hpp>
#include <polder/terrain/watertight.hpp>

namespace polder::terrain {
namespace {

// Hills, ridges, a terrace and per-sample noise: every LOD has real errors and every dike
// real slopes.
Heightfield makeField(int width, int height, std::uint64_t seed) {
  Heightfield field(width, height, 10.0, 10.0);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double a = 0.02 + 0.05 * unit(rng), b = 0.02 + 0.05 * unit(rng), phase = 6.0 * unit(rng);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      double h =
          300.0 + 120.0 * std::sin(a * x + phase) * std::cos(b * y) + 60.0 * std::abs(std::sin(0.013 * (x + 2 * y)));
      h += 25.0 * std::sin(0.3 * x - 0.2 * y) + 4.0 * unit(rng);
      if ((x / 17 + y / 23) % 5 == 0) h = std::floor(h / 20.0) * 20.0;  // terraces: flat spots and steps
      field.at(x, y) = float(h);
    }
  }
  return field;
}

bool drawable(const BlockLayout& layout, NodeId node) {
  const SampleRect f = layout.footprint(node);
  const int s = layout.stride(node);
  return (layout.width() - 1 - f.x0) / s >= 1 && (layout.height() - 1 - f.y0) / s >= 1;
}

enum class CutKind { Random, DeepPaths, Finest, Coarsest };

// A quadtree cut from the root: nodes that cannot be drawn at their stride are always split,
// children outside the DEM skipped.
void cutFrom(const BlockLayout& layout, NodeId node, CutKind kind, std::mt19937_64& rng,
             const std::vector<std::pair<int, int>>& targets, std::vector<NodeId>& cut) {
  bool split = false;
  if (node.level > 0) {
    if (!drawable(layout, node)) {
      split = true;
    } else {
      switch (kind) {
        case CutKind::Random:
          split = std::uniform_real_distribution<double>(0.0, 1.0)(rng) < 0.55;
          break;
        case CutKind::Finest:
          split = true;
          break;
        case CutKind::Coarsest:
          split = false;
          break;
        case CutKind::DeepPaths: {
          // Down to level 0 around a few points only: nodes many levels apart meet there.
          const SampleRect f = layout.footprint(node);
          for (const auto& [x, y] : targets) split |= x >= f.x0 && x <= f.x1 && y >= f.y0 && y <= f.y1;
          break;
        }
      }
    }
  }
  if (!split) {
    cut.push_back(node);
    return;
  }
  for (int q = 0; q < 4; ++q) {
    const NodeId child = node.child(q);
    if (layout.exists(child)) cutFrom(layout, child, kind, rng, targets, cut);
  }
}

std::vector<NodeId> makeCut(const BlockLayout& layout, CutKind kind, std::mt19937_64& rng) {
  std::vector<std::pair<int, int>> targets;
  std::uniform_int_distribution<int> tx(0, layout.width() - 1), ty(0, layout.height() - 1);
  const int count = std::uniform_int_distribution<int>(1, 3)(rng);
  for (int i = 0; i < count; ++i) targets.emplace_back(tx(rng), ty(rng));
  // Half of the time one target sits just east of the root's vertical midline, so that a
  // level-0 block there meets the root's unrefined west child: rootLevel - 1 levels apart.
  const int midline = layout.pitch() << std::max(layout.rootLevel() - 1, 0);
  if (kind == CutKind::DeepPaths && rng() % 2 == 0 && midline + 1 < layout.width()) targets[0].first = midline + 1;
  std::vector<NodeId> cut;
  cutFrom(layout, layout.root(), kind, rng, targets, cut);
  return cut;
}

// The largest level difference between two nodes of the cut whose footprints share a side.
int maxLevelJump(const BlockLayout& layout, const std::vector<NodeId>& cut) {
  const int bx = layout.nodesX(0), by = layout.nodesY(0);
  std::vector<int> level(std::size_t(bx) * by, -1);
  for (const NodeId& n : cut) {
    const int span = 1 << n.level;
    for (int y = int(n.by) * span; y < std::min((int(n.by) + 1) * span, by); ++y)
      for (int x = int(n.bx) * span; x < std::min((int(n.bx) + 1) * span, bx); ++x)
        level[std::size_t(y) * bx + x] = n.level;
  }
  int jump = 0;
  for (int y = 0; y < by; ++y) {
    for (int x = 0; x < bx; ++x) {
      const int here = level[std::size_t(y) * bx + x];
      if (x + 1 < bx) jump = std::max(jump, std::abs(here - level[std::size_t(y) * bx + x + 1]));
      if (y + 1 < by) jump = std::max(jump, std::abs(here - level[std::size_t(y + 1) * bx + x]));
    }
  }
  return jump;
}

enum class LodKind { Mixed, Full, Coarsest };

// Block LODs built once per node and kept for the whole test.
struct Blocks {
  const Heightfield* field = nullptr;
  std::map<std::tuple<int, int, int>, BlockLod> lods;
  RtinScratch scratch;

  const BlockLod& lod(const BlockLayout& layout, NodeId node) {
    const auto key = std::make_tuple(int(node.level), int(node.bx), int(node.by));
    auto it = lods.find(key);
    if (it == lods.end()) {
      auto built = BlockLod::build(*field, layout.interior(node));
      EXPECT_TRUE(built.ok()) << (built.ok() ? "" : built.error().message);
      it = lods.emplace(key, std::move(*built)).first;
    }
    return it->second;
  }

  void extract(const BlockLod& lod, LodKind kind, std::mt19937_64& rng, BlockMesh& mesh) {
    std::uniform_int_distribution<int> pick(0, 4);
    const int choice = kind == LodKind::Full ? 0 : (kind == LodKind::Coarsest ? 1 : pick(rng));
    switch (choice) {
      case 0:
        lod.extractThreshold(-1.0f, mesh, scratch);
        break;
      case 1:
        lod.extractCount(0, mesh, scratch);
        break;
      case 2:
        lod.extractThreshold(float(std::uniform_real_distribution<double>(0.0, 30.0)(rng)), mesh, scratch);
        break;
      case 3:
        lod.extractCount(std::size_t(std::uniform_int_distribution<int>(2, 300)(rng)), mesh, scratch);
        break;
      default: {
        LodView view;
        view.camera = glm::dvec3(std::uniform_real_distribution<double>(-500.0, 1500.0)(rng),
                                 std::uniform_real_distribution<double>(-500.0, 1500.0)(rng), 600.0);
        view.projectionConstant = 800.0;
        view.tolerancePx = std::uniform_real_distribution<double>(0.5, 8.0)(rng);
        lod.extractView(view, mesh, scratch);
        break;
      }
    }
  }
};

struct FrameResult {
  DikeMesh dikes;
  std::vector<BlockMesh> meshes;
  std::vector<DikeBlock> blocks;
};

// Builds every block mesh and the dikes of a cut.
void buildFrame(const BlockLayout& layout, const std::vector<NodeId>& cut, Blocks& lods, LodKind kind,
                std::mt19937_64& rng, FrameResult& frame, DikeScratch& scratch) {
  frame.meshes.assign(cut.size(), BlockMesh{});
  frame.blocks.clear();
  for (std::size_t i = 0; i < cut.size(); ++i) {
    lods.extract(lods.lod(layout, cut[i]), kind, rng, frame.meshes[i]);
    frame.blocks.push_back(DikeBlock{cut[i], &frame.meshes[i]});
  }
  const Status status = buildDikes(layout, frame.blocks, frame.dikes, scratch);
  ASSERT_TRUE(status.ok()) << status.error().message;
}

void expectWatertight(const BlockLayout& layout, const FrameResult& frame, const std::string& what) {
  TriangleSoup soup;
  for (const BlockMesh& mesh : frame.meshes) soup.addBlock(mesh);
  soup.addDikes(frame.dikes);
  WatertightOptions options;
  options.samplePoints = 200;
  const WatertightReport r = checkWatertight(soup, layout.width(), layout.height(), options);
  EXPECT_TRUE(r.watertight()) << what << ": open " << r.openEdges << ", T-junctions " << r.tJunctions << ", degenerate "
                              << r.degenerate << ", clockwise " << r.wrongWinding << ", flipped " << r.flippedEdges
                              << ", over-shared " << r.overSharedEdges << ", border " << r.borderErrors << ", area "
                              << r.doubledArea << " of " << r.expectedDoubledArea << ", samples uncovered "
                              << r.samplesUncovered << " overlapped " << r.samplesOverlapped;
}

// Exact errors within the owners' bounds, and every triangle inside its owner's region.
struct ErrorStats {
  double worstExact = 0.0;
  double worstRatio = 0.0;  // exact / bound, over triangles with a nonzero bound
};

// Largest |surface - plane| over a closed triangle, where the surface is heightfield.hpp's
// triangulation (each cell cut from (x+1, y) to (x, y+1)): the triangle is clipped against
// each surface triangle of every cell under it, and the difference (linear on each piece) is
// evaluated at the pieces' corners.
double bruteForceError(const Heightfield& field, DikeVertex a, DikeVertex b, DikeVertex c) {
  struct P {
    double x, y;
  };
  auto planeOf = [](P p0, double z0, P p1, double z1, P p2, double z2) {
    const double e1x = p1.x - p0.x, e1y = p1.y - p0.y, e2x = p2.x - p0.x, e2y = p2.y - p0.y;
    const double det = e1x * e2y - e1y * e2x;
    const double gx = ((z1 - z0) * e2y - (z2 - z0) * e1y) / det, gy = (e1x * (z2 - z0) - e2x * (z1 - z0)) / det;
    return std::array<double, 3>{z0 - gx * p0.x - gy * p0.y, gx, gy};
  };
  const P ta{double(a.x), double(a.y)}, tb{double(b.x), double(b.y)}, tc{double(c.x), double(c.y)};
  const auto drawn = planeOf(ta, field.at(a.x, a.y), tb, field.at(b.x, b.y), tc, field.at(c.x, c.y));
  double worst = 0.0;
  std::vector<P> poly, next;
  for (int y = std::min({a.y, b.y, c.y}); y < std::max({a.y, b.y, c.y}); ++y) {
    for (int x = std::min({a.x, b.x, c.x}); x < std::max({a.x, b.x, c.x}); ++x) {
      const P corners[2][3] = {{{double(x), double(y)}, {x + 1.0, double(y)}, {double(x), y + 1.0}},
                               {{x + 1.0, y + 1.0}, {double(x), y + 1.0}, {x + 1.0, double(y)}}};
      for (const auto& s : corners) {
        poly = {ta, tb, tc};
        for (int e = 0; e < 3 && !poly.empty(); ++e) {  // Sutherland-Hodgman against one edge
          const P p = s[e], q = s[(e + 1) % 3];
          auto side = [&](P r) { return (q.x - p.x) * (r.y - p.y) - (q.y - p.y) * (r.x - p.x); };
          next.clear();
          for (std::size_t i = 0; i < poly.size(); ++i) {
            const P u = poly[i], w = poly[(i + 1) % poly.size()];
            const double su = side(u), sw = side(w);
            if (su >= 0) next.push_back(u);
            if ((su > 0 && sw < 0) || (su < 0 && sw > 0))
              next.push_back(P{u.x + (w.x - u.x) * su / (su - sw), u.y + (w.y - u.y) * su / (su - sw)});
          }
          poly.swap(next);
        }
        if (poly.empty()) continue;
        const auto surface = planeOf(s[0], field.at(int(s[0].x), int(s[0].y)), s[1], field.at(int(s[1].x), int(s[1].y)),
                                     s[2], field.at(int(s[2].x), int(s[2].y)));
        for (const P& p : poly)
          worst = std::max(worst, std::abs((surface[0] + surface[1] * p.x + surface[2] * p.y) -
                                           (drawn[0] + drawn[1] * p.x + drawn[2] * p.y)));
      }
    }
  }
  return worst;
}

void expectHonestErrors(const Heightfield& field, const BlockLayout& layout, const DikeErrorBounds& bounds,
                        const std::vector<NodeId>& cut, const FrameResult& frame, const std::string& what,
                        ErrorStats& stats, bool bruteForce) {
  std::vector<float> exact;
  const float worst = dikeTriangleErrors(field, frame.dikes, &exact);
  ASSERT_EQ(exact.size(), frame.dikes.triangleCount());
  ASSERT_EQ(frame.dikes.owners.size(), frame.dikes.triangleCount());
  float frameBound = 0.0f;
  for (const NodeId& node : cut) frameBound = std::max(frameBound, bounds.bound(node));
  EXPECT_LE(worst, frameBound) << what;
  for (std::size_t t = 0; t < exact.size(); ++t) {
    if (bruteForce) {
      const DikeVertex* v = &frame.dikes.vertices[0];
      const std::uint32_t* i = &frame.dikes.indices[3 * t];
      const double expected = bruteForceError(field, v[i[0]], v[i[1]], v[i[2]]);
      EXPECT_NEAR(exact[t], expected, 1e-4 * (1.0 + expected)) << what << ": triangle " << t;
    }
    const NodeId owner = cut[frame.dikes.owners[t]];
    const float bound = bounds.bound(owner);
    EXPECT_LE(exact[t], bound) << what << ": triangle " << t;
    const SampleRect region = dikeBoundRegion(layout, owner);
    for (int c = 0; c < 3; ++c) {
      const DikeVertex& v = frame.dikes.vertices[frame.dikes.indices[3 * t + c]];
      ASSERT_TRUE(v.x >= region.x0 && v.x <= region.x1 && v.y >= region.y0 && v.y <= region.y1)
          << what << ": triangle " << t << " leaves its owner's region";
    }
    stats.worstExact = std::max(stats.worstExact, double(exact[t]));
    if (bound > 0.0f) stats.worstRatio = std::max(stats.worstRatio, double(exact[t]) / bound);
  }
}

struct Case {
  int width, height, k;
};

// The main property test: many cuts, LODs and DEM shapes.
TEST(Dikes, WatertightAndHonestOnRandomCutsAndLods) {
  // Odd sizes (edge blocks clipped), sizes one sample past a block, single blocks, and two
  // DEMs with root level 5 and 4 for neighbours 3 and more levels apart.
  const Case cases[] = {{67, 67, 4},  {100, 61, 4},  {131, 97, 4},  {200, 150, 4}, {34, 34, 5},
                        {97, 140, 5}, {163, 163, 5}, {250, 90, 5},  {66, 300, 4},  {35, 200, 5},
                        {18, 18, 4},  {260, 260, 4}, {401, 333, 4}, {301, 529, 5}};
  std::mt19937_64 rng(20240611);
  int frames = 0, deepJumps = 0;
  ErrorStats stats;
  DikeScratch scratch;
  FrameResult frame;
  for (const Case& c : cases) {
    const Heightfield field = makeField(c.width, c.height, rng());
    auto layout = BlockLayout::create(c.width, c.height, c.k);
    ASSERT_TRUE(layout.ok());
    auto bounds = DikeErrorBounds::build(field, *layout);
    ASSERT_TRUE(bounds.ok());
    Blocks lods;
    lods.field = &field;
    const CutKind cutKinds[] = {CutKind::Random, CutKind::DeepPaths, CutKind::Finest, CutKind::Coarsest};
    const LodKind lodKinds[] = {LodKind::Mixed, LodKind::Full, LodKind::Coarsest};
    for (CutKind cutKind : cutKinds) {
      const int repeats = cutKind == CutKind::Random || cutKind == CutKind::DeepPaths ? 6 : 1;
      for (int r = 0; r < repeats; ++r) {
        const std::vector<NodeId> cut = makeCut(*layout, cutKind, rng);
        deepJumps += maxLevelJump(*layout, cut) >= 3;
        for (LodKind lodKind : lodKinds) {
          const std::string what = std::to_string(c.width) + "x" + std::to_string(c.height) + " k" +
                                   std::to_string(c.k) + " cut " + std::to_string(int(cutKind)) + "/" +
                                   std::to_string(r) + " lod " + std::to_string(int(lodKind)) + " nodes " +
                                   std::to_string(cut.size());
          buildFrame(*layout, cut, lods, lodKind, rng, frame, scratch);
          if (HasFatalFailure()) return;
          expectWatertight(*layout, frame, what);
          expectHonestErrors(field, *layout, *bounds, cut, frame, what, stats, frames % 7 == 0);
          if (HasFailure()) return;
          ++frames;
        }
      }
    }
  }
  EXPECT_GT(frames, 300);
  EXPECT_GT(deepJumps, 20);  // cuts where side neighbours differ by 3 levels or more
  RecordProperty("frames", frames);
  RecordProperty("cutsWithJumpsOf3OrMore", deepJumps);
  RecordProperty("worstExactErrorM", std::to_string(stats.worstExact));
  RecordProperty("worstExactOverBound", std::to_string(stats.worstRatio));
}

// Level jumps far beyond the default block size: k = 1 and 2 give many levels on small DEMs.
TEST(Dikes, WatertightWithNeighboursManyLevelsApart) {
  std::mt19937_64 rng(77);
  DikeScratch scratch;
  FrameResult frame;
  int bigJumps = 0;
  for (const Case& c : {Case{230, 190, 1}, Case{301, 127, 2}, Case{160, 160, 1}}) {
    const Heightfield field = makeField(c.width, c.height, rng());
    auto layout = BlockLayout::create(c.width, c.height, c.k);
    ASSERT_TRUE(layout.ok());
    auto bounds = DikeErrorBounds::build(field, *layout);
    Blocks lods;
    lods.field = &field;
    ErrorStats stats;
    for (int r = 0; r < 6; ++r) {
      const std::vector<NodeId> cut = makeCut(*layout, CutKind::DeepPaths, rng);
      bigJumps += maxLevelJump(*layout, cut) >= 5;
      const std::string what = std::to_string(c.width) + "x" + std::to_string(c.height) + " k" + std::to_string(c.k) +
                               " cut " + std::to_string(r);
      buildFrame(*layout, cut, lods, LodKind::Mixed, rng, frame, scratch);
      if (HasFatalFailure()) return;
      expectWatertight(*layout, frame, what);
      expectHonestErrors(field, *layout, *bounds, cut, frame, what, stats, false);
      if (HasFailure()) return;
    }
  }
  EXPECT_GT(bigJumps, 5);
}

// With every block at full detail at level 0 (stride 1), every dike triangle is a half cell
// of heightfield.hpp's triangulation, cut from (x+1, y) to (x, y+1): zippers and junctions
// alike, so the dikes are the surface itself and every exact error is 0. On random heights per
// sample any other cut of a cell is off by |h00 + h11 - h10 - h01| / 2 at the cell centre, so a
// junction of one cell cut along the other diagonal (the tie-break between two equally long
// diagonals) shows at once.
TEST(Dikes, FullDetailAtLevelZeroIsTheSurface) {
  // Edge blocks clipped, dikes against the DEM's east and north borders (e.g. 69 = 4 * 17 + 1:
  // the last interior ends one sample before the border), single-cell blocks (k = 1: a
  // junction at every block corner), and the default block size.
  const Case cases[] = {{67, 67, 4}, {69, 52, 4}, {100, 61, 4}, {131, 97, 3}, {34, 34, 5},
                        {35, 70, 5}, {41, 29, 1}, {30, 43, 2},  {18, 18, 4},  {19, 36, 4}};
  std::mt19937_64 rng(424242);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  DikeScratch scratch;
  FrameResult frame;
  std::size_t junctionTriangles = 0, zipperTriangles = 0, bruteForced = 0;
  for (const Case& c : cases) {
    Heightfield field(c.width, c.height, 10.0, 10.0);
    for (int y = 0; y < c.height; ++y)
      for (int x = 0; x < c.width; ++x) field.at(x, y) = float(100.0 * unit(rng));  // rough: no two cells alike
    auto layout = BlockLayout::create(c.width, c.height, c.k);
    ASSERT_TRUE(layout.ok());
    Blocks lods;
    lods.field = &field;
    const std::vector<NodeId> cut = makeCut(*layout, CutKind::Finest, rng);
    for (const NodeId& node : cut) ASSERT_EQ(node.level, 0);
    const std::string what = std::to_string(c.width) + "x" + std::to_string(c.height) + " k" + std::to_string(c.k);
    buildFrame(*layout, cut, lods, LodKind::Full, rng, frame, scratch);
    if (HasFatalFailure()) return;
    expectWatertight(*layout, frame, what);
    const DikeMesh& dikes = frame.dikes;
    std::vector<float> exact;
    EXPECT_EQ(dikeTriangleErrors(field, dikes, &exact), 0.0f) << what;
    ASSERT_EQ(exact.size(), dikes.triangleCount());
    for (std::size_t t = 0; t < dikes.triangleCount(); ++t) {
      const DikeVertex a = dikes.vertices[dikes.indices[3 * t]], b = dikes.vertices[dikes.indices[3 * t + 1]],
                       d = dikes.vertices[dikes.indices[3 * t + 2]];
      const std::string tri = what + (t < dikes.zipperTriangles ? ": zipper" : ": junction") + " triangle (" +
                              std::to_string(a.x) + "," + std::to_string(a.y) + ") (" + std::to_string(b.x) + "," +
                              std::to_string(b.y) + ") (" + std::to_string(d.x) + "," + std::to_string(d.y) + ")";
      EXPECT_EQ(dikeTriangleError(field, a, b, d), 0.0f) << tri;
      EXPECT_EQ(dikeTriangleError(field, a, d, b), 0.0f) << tri << " (other winding)";
      EXPECT_EQ(exact[t], 0.0f) << tri;
      // Its shape: one of the two halves of a cell, cut from (x+1, y) to (x, y+1).
      const int x0 = std::min({a.x, b.x, d.x}), y0 = std::min({a.y, b.y, d.y});
      std::array<std::pair<int, int>, 3> corners{{{a.x, a.y}, {b.x, b.y}, {d.x, d.y}}};
      std::sort(corners.begin(), corners.end());
      const std::array<std::pair<int, int>, 3> lower{{{x0, y0}, {x0, y0 + 1}, {x0 + 1, y0}}};
      const std::array<std::pair<int, int>, 3> upper{{{x0, y0 + 1}, {x0 + 1, y0}, {x0 + 1, y0 + 1}}};
      EXPECT_TRUE(corners == lower || corners == upper) << tri << " is not a half cell of the surface";
      if (t % 5 == 0) {  // the brute force of this file agrees (a sample of the triangles)
        EXPECT_LE(bruteForceError(field, a, b, d), 1e-9) << tri;
        ++bruteForced;
      }
    }
    junctionTriangles += dikes.triangleCount() - dikes.zipperTriangles;
    zipperTriangles += dikes.zipperTriangles;
  }
  EXPECT_GT(junctionTriangles, 100u);  // one-cell junctions at the block corners, among others
  EXPECT_GT(zipperTriangles, 1000u);
  EXPECT_GT(bruteForced, 100u);
}

// A 4-vertex junction of one cell, alone: two blocks of one cell side by side under two more
// (k = 1, 2 x 2 blocks, 6 x 6 samples), each at full detail. Whatever the walk's starting
// vertex, the cell where the four blocks' corners meet is cut from (x+1, y) to (x, y+1).
TEST(Dikes, OneCellJunctionsAreCutLikeTheSurface) {
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const int size = 6 + int(seed % 3);  // 6: no border strip; 7, 8: border strips and corners
    Heightfield field(size, size, 10.0, 10.0);
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x) field.at(x, y) = float(50.0 * unit(rng) - 25.0);
    auto layout = BlockLayout::create(size, size, 1);
    ASSERT_TRUE(layout.ok());
    Blocks lods;
    lods.field = &field;
    DikeScratch scratch;
    FrameResult frame;
    buildFrame(*layout, makeCut(*layout, CutKind::Finest, rng), lods, LodKind::Full, rng, frame, scratch);
    if (HasFatalFailure()) return;
    expectWatertight(*layout, frame, "seed " + std::to_string(seed));
    ASSERT_GT(frame.dikes.triangleCount(), frame.dikes.zipperTriangles);
    std::vector<float> exact;
    EXPECT_EQ(dikeTriangleErrors(field, frame.dikes, &exact), 0.0f) << "seed " << seed;
    // The junction at (2, 2)-(3, 3), where the four blocks' corners meet: its two triangles
    // share the diagonal (3, 2)-(2, 3) and neither uses (2, 2)-(3, 3).
    bool sawDiagonal = false;
    for (std::size_t t = frame.dikes.zipperTriangles; t < frame.dikes.triangleCount(); ++t) {
      DikeVertex v[3];
      for (int k = 0; k < 3; ++k) v[k] = frame.dikes.vertices[frame.dikes.indices[3 * t + k]];
      for (int e = 0; e < 3; ++e) {
        const DikeVertex p = v[e], q = v[(e + 1) % 3];
        const bool southWestToNorthEast = std::abs(p.x - q.x) == 1 && (p.x - q.x) == (p.y - q.y);
        EXPECT_FALSE(southWestToNorthEast) << "seed " << seed << ": junction edge (" << p.x << "," << p.y << ")-("
                                           << q.x << "," << q.y << ") cuts a cell against the surface";
        sawDiagonal |=
            (p == DikeVertex{3, 2} && q == DikeVertex{2, 3}) || (p == DikeVertex{2, 3} && q == DikeVertex{3, 2});
      }
    }
    EXPECT_TRUE(sawDiagonal) << "seed " << seed;
  }
}

// A DEM that is a single block: no gap when the block fills it, a border strip otherwise.
TEST(Dikes, SingleBlockDems) {
  std::mt19937_64 rng(5);
  DikeScratch scratch;
  FrameResult frame;
  for (const Case& c : {Case{33, 33, 5}, Case{34, 33, 5}, Case{33, 34, 5}, Case{34, 34, 5}, Case{2, 2, 1},
                        Case{3, 2, 1}, Case{4, 4, 1}, Case{17, 12, 4}}) {
    const Heightfield field = makeField(c.width, c.height, rng());
    auto layout = BlockLayout::create(c.width, c.height, c.k);
    ASSERT_TRUE(layout.ok());
    ASSERT_EQ(layout->rootLevel(), 0);
    Blocks lods;
    lods.field = &field;
    const std::vector<NodeId> cut{layout->root()};
    for (LodKind kind : {LodKind::Full, LodKind::Coarsest}) {
      const std::string what = std::to_string(c.width) + "x" + std::to_string(c.height);
      buildFrame(*layout, cut, lods, kind, rng, frame, scratch);
      if (HasFatalFailure()) return;
      expectWatertight(*layout, frame, what);
      const bool fills = c.width - 1 <= (1 << c.k) && c.height - 1 <= (1 << c.k);  // the interior is the DEM
      if (fills)
        EXPECT_EQ(frame.dikes.triangleCount(), 0u) << what;
      else
        EXPECT_GT(frame.dikes.triangleCount(), 0u) << what;
    }
  }
}

// Nodes without a mesh (e.g. culled) count as their two-triangle quads.
TEST(Dikes, NodesWithoutAMeshJoinTheirQuads) {
  std::mt19937_64 rng(9);
  const Heightfield field = makeField(150, 113, 3);
  auto layout = BlockLayout::create(150, 113, 4);
  ASSERT_TRUE(layout.ok());
  Blocks lods;
  lods.field = &field;
  DikeScratch scratch;
  for (int r = 0; r < 8; ++r) {
    const std::vector<NodeId> cut = makeCut(*layout, r % 2 ? CutKind::Random : CutKind::DeepPaths, rng);
    FrameResult frame;
    frame.meshes.resize(cut.size());
    for (std::size_t i = 0; i < cut.size(); ++i) {
      lods.extract(lods.lod(*layout, cut[i]), LodKind::Mixed, rng, frame.meshes[i]);
      frame.blocks.push_back(DikeBlock{cut[i], rng() % 3 == 0 ? nullptr : &frame.meshes[i]});
    }
    const Status status = buildDikes(*layout, frame.blocks, frame.dikes, scratch);
    ASSERT_TRUE(status.ok()) << status.error().message;
    TriangleSoup soup;
    for (std::size_t i = 0; i < cut.size(); ++i) {
      if (frame.blocks[i].mesh) {
        soup.addBlock(frame.meshes[i]);
        continue;
      }
      const BlockMesh& m = frame.meshes[i];
      const int s = m.footprint.stride, x0 = m.footprint.x0, y0 = m.footprint.y0;
      const GridPoint sw{x0, y0}, se{x0 + m.cellsX * s, y0}, nw{x0, y0 + m.cellsY * s}, ne{se.x, nw.y};
      soup.addTriangle(sw, se, nw);
      soup.addTriangle(ne, nw, se);
    }
    soup.addDikes(frame.dikes);
    const WatertightReport report = checkWatertight(soup, layout->width(), layout->height(), WatertightOptions{300, 1});
    EXPECT_TRUE(report.watertight()) << "cut " << r << ": open " << report.openEdges << ", T-junctions "
                                     << report.tJunctions;
  }
}

// The same cut frame after frame (with new LODs every frame, so sizes change): the output and
// the scratch keep their memory; and the bounds hold for the largest possible frame.
TEST(Dikes, SteadyStateKeepsItsMemory) {
  std::mt19937_64 rng(13);
  const Heightfield field = makeField(300, 260, 4);
  auto layout = BlockLayout::create(300, 260, 4);
  ASSERT_TRUE(layout.ok());
  Blocks lods;
  lods.field = &field;
  const std::vector<NodeId> cut = makeCut(*layout, CutKind::DeepPaths, rng);
  FrameResult frame;
  DikeScratch scratch;
  frame.dikes.reserve(*layout, cut.size());
  scratch.reserve(*layout, cut.size());
  const auto* vertices = frame.dikes.vertices.data();
  const auto* indices = frame.dikes.indices.data();
  const auto* owners = frame.dikes.owners.data();
  const std::size_t capacities[3] = {frame.dikes.vertices.capacity(), frame.dikes.indices.capacity(),
                                     frame.dikes.owners.capacity()};
  const std::size_t scratchBytes = scratch.capacityBytes();
  for (int f = 0; f < 5; ++f) {
    // Every frame a new LOD for every block: sizes change, capacities must not.
    buildFrame(*layout, cut, lods, f == 0 ? LodKind::Full : LodKind::Mixed, rng, frame, scratch);
    if (HasFatalFailure()) return;
    EXPECT_EQ(frame.dikes.vertices.data(), vertices);
    EXPECT_EQ(frame.dikes.indices.data(), indices);
    EXPECT_EQ(frame.dikes.owners.data(), owners);
    EXPECT_EQ(frame.dikes.vertices.capacity(), capacities[0]);
    EXPECT_EQ(frame.dikes.indices.capacity(), capacities[1]);
    EXPECT_EQ(frame.dikes.owners.capacity(), capacities[2]);
    EXPECT_EQ(scratch.capacityBytes(), scratchBytes) << "frame " << f;
  }
  // The bounds hold for the largest frame: every block at full detail on the finest cut.
  const std::vector<NodeId> finest = makeCut(*layout, CutKind::Finest, rng);
  FrameResult full;
  full.dikes.reserve(*layout, finest.size());
  DikeScratch fullScratch;
  fullScratch.reserve(*layout, finest.size());
  const std::size_t fullBytes = fullScratch.capacityBytes();
  const std::size_t fullCapacity = full.dikes.indices.capacity();
  buildFrame(*layout, finest, lods, LodKind::Full, rng, full, fullScratch);
  EXPECT_EQ(fullScratch.capacityBytes(), fullBytes);
  EXPECT_EQ(full.dikes.indices.capacity(), fullCapacity);
  EXPECT_LE(full.dikes.vertices.size(), dikeVertexBound(*layout, finest.size()));
  EXPECT_LE(full.dikes.triangleCount(), dikeTriangleBound(*layout, finest.size()));
}

// Inputs that are not a quadtree cut, or meshes that are not for their node: errors, no asserts.
TEST(Dikes, RejectsWhatIsNotACut) {
  const Heightfield field = makeField(100, 70, 1);
  auto layout = BlockLayout::create(100, 70, 4);
  ASSERT_TRUE(layout.ok());
  std::mt19937_64 rng(3);
  const std::vector<NodeId> cut = makeCut(*layout, CutKind::Random, rng);
  ASSERT_GT(cut.size(), 2u);
  std::vector<DikeBlock> blocks;
  for (const NodeId& n : cut) blocks.push_back(DikeBlock{n, nullptr});
  DikeMesh dikes;
  DikeScratch scratch;
  ASSERT_TRUE(buildDikes(*layout, blocks, dikes, scratch).ok());

  auto fails = [&](std::vector<DikeBlock> b, const char* what) {
    const Status status = buildDikes(*layout, b, dikes, scratch);
    EXPECT_FALSE(status.ok()) << what;
    if (!status.ok()) {
      EXPECT_EQ(status.error().kind, ErrorKind::InvalidArgument) << what;
    }
    EXPECT_EQ(dikes.triangleCount(), 0u) << what;
  };
  fails({}, "no nodes");
  std::vector<DikeBlock> hole(blocks.begin() + 1, blocks.end());
  fails(hole, "a hole");
  std::vector<DikeBlock> overlap = blocks;
  overlap.push_back(DikeBlock{layout->root(), nullptr});
  fails(overlap, "an overlap");
  std::vector<DikeBlock> missing = blocks;
  missing[0].node = NodeId{0, 1000, 0};
  fails(missing, "a node outside the layout");

  // A mesh for another node, and a mesh whose side lists are broken.
  Blocks lods;
  lods.field = &field;
  BlockMesh mesh, other;
  lods.lod(*layout, cut[0]).extractThreshold(-1.0f, mesh, lods.scratch);
  lods.lod(*layout, cut[1]).extractThreshold(-1.0f, other, lods.scratch);
  std::vector<DikeBlock> wrong = blocks;
  wrong[0].mesh = &other;
  fails(wrong, "a mesh for another node");
  BlockMesh unsorted = mesh;
  std::swap(unsorted.edges[int(BlockEdge::East)][1], unsorted.edges[int(BlockEdge::East)][2]);
  wrong[0].mesh = &unsorted;
  fails(wrong, "an unsorted side");
  BlockMesh offSide = mesh;
  offSide.edges[int(BlockEdge::North)][1] = offSide.edges[int(BlockEdge::South)][1];
  wrong[0].mesh = &offSide;
  fails(wrong, "a vertex off its side");
  BlockMesh outOfRange = mesh;
  outOfRange.edges[int(BlockEdge::West)][1] = 1u << 30;
  wrong[0].mesh = &outOfRange;
  fails(wrong, "an index out of range");
  wrong[0].mesh = &mesh;
  ASSERT_TRUE(buildDikes(*layout, wrong, dikes, scratch).ok());

  // A node with no whole cell inside the DEM at its stride: 68 samples, k = 5, the level-1
  // node over blocks 2 and 3 starts at sample 66.
  const Heightfield narrow = makeField(68, 40, 2);
  auto narrowLayout = BlockLayout::create(68, 40, 5);
  ASSERT_TRUE(narrowLayout.ok());
  std::vector<DikeBlock> coarse{{NodeId{1, 0, 0}, nullptr}, {NodeId{1, 1, 0}, nullptr}};
  const Status status = buildDikes(*narrowLayout, coarse, dikes, scratch);
  EXPECT_FALSE(status.ok());
}

// The a-priori bounds: DikeErrorBounds agrees with dikeErrorBound, the region is the node's
// footprint widened one footprint west and south, and a plane gives (almost) 0 for every dike.
TEST(Dikes, BoundsAgreeAndPlanesAreExact) {
  const Heightfield field = makeField(130, 95, 8);
  auto layout = BlockLayout::create(130, 95, 4);
  ASSERT_TRUE(layout.ok());
  auto bounds = DikeErrorBounds::build(field, *layout);
  ASSERT_TRUE(bounds.ok());
  for (int level = 0; level <= layout->rootLevel(); ++level) {
    for (int by = 0; by < layout->nodesY(level); ++by) {
      for (int bx = 0; bx < layout->nodesX(level); ++bx) {
        const NodeId node{std::uint8_t(level), std::uint32_t(bx), std::uint32_t(by)};
        EXPECT_EQ(bounds->bound(node), dikeErrorBound(field, *layout, node));
        const SampleRect f = layout->footprint(node), r = dikeBoundRegion(*layout, node);
        const int reach = layout->pitch() * layout->stride(node);
        EXPECT_EQ(r, (SampleRect{std::max(f.x0 - reach, 0), std::max(f.y0 - reach, 0), f.x1, f.y1}));
      }
    }
  }
  EXPECT_FALSE(DikeErrorBounds::build(makeField(20, 20, 1), *layout).ok());

  Heightfield plane(130, 95, 10.0, 10.0);
  for (int y = 0; y < plane.height; ++y)
    for (int x = 0; x < plane.width; ++x) plane.at(x, y) = float(3 * x - 2 * y);  // exact in float
  std::mt19937_64 rng(1);
  Blocks lods;
  lods.field = &plane;
  DikeScratch scratch;
  FrameResult frame;
  buildFrame(*layout, makeCut(*layout, CutKind::DeepPaths, rng), lods, LodKind::Coarsest, rng, frame, scratch);
  std::vector<float> errors;
  EXPECT_LT(dikeTriangleErrors(plane, frame.dikes, &errors), 1e-9f);  // rounding at edge crossings only
  EXPECT_EQ(errors.size(), frame.dikes.triangleCount());
}

// The sides a dike triangle lies beside, for pins: rounded outwards to the stride, clamped to
// the side, none where the triangle overlaps the interior's rows and columns alike.
TEST(Dikes, SidesBesideADikeTriangle) {
  BlockMesh mesh;
  mesh.footprint = BlockFootprint{66, 132, 5, 2};  // interior [66, 130] x [132, 196] at stride 2
  mesh.cellsX = 32;
  mesh.cellsY = 32;
  SideRange sides[2];
  ASSERT_EQ(sidesBesideDikeTriangle(mesh, SampleRect{130, 139, 132, 144}, sides), 1);  // east gap, rows 139..144
  EXPECT_EQ(sides[0].side, BlockEdge::East);
  EXPECT_EQ(sides[0].from, 3);
  EXPECT_EQ(sides[0].to, 6);
  ASSERT_EQ(sidesBesideDikeTriangle(mesh, SampleRect{64, 100, 66, 140}, sides), 1);  // west, reaching south of it
  EXPECT_EQ(sides[0].side, BlockEdge::West);
  EXPECT_EQ(sides[0].from, 0);
  EXPECT_EQ(sides[0].to, 4);
  ASSERT_EQ(sidesBesideDikeTriangle(mesh, SampleRect{130, 196, 133, 198}, sides), 2);  // the north-east corner
  EXPECT_EQ(sides[0].side, BlockEdge::East);
  EXPECT_EQ(sides[0].from, 32);
  EXPECT_EQ(sides[0].to, 32);
  EXPECT_EQ(sides[1].side, BlockEdge::North);
  EXPECT_EQ(sides[1].from, 32);
  EXPECT_EQ(sides[1].to, 32);
  ASSERT_EQ(sidesBesideDikeTriangle(mesh, SampleRect{125, 196, 133, 198}, sides), 1);  // north, past the corner
  EXPECT_EQ(sides[0].side, BlockEdge::North);
  EXPECT_EQ(sides[0].from, 29);
  EXPECT_EQ(sides[0].to, 32);
  EXPECT_EQ(sidesBesideDikeTriangle(mesh, SampleRect{100, 150, 101, 151}, sides), 0);  // inside: beside nothing
}

// The samples-only error: every sample in the closed triangle (found here by orientation
// tests), never above the exact error, which also looks between the samples.
TEST(Dikes, SampleErrorScansTheSamplesOnly) {
  const Heightfield field = makeField(60, 50, 21);
  std::mt19937_64 rng(8);
  std::uniform_int_distribution<int> px(0, 59), py(0, 49);
  int strictlyBelow = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const DikeVertex a{px(rng), py(rng)}, b{px(rng), py(rng)}, c{px(rng), py(rng)};
    const std::int64_t area = std::int64_t(b.x - a.x) * (c.y - a.y) - std::int64_t(b.y - a.y) * (c.x - a.x);
    if (area == 0) continue;
    const double gx = ((field.at(b.x, b.y) - double(field.at(a.x, a.y))) * (c.y - a.y) -
                       (field.at(c.x, c.y) - double(field.at(a.x, a.y))) * (b.y - a.y)) /
                      double(area);
    const double gy = ((b.x - a.x) * (field.at(c.x, c.y) - double(field.at(a.x, a.y))) -
                       (c.x - a.x) * (field.at(b.x, b.y) - double(field.at(a.x, a.y)))) /
                      double(area);
    double expected = 0.0;
    for (int y = 0; y < field.height; ++y)
      for (int x = 0; x < field.width; ++x) {
        auto side = [&](DikeVertex p, DikeVertex q) {
          return (std::int64_t(q.x - p.x) * (y - p.y) - std::int64_t(q.y - p.y) * (x - p.x)) * (area > 0 ? 1 : -1);
        };
        if (side(a, b) < 0 || side(b, c) < 0 || side(c, a) < 0) continue;
        const double plane = field.at(a.x, a.y) + gx * (x - a.x) + gy * (y - a.y);
        expected = std::max(expected, std::abs(double(field.at(x, y)) - plane));
      }
    const float samples = triangleSampleError(field, a, b, c), exact = dikeTriangleError(field, a, b, c);
    EXPECT_NEAR(samples, expected, 1e-4 * (1.0 + expected)) << trial;
    EXPECT_LE(samples, exact) << trial;
    strictlyBelow += samples < exact;
  }
  EXPECT_GT(strictlyBelow, 10) << "the surface between samples matters";
}

}  // namespace
}  // namespace polder::terrain
