// Speed of the region/allocator core: ASLOD's budget split (Schmalstieg and Fuhrmann 1999,
// section 3) over 10,000 regions, target under 0.5 ms per allocation, and the projected area
// of 10,000 boxes (Schmalstieg & Tobler, JGT 1999). A standalone Google Benchmark program
// with its own main; it also counts heap allocations inside the timed loops (expected 0).
#include <polder/lod/allocator.hpp>
#include <polder/lod/projected_area.hpp>

#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <new>
#include <random>
#include <vector>

#include <benchmark/benchmark.h>
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace {
std::atomic<std::uint64_t> g_allocations{0};  // benchmark instrumentation only
}  // namespace

// Counting replacements of the global allocation functions (noinline: GCC otherwise pairs
// the inlined free() with the builtin operator new and warns of a mismatch).
[[gnu::noinline]] void* operator new(std::size_t size) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
[[gnu::noinline]] void operator delete(void* p) noexcept { std::free(p); }
[[gnu::noinline]] void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace {

using namespace polder;
using namespace polder::lod;

constexpr int kRegions = 10'000;

// A flight-sim view over a 100 x 100 grid of 32 m terrain blocks (one block per region),
// camera 150 m up near the middle, looking north-east and down.
Camera terrainCamera() {
  Camera camera;
  camera.position = {1650.0, 1500.0, 150.0};
  camera.yawDeg = 40.0;
  camera.pitchDeg = -20.0;
  camera.fovYDeg = 60.0;
  camera.widthPx = 1920;
  camera.heightPx = 1080;
  camera.nearM = 1.0;
  return camera;
}

std::vector<OrientedBox> terrainBlocks() {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<OrientedBox> boxes;
  boxes.reserve(kRegions);
  for (int row = 0; row < 100; ++row) {
    for (int col = 0; col < 100; ++col) {
      const double low = 60.0 * unit(rng), high = low + 5.0 + 80.0 * unit(rng);
      boxes.push_back(orientedBoxFromAabb({col * 32.0, row * 32.0, low}, {col * 32.0 + 32.0, row * 32.0 + 32.0, high}));
    }
  }
  return boxes;
}

std::vector<OrientedBox> randomBoxes() {
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> normal;
  std::vector<OrientedBox> boxes(kRegions);
  for (OrientedBox& box : boxes) {
    box.centre = {4000.0 * unit(rng) - 2000.0, 4000.0 * unit(rng) - 2000.0, 400.0 * unit(rng) - 200.0};
    box.axes = glm::mat3_cast(glm::normalize(glm::dquat(normal(rng), normal(rng), normal(rng), normal(rng))));
    box.halfExtents = {1.0 + 50.0 * unit(rng), 1.0 + 50.0 * unit(rng), 1.0 + 20.0 * unit(rng)};
  }
  return boxes;
}

// Block weights as the terrain would pass them: visible area, 2..2048 triangles per block.
std::vector<RegionDemand> terrainDemands() {
  const AreaView view = makeAreaView(terrainCamera());
  std::vector<RegionDemand> demands;
  for (const OrientedBox& box : terrainBlocks()) demands.push_back({visibleAreaPx(box, view), 2, 2048});
  return demands;
}

std::vector<RegionDemand> lognormalDemands() {
  std::mt19937_64 rng(29);
  std::lognormal_distribution<double> spread(0.0, 2.0);
  std::vector<RegionDemand> demands(kRegions);
  for (RegionDemand& demand : demands) demand = {spread(rng), 128, 2048};
  return demands;
}

// Weights 1.05^i: a plain clamp-and-redistribute loop caps about one region per pass here.
std::vector<RegionDemand> geometricDemands() {
  std::vector<RegionDemand> demands(kRegions);
  for (int i = 0; i < kRegions; ++i) demands[i] = {std::pow(1.05, double(i)), 0, 1000};
  return demands;
}

void runAllocation(benchmark::State& state, const std::vector<RegionDemand>& demands, double alpha) {
  const std::uint64_t budget = std::uint64_t(state.range(0));
  std::vector<std::uint32_t> counts(demands.size());
  AllocationScratch scratch(demands.size());
  bool feasible = true;
  const std::uint64_t allocationsBefore = g_allocations.load();
  for (auto _ : state) {
    const AllocationResult result = allocateTriangles(demands, budget, alpha, counts, scratch);
    feasible = feasible && result.feasible;
    benchmark::DoNotOptimize(counts.data());
  }
  state.counters["heapAllocs"] = double(g_allocations.load() - allocationsBefore);
  state.counters["feasible"] = feasible ? 1.0 : 0.0;
  state.counters["regions"] = double(demands.size());
}

void BM_AllocateTerrainAlpha3(benchmark::State& state) { runAllocation(state, terrainDemands(), 3.0); }
void BM_AllocateTerrainAlpha1(benchmark::State& state) { runAllocation(state, terrainDemands(), 1.0); }
void BM_AllocateTerrainAlpha2_5(benchmark::State& state) { runAllocation(state, terrainDemands(), 2.5); }
void BM_AllocateLognormalAlpha3(benchmark::State& state) { runAllocation(state, lognormalDemands(), 3.0); }
void BM_AllocateLognormalAlpha0_5(benchmark::State& state) { runAllocation(state, lognormalDemands(), 0.5); }
void BM_AllocateGeometricAlpha1(benchmark::State& state) { runAllocation(state, geometricDemands(), 1.0); }

BENCHMARK(BM_AllocateTerrainAlpha3)->Arg(200'000)->Arg(1'000'000)->Arg(5'000'000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_AllocateTerrainAlpha1)->Arg(1'000'000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_AllocateTerrainAlpha2_5)->Arg(1'000'000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_AllocateLognormalAlpha3)->Arg(5'000'000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_AllocateLognormalAlpha0_5)->Arg(5'000'000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_AllocateGeometricAlpha1)->Arg(1'000'000)->Arg(5'000'000)->Unit(benchmark::kMicrosecond);

template <double (*kArea)(const OrientedBox&, const AreaView&)>
void runArea(benchmark::State& state, const std::vector<OrientedBox>& boxes) {
  const AreaView view = makeAreaView(terrainCamera());
  std::uint64_t allocationsBefore = g_allocations.load();
  for (auto _ : state) {
    double total = 0.0;
    for (const OrientedBox& box : boxes) total += kArea(box, view);
    benchmark::DoNotOptimize(total);
  }
  state.counters["heapAllocs"] = double(g_allocations.load() - allocationsBefore);
  state.counters["boxesPerSec"] =
      benchmark::Counter(double(boxes.size()) * double(state.iterations()), benchmark::Counter::kIsRate);
}

void BM_ProjectedAreaTerrainBlocks(benchmark::State& state) { runArea<projectedAreaPx>(state, terrainBlocks()); }
void BM_VisibleAreaTerrainBlocks(benchmark::State& state) { runArea<visibleAreaPx>(state, terrainBlocks()); }
void BM_ProjectedAreaRandomBoxes(benchmark::State& state) { runArea<projectedAreaPx>(state, randomBoxes()); }

BENCHMARK(BM_ProjectedAreaTerrainBlocks)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_VisibleAreaTerrainBlocks)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ProjectedAreaRandomBoxes)->Unit(benchmark::kMicrosecond);

// The Camera overload rebuilds the view (trigonometry) per box: the cost AreaView saves.
void BM_ProjectedAreaCameraOverload(benchmark::State& state) {
  const std::vector<OrientedBox> boxes = terrainBlocks();
  const Camera camera = terrainCamera();
  for (auto _ : state) {
    double total = 0.0;
    for (const OrientedBox& box : boxes) total += projectedAreaPx(box, camera);
    benchmark::DoNotOptimize(total);
  }
}
BENCHMARK(BM_ProjectedAreaCameraOverload)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
