// Query scene speed on a 2049 x 2049 synthetic field (30 m spacing): scene build time, and
// rays per second (items_per_second) for single rays and the 16-wide batch path, on one and
// two threads, with and without the double-precision hit refinement; scattered random rays
// (cache-bound: every ray walks a different part of a 120 MB BVH) and camera rays in pixel
// order (the reference renderer's and the error measurement's case).
#include <polder/query/query_scene.hpp>
#include <polder/query/reference_renderer.hpp>

#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <vector>

#include <benchmark/benchmark.h>

namespace polder::query {
namespace {

constexpr int kSize = 2049;
constexpr double kSpacing = 30.0;
constexpr std::size_t kRaysPerIteration = 4096;

terrain::Heightfield makeField() {
  // Ridges and valleys at several wavelengths: 0-1600 m relief, slopes up to about 1.
  terrain::Heightfield field(kSize, kSize, kSpacing, kSpacing);
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      const double u = x * kSpacing, v = y * kSpacing;
      field.at(x, y) = float(800.0 + 500.0 * std::sin(u * 1.3e-4) * std::cos(v * 1.1e-4) +
                             200.0 * std::sin(u * 7.1e-4 + v * 3.3e-4) + 60.0 * std::cos(u * 3.7e-3 - v * 2.9e-3) +
                             15.0 * std::sin(u * 1.9e-2) * std::sin(v * 2.3e-2));
    }
  }
  return field;
}

const terrain::Heightfield& field() {
  static const terrain::Heightfield instance = makeField();
  return instance;
}

std::unique_ptr<QueryScene> buildScene(bool refine, bool robust) {
  QueryOptions options;
  options.refineHits = refine;
  options.robust = robust;
  auto scene = QueryScene::create(field(), options);
  if (!scene.ok()) {
    std::fprintf(stderr, "query_bench: %s\n", scene.error().message.c_str());
    std::abort();
  }
  return std::move(scene).value();
}

// Scenes by (refine, robust), built once and shared by every benchmark thread.
const QueryScene& scene(bool refine, bool robust) {
  static const std::unique_ptr<QueryScene> scenes[2][2] = {{buildScene(false, false), buildScene(false, true)},
                                                           {buildScene(true, false), buildScene(true, true)}};
  return *scenes[refine][robust];
}

// Random downward-ish rays from 500 m above the highest point, anywhere over the field.
std::vector<QueryRay> makeRays(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> position(0.0, (kSize - 1) * kSpacing), slant(-0.7, 0.7);
  std::vector<QueryRay> rays(kRaysPerIteration);
  for (QueryRay& ray : rays) {
    ray.origin = glm::dvec3(position(rng), position(rng), 2100.0);
    ray.direction = glm::normalize(glm::dvec3(slant(rng), slant(rng), -1.0));
  }
  return rays;
}

void BM_SceneBuild(benchmark::State& state) {
  const terrain::Heightfield& heights = field();
  std::size_t bytes = 0;
  for (auto _ : state) {
    auto built = QueryScene::create(heights);
    benchmark::DoNotOptimize(built.ok());
    bytes = (*built)->memoryBytes();
  }
  state.counters["MB"] = double(bytes) / 1e6;
}
BENCHMARK(BM_SceneBuild)->Unit(benchmark::kMillisecond)->Iterations(3)->UseRealTime();

// Arguments: refine (0/1), robust (0/1).
void BM_RaycastSingle(benchmark::State& state) {
  const QueryScene& target = scene(state.range(0) != 0, state.range(1) != 0);
  const std::vector<QueryRay> rays = makeRays(unsigned(state.thread_index()) + 1);
  std::size_t hits = 0;
  for (auto _ : state) {
    for (const QueryRay& ray : rays) hits += target.raycast(ray).has_value();
  }
  benchmark::DoNotOptimize(hits);
  state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(rays.size()));
}
BENCHMARK(BM_RaycastSingle)->ArgsProduct({{0, 1}, {1}})->Args({1, 0})->ThreadRange(1, 2)->UseRealTime();

void BM_RaycastBatch(benchmark::State& state) {
  const QueryScene& target = scene(state.range(0) != 0, state.range(1) != 0);
  const std::vector<QueryRay> rays = makeRays(unsigned(state.thread_index()) + 1);
  std::vector<std::optional<RayHit>> hits(rays.size());
  for (auto _ : state) {
    target.raycastMany(rays, hits);
    benchmark::DoNotOptimize(hits.data());
  }
  state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(rays.size()));
}
BENCHMARK(BM_RaycastBatch)->ArgsProduct({{0, 1}, {1}})->Args({1, 0})->ThreadRange(1, 2)->UseRealTime();

// Camera rays over the field, in pixel order: a 1280 x 720 view, each thread a 1280 x 32 strip.
std::vector<QueryRay> makeCameraRays(int strip) {
  Camera camera;
  camera.position = glm::dvec3(30000.0, 5000.0, 2500.0);
  camera.yawDeg = 10.0;
  camera.pitchDeg = -20.0;
  camera.widthPx = 1280;
  camera.heightPx = 720;
  std::vector<QueryRay> rays;
  for (int y = 400 + 32 * strip; y < 432 + 32 * strip; ++y) {
    for (int x = 0; x < camera.widthPx; ++x)
      rays.push_back(QueryRay{camera.position, camera.pixelRay(x + 0.5, y + 0.5)});
  }
  return rays;
}

void BM_CameraRaysSingle(benchmark::State& state) {
  const QueryScene& target = scene(true, true);
  const std::vector<QueryRay> rays = makeCameraRays(state.thread_index());
  std::size_t hits = 0;
  for (auto _ : state) {
    for (const QueryRay& ray : rays) hits += target.raycast(ray).has_value();
  }
  benchmark::DoNotOptimize(hits);
  state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(rays.size()));
}
BENCHMARK(BM_CameraRaysSingle)->ThreadRange(1, 2)->UseRealTime();

// Argument: coherence hint (0 incoherent, 1 coherent).
void BM_CameraRaysBatch(benchmark::State& state) {
  const QueryScene& target = scene(true, true);
  const std::vector<QueryRay> rays = makeCameraRays(state.thread_index());
  std::vector<std::optional<RayHit>> hits(rays.size());
  const RayCoherence coherence = state.range(0) ? RayCoherence::Coherent : RayCoherence::Incoherent;
  for (auto _ : state) {
    target.raycastMany(rays, hits, coherence);
    benchmark::DoNotOptimize(hits.data());
  }
  state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(rays.size()));
}
BENCHMARK(BM_CameraRaysBatch)->Arg(0)->Arg(1)->ThreadRange(1, 2)->UseRealTime();

// A 640 x 360 reference frame on the renderer's own 1 or 2 threads.
void BM_RenderReference(benchmark::State& state) {
  const QueryScene& target = scene(true, true);
  Camera camera;
  camera.position = glm::dvec3(30000.0, 5000.0, 2500.0);
  camera.yawDeg = 10.0;
  camera.pitchDeg = -20.0;
  camera.widthPx = 640;
  camera.heightPx = 360;
  TerrainStyle style;
  style.maxHeightM = 1600.0f;
  for (auto _ : state) {
    RgbaImage image = renderReference(target, field(), camera, style, int(state.range(0)));
    benchmark::DoNotOptimize(image.pixels.data());
  }
  state.SetItemsProcessed(std::int64_t(state.iterations()) * 640 * 360);
}
BENCHMARK(BM_RenderReference)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_LineOfSight(benchmark::State& state) {
  const QueryScene& target = scene(true, true);
  const std::vector<QueryRay> rays = makeRays(unsigned(state.thread_index()) + 7);
  std::size_t visible = 0;
  for (auto _ : state) {
    for (const QueryRay& ray : rays) visible += target.lineOfSight(ray.origin, ray.origin + 3000.0 * ray.direction);
  }
  benchmark::DoNotOptimize(visible);
  state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(rays.size()));
}
BENCHMARK(BM_LineOfSight)->ThreadRange(1, 2)->UseRealTime();

void BM_Height(benchmark::State& state) {
  const QueryScene& target = scene(true, true);
  const std::vector<QueryRay> points = makeRays(unsigned(state.thread_index()) + 13);
  double sum = 0.0;
  for (auto _ : state) {
    for (const QueryRay& p : points) sum += target.height(p.origin.x, p.origin.y).value_or(0.0);
  }
  benchmark::DoNotOptimize(sum);
  state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(points.size()));
}
BENCHMARK(BM_Height)->UseRealTime();

}  // namespace
}  // namespace polder::query

BENCHMARK_MAIN();
