// Progressive-mesh simplification quality and speed on the shared models, against
// meshoptimizer's meshopt_simplify as the reference (meshoptimizer is used here only).
//
//   simplify_bench [DATA_DIR] [--json PATH] [--samples N] [--runs N] [--trips N]
//                  [--only quality,colour,speed,moves,scale] [--benchmark_...]
//
// DATA_DIR defaults to POLDER_SHARED_DATA_DIR (the folder holding meshes/). Tables:
//   1. Quality: Hausdorff and RMS distance (measureSurfaceDeviation, relative to the
//      bounding-box diagonal) at 50%, 10% and 1% of the input triangles, for `collapse`
//      (geometry only, and with its default attribute weights) and `cluster`, each against
//      meshopt_simplify at the same triangle count (where meshopt stops above the target,
//      ours is extracted at meshopt's count). Target: collapse / meshopt <= 1.25, checked on
//      the geometry-only rows (meshopt sees positions only; the default rows trade distance
//      for attributes and are shown for information).
//   2. Colour: colourRms at 10% on spot (texture baked to vertex colours) and on the bunny
//      painted by region, attribute-aware vs colourWeight = 0. Target: aware / blind <= 0.5.
//      The same ratio at 5% to 50% follows, for information.
//   3. Speed: build time of the whole sequence (steps + assemble), median of --runs runs,
//      as M input triangles per second (target >= 1), plus meshopt_simplify to the same
//      base count; bunny to 500 triangles (target < 0.1 s).
//   4. Level moves (the paper's Table 2): base mesh -> full mesh -> base mesh round trips,
//      median over --trips, with the level count and the triangles changed per level.
//   5. Speed at terrain scale: the Mt Rainier DEM as one mesh (the scene files' Silvretta
//      model), cropped to 261 x 261 samples (135,200 triangles) and 725 x 725 (1,048,352),
//      timed as in 3 over at most 3 runs (target >= 1 M input triangles/s).
// Arguments starting with --benchmark go to Google Benchmark, which then also runs its
// registered timings (sequence builds and round trips).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <unordered_set>
#include <utility>
#include <vector>

#include <benchmark/benchmark.h>
#include <meshoptimizer.h>
#include <nlohmann/json.hpp>

#include <polder/mesh/cluster_builder.hpp>
#include <polder/mesh/collapse_builder.hpp>
#include <polder/mesh/level_selection.hpp>
#include <polder/mesh/mesh_extraction.hpp>
#include <polder/mesh/progressive_mesh.hpp>
#include <polder/mesh/progressive_mesh_build.hpp>
#include <polder/mesh/progressive_mesh_instance.hpp>
#include <polder/mesh/region_partition.hpp>
#include <polder/mesh_io/mesh_file.hpp>
#include <polder/query/surface_deviation.hpp>
#include <polder/scene/heightfield_mesh.hpp>
#include <polder/terrain/dem_reader.hpp>
#include <polder/terrain/heightfield_crop.hpp>

#ifndef POLDER_SHARED_DATA_DIR
#define POLDER_SHARED_DATA_DIR ""
#endif

namespace {

using polder::mesh::TriangleMesh;
using Clock = std::chrono::steady_clock;

constexpr double kCollapseQualityTarget = 1.25;
constexpr double kColourTarget = 0.5;
constexpr double kSpeedTarget = 1.0;  // M input triangles per second
constexpr double kBunny500Seconds = 0.1;

[[noreturn]] void fail(const std::string& message) {
  std::fprintf(stderr, "simplify_bench: %s\n", message.c_str());
  std::exit(1);
}

template <class T>
T check(polder::Result<T> result, const std::string& what) {
  if (!result.ok()) fail(what + ": " + result.error().message);
  return std::move(result).value();
}

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

double median(std::vector<double> values) {
  if (values.empty()) return std::nan("");
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

// ---------------------------------------------------------------------------------------
// Models and builders

struct Model {
  std::string name;
  std::string file;
  std::string texture;  // baked into colours; empty: none
  TriangleMesh mesh;
  bool keepUvSeams = false;  // vertices stay split where texture coordinates differ
};

enum class Builder { CollapseGeometry, CollapseDefault, CollapseColourBlind, ClusterDefault, ClusterColourBlind };

const char* builderName(Builder b) {
  switch (b) {
    case Builder::CollapseGeometry:
      return "collapse (geometry)";
    case Builder::CollapseDefault:
      return "collapse (default)";
    case Builder::CollapseColourBlind:
      return "collapse (colourW=0)";
    case Builder::ClusterDefault:
      return "cluster (default)";
    case Builder::ClusterColourBlind:
      return "cluster (colourW=0)";
  }
  return "?";
}

const char* builderKey(Builder b) {
  switch (b) {
    case Builder::CollapseGeometry:
      return "collapse_geometry";
    case Builder::CollapseDefault:
      return "collapse_default";
    case Builder::CollapseColourBlind:
      return "collapse_colour_blind";
    case Builder::ClusterDefault:
      return "cluster_default";
    case Builder::ClusterColourBlind:
      return "cluster_colour_blind";
  }
  return "?";
}

bool isCollapse(Builder b) {
  return b == Builder::CollapseGeometry || b == Builder::CollapseDefault || b == Builder::CollapseColourBlind;
}

polder::mesh::CollapseOptions collapseOptions(Builder b, std::uint32_t stopAt) {
  polder::mesh::CollapseOptions options;
  if (b == Builder::CollapseGeometry) options.colourWeight = options.uvWeight = options.normalWeight = 0.0;
  if (b == Builder::CollapseColourBlind) options.colourWeight = 0.0;
  options.stopAtTriangles = stopAt;
  return options;
}

polder::mesh::ClusterOptions clusterOptions(Builder b, std::uint32_t stopAt) {
  polder::mesh::ClusterOptions options;
  if (b == Builder::ClusterColourBlind) options.colourWeight = 0.0;
  options.stopAtTriangles = stopAt;
  return options;
}

// The builder's steps alone.
polder::Result<polder::mesh::SimplificationSteps> buildSteps(const TriangleMesh& mesh, Builder b,
                                                             std::uint32_t stopAt = 0) {
  const polder::mesh::RegionPartition partition = polder::mesh::singleRegion();
  if (isCollapse(b)) return polder::mesh::buildCollapseSteps(mesh, partition, collapseOptions(b, stopAt));
  return polder::mesh::buildClusterSteps(mesh, partition, clusterOptions(b, stopAt));
}

// The whole sequence, as the library builds it in one call (the steps assembled on a
// second thread as they come); its time in `seconds` when given.
std::unique_ptr<polder::mesh::ProgressiveMesh> buildSequence(const Model& model, Builder b, std::uint32_t stopAt = 0,
                                                             double* seconds = nullptr) {
  const polder::mesh::RegionPartition partition = polder::mesh::singleRegion();
  const auto start = Clock::now();
  auto pm = isCollapse(b) ? polder::mesh::buildProgressiveMesh(model.mesh, partition, collapseOptions(b, stopAt))
                          : polder::mesh::buildProgressiveMesh(model.mesh, partition, clusterOptions(b, stopAt));
  if (seconds) *seconds = secondsSince(start);
  return std::make_unique<polder::mesh::ProgressiveMesh>(check(std::move(pm), model.name + " " + builderName(b)));
}

// The finest level of the sequence with at most `triangles` triangles, as a standalone mesh.
TriangleMesh extractAt(const polder::mesh::ProgressiveMesh& pm, std::uint64_t triangles) {
  polder::mesh::ProgressiveMeshInstance instance(pm);
  std::vector<std::uint32_t> levels(pm.regionCount());
  polder::mesh::levelsForTriangleBudget(pm, triangles, levels);
  for (std::uint32_t r = 0; r < pm.regionCount(); ++r) instance.setLevel(r, levels[r]);
  instance.resolveBorders();
  return polder::mesh::extractMesh(instance);
}

std::uint32_t baseTriangles(const polder::mesh::ProgressiveMesh& pm) {
  std::uint32_t total = 0;
  for (std::uint32_t r = 0; r < pm.regionCount(); ++r) total += pm.region(r).trianglesAt(0);
  return total;
}

// ---------------------------------------------------------------------------------------
// meshoptimizer reference

struct MeshoptResult {
  TriangleMesh mesh;  // the welded input's positions (and colours), the simplified indices
  float resultError = 0.0f;
  double seconds = 0.0;
};

MeshoptResult meshoptSimplify(const TriangleMesh& mesh, std::size_t targetTriangles) {
  MeshoptResult result;
  result.mesh.positions = mesh.positions;
  result.mesh.colours = mesh.colours;  // meshopt keeps input vertices: their colours apply as they are
  result.mesh.indices.resize(mesh.indices.size());
  const auto start = Clock::now();
  const std::size_t count =
      meshopt_simplify(result.mesh.indices.data(), mesh.indices.data(), mesh.indices.size(), &mesh.positions[0].x,
                       mesh.positions.size(), sizeof(glm::vec3), 3 * targetTriangles, 1.0f, 0, &result.resultError);
  result.seconds = secondsSince(start);
  result.mesh.indices.resize(count);
  return result;
}

// ---------------------------------------------------------------------------------------
// Deviation

polder::query::SurfaceDeviationOptions g_deviationOptions;

polder::query::SurfaceDeviation deviation(const Model& model, const TriangleMesh& simplified, const std::string& what) {
  if (simplified.triangleCount() == 0) fail(model.name + " " + what + ": no triangles left");
  return check(polder::query::measureSurfaceDeviation(model.mesh, simplified, g_deviationOptions),
               model.name + " " + what + " deviation");
}

void rule(int width) {
  for (int i = 0; i < width; ++i) std::putchar('-');
  std::putchar('\n');
}

// ---------------------------------------------------------------------------------------
// Google Benchmark registrations (run only when a --benchmark flag is given)

void registerGoogleBenchmarks(const std::vector<Model>& models) {
  for (const Model& model : models) {
    for (Builder b : {Builder::CollapseDefault, Builder::ClusterDefault}) {
      benchmark::RegisterBenchmark(("BM_BuildSequence/" + model.name + "/" + builderKey(b)).c_str(),
                                   [&model, b](benchmark::State& state) {
                                     for (auto _ : state) {
                                       auto pm = buildSequence(model, b);
                                       benchmark::DoNotOptimize(pm.get());
                                     }
                                     state.SetItemsProcessed(state.iterations() * model.mesh.triangleCount());
                                   })
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
      benchmark::RegisterBenchmark(("BM_RoundTrip/" + model.name + "/" + builderKey(b)).c_str(),
                                   [&model, b](benchmark::State& state) {
                                     auto pm = buildSequence(model, b);
                                     polder::mesh::ProgressiveMeshInstance instance(*pm);
                                     const std::uint32_t levels = pm->region(0).levelCount();
                                     instance.setLevel(0, 0);
                                     for (auto _ : state) {
                                       instance.setLevel(0, levels);
                                       instance.setLevel(0, 0);
                                       benchmark::DoNotOptimize(instance.indices(0).data());
                                     }
                                     state.counters["levels"] = levels;
                                   })
          ->Unit(benchmark::kMicrosecond)
          ->UseRealTime();
    }
    benchmark::RegisterBenchmark(("BM_Meshopt/" + model.name + "/10pct").c_str(),
                                 [&model](benchmark::State& state) {
                                   for (auto _ : state) {
                                     auto r = meshoptSimplify(model.mesh, model.mesh.triangleCount() / 10);
                                     benchmark::DoNotOptimize(r.mesh.indices.data());
                                   }
                                   state.SetItemsProcessed(state.iterations() * model.mesh.triangleCount());
                                 })
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::string dataDir = POLDER_SHARED_DATA_DIR;
  std::string jsonPath;
  int runs = 5;
  int trips = 200;
  std::size_t samples = 200000;
  std::string only = "quality,colour,speed,moves,scale";
  std::vector<char*> benchmarkArgs{argv[0]};
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) fail(arg + " needs a value");
      return argv[++i];
    };
    if (arg == "--json")
      jsonPath = next();
    else if (arg == "--runs")
      runs = std::max(1, std::atoi(next().c_str()));
    else if (arg == "--trips")
      trips = std::max(1, std::atoi(next().c_str()));
    else if (arg == "--only")
      only = next();
    else if (arg == "--samples")
      samples = std::max<long long>(1000, std::atoll(next().c_str()));
    else if (arg.rfind("--benchmark", 0) == 0)
      benchmarkArgs.push_back(argv[i]);
    else if (arg == "-h" || arg == "--help") {
      std::printf(
          "usage: %s [DATA_DIR] [--json PATH] [--samples N] [--runs N] [--trips N]\n"
          "       [--only quality,colour,speed,moves,scale] [--benchmark_...]\n",
          argv[0]);
      return 0;
    } else if (!arg.empty() && arg[0] != '-')
      dataDir = arg;
    else
      fail("unknown argument " + arg);
  }
  if (dataDir.empty() || !std::filesystem::is_directory(std::filesystem::path(dataDir) / "meshes"))
    fail("no meshes/ folder under '" + dataDir + "' (give the shared data folder as the first argument)");
  auto section = [&only](const char* name) { return only.find(name) != std::string::npos; };
  g_deviationOptions.samplesPerSurface = samples;
  g_deviationOptions.seed = 1;

  const std::filesystem::path meshes = std::filesystem::path(dataDir) / "meshes";
  std::vector<Model> models = {
      {"bunny", "stanford_bunny_bun_zipper.ply", "", {}},
      {"cow", "cow.obj", "", {}},
      {"fandisk", "fandisk.obj", "", {}},
      {"spot", "spot_triangulated.obj", "spot_texture.png", {}},
      // Textured as `polder simplify` reads it: split along its UV seams, which both
      // builders move in pairs.
      {"spot-uv", "spot_triangulated.obj", "", {}, true},
  };
  nlohmann::json report;
  report["data_dir"] = dataDir;
  report["samples_per_surface"] = samples;
  report["runs"] = runs;
  report["round_trips"] = trips;
  std::printf("simplify_bench: data %s, %zu samples per surface (seed 1), median of %d builds, %d round trips\n\n",
              dataDir.c_str(), samples, runs, trips);
  std::printf("%-8s %-32s %9s %9s  %s\n", "model", "file", "vertices", "triangles", "attributes");
  for (Model& model : models) {
    polder::mesh_io::MeshReadOptions options;
    if (!model.texture.empty()) options.bakeTexture = meshes / model.texture;
    options.keepUvSeams = model.keepUvSeams;
    model.mesh = check(polder::mesh_io::readMesh(meshes / model.file, options), model.file);
    std::printf("%-8s %-32s %9zu %9zu  %s%s%s%s\n", model.name.c_str(), model.file.c_str(), model.mesh.vertexCount(),
                model.mesh.triangleCount(), model.mesh.hasNormals() ? "normals " : "",
                model.mesh.hasColours() ? (model.texture.empty() ? "colours " : "colours(baked) ") : "",
                model.mesh.hasUvs() ? "uvs " : "", "");
    report["models"].push_back({{"name", model.name},
                                {"file", model.file},
                                {"texture", model.texture},
                                {"vertices", model.mesh.vertexCount()},
                                {"triangles", model.mesh.triangleCount()}});
  }

  // "A mesh painted by region": the bunny with 8 automatic regions in 8 distinct colours,
  // real colour borders on a real surface (the colour table's second model).
  for (const Model& model : std::vector<Model>(models)) {
    if (model.name != "bunny") continue;
    Model painted = model;
    painted.name = "bunny-painted";
    const auto regions = polder::mesh::automaticPartition(painted.mesh.positions, 8);
    painted.mesh.colours.clear();
    for (std::uint32_t v = 0; v < painted.mesh.vertexCount(); ++v) {
      const std::uint32_t r = regions.regionOf(v);
      painted.mesh.colours.emplace_back(float((r * 5 + 1) % 8) / 7.0f, float((r * 3 + 2) % 8) / 7.0f,
                                        float((r * 7 + 3) % 8) / 7.0f, 1.0f);
    }
    std::printf("%-8s painted by %u automatic regions\n", painted.name.c_str(), regions.regionCount);
    models.push_back(std::move(painted));
  }

  // Sequences used by tables 1, 2 and 4, built once.
  std::map<std::pair<std::string, Builder>, std::unique_ptr<polder::mesh::ProgressiveMesh>> sequences;
  auto sequence = [&](const Model& model, Builder b) -> const polder::mesh::ProgressiveMesh& {
    auto& slot = sequences[{model.name, b}];
    if (!slot) slot = buildSequence(model, b);
    return *slot;
  };

  int qualityMisses = 0, colourMisses = 0, speedMisses = 0;

  // ---------------------------------------------------------------- 1. quality
  if (section("quality")) {
    const Builder qualityBuilders[] = {Builder::CollapseGeometry, Builder::CollapseDefault, Builder::ClusterDefault};
    const double fractions[] = {0.5, 0.1, 0.01};
    std::printf(
        "\n1. Quality vs meshopt_simplify (target_error 1.0, options 0): distances relative to the bbox diagonal;\n"
        "   ratio = ours / meshopt at equal triangles (target: collapse <= %.2f for Hausdorff and RMS)\n",
        kCollapseQualityTarget);
    const int width1 = 150;
    rule(width1);
    std::printf("%-8s %4s %7s | %-20s %7s %10s %10s | %7s %10s %10s %9s | %7s %7s %s\n", "model", "pct", "target",
                "builder", "ours_t", "hausdorff", "rms", "mopt_t", "hausdorff", "rms", "mopt_err", "H ratio", "RMS rat",
                "check");
    rule(width1);
    for (const Model& model : models) {
      // meshopt results (and their deviations) by requested triangle count.
      std::map<std::size_t, std::pair<MeshoptResult, polder::query::SurfaceDeviation>> meshoptCache;
      auto meshoptAt = [&](std::size_t target) -> const std::pair<MeshoptResult, polder::query::SurfaceDeviation>& {
        auto it = meshoptCache.find(target);
        if (it == meshoptCache.end()) {
          MeshoptResult r = meshoptSimplify(model.mesh, target);
          auto d = deviation(model, r.mesh, "meshopt");
          it = meshoptCache.emplace(target, std::make_pair(std::move(r), d)).first;
        }
        return it->second;
      };
      for (double fraction : fractions) {
        const std::size_t target =
            std::max<std::size_t>(1, std::size_t(std::floor(model.mesh.triangleCount() * fraction)));
        for (Builder b : qualityBuilders) {
          const auto& pm = sequence(model, b);
          // Compare at meshopt's count where it stops above the target; where our base mesh
          // cannot get down to the count, meshopt is asked for ours instead.
          std::size_t compareAt = target;
          const auto* mo = &meshoptAt(target);
          const std::size_t moTriangles = mo->first.mesh.triangleCount();
          if (moTriangles > compareAt) compareAt = moTriangles;
          const TriangleMesh ours = extractAt(pm, compareAt);
          std::string note;
          if (moTriangles > target) note += " meshopt stopped above target;";
          if (ours.triangleCount() > compareAt) {
            note += " our base mesh above target, meshopt re-run at our count;";
            mo = &meshoptAt(ours.triangleCount());
          }
          const auto dOurs = deviation(model, ours, builderName(b));
          const auto& dMo = mo->second;
          const double hRatio = dOurs.hausdorff / dMo.hausdorff;
          const double rRatio = dOurs.rms / dMo.rms;
          std::string verdict = "";
          if (b == Builder::CollapseGeometry) {
            const bool ok = hRatio <= kCollapseQualityTarget && rRatio <= kCollapseQualityTarget;
            verdict = ok ? "ok" : "MISS";
            qualityMisses += !ok;
          } else if (isCollapse(b)) {
            verdict = "info";
          }
          std::printf("%-8s %3.0f%% %7zu | %-20s %7zu %10.3e %10.3e | %7zu %10.3e %10.3e %9.2e | %7.3f %7.3f %s%s\n",
                      model.name.c_str(), fraction * 100.0, target, builderName(b), ours.triangleCount(),
                      dOurs.hausdorff, dOurs.rms, mo->first.mesh.triangleCount(), dMo.hausdorff, dMo.rms,
                      double(mo->first.resultError), hRatio, rRatio, verdict.c_str(), note.c_str());
          report["quality"].push_back({{"model", model.name},
                                       {"fraction", fraction},
                                       {"target_triangles", target},
                                       {"builder", builderKey(b)},
                                       {"base_triangles", baseTriangles(pm)},
                                       {"triangles", ours.triangleCount()},
                                       {"hausdorff", dOurs.hausdorff},
                                       {"rms", dOurs.rms},
                                       {"meshopt_triangles", mo->first.mesh.triangleCount()},
                                       {"meshopt_hausdorff", dMo.hausdorff},
                                       {"meshopt_rms", dMo.rms},
                                       {"meshopt_result_error", mo->first.resultError},
                                       {"hausdorff_ratio", hRatio},
                                       {"rms_ratio", rRatio},
                                       {"note", note}});
        }
      }
      rule(width1);
    }
  }

  // ---------------------------------------------------------------- 2. colour
  if (section("colour")) {
    std::printf(
        "\n2. Colour error at 10%% on spot (texture baked to vertex colours): colourRms (RGB in [0,1]);\n"
        "   ratio = aware / colour-blind (target <= %.2f); meshopt (geometry only, input vertices keep their\n"
        "   colours) at the same count for reference\n",
        kColourTarget);
    const int width2 = 132;
    rule(width2);
    std::printf("%-8s %-20s %7s %10s | %-20s %7s %10s | %7s %s | %7s %10s\n", "model", "aware", "tris", "colourRms",
                "blind", "tris", "colourRms", "ratio", "check", "mopt_t", "colourRms");
    rule(width2);
    // Each builder's level at a count is extracted and measured once: the pairs share the
    // aware builds, and the table by share meets the pairs' count again.
    struct Measured {
      std::size_t triangles;
      polder::query::SurfaceDeviation deviation;
    };
    std::map<std::tuple<const Model*, Builder, std::size_t>, Measured> measured;
    auto measuredAt = [&](const Model& model, Builder b, std::size_t target) -> const Measured& {
      auto it = measured.find({&model, b, target});
      if (it == measured.end()) {
        const TriangleMesh level = extractAt(sequence(model, b), target);
        it = measured
                 .emplace(std::tuple{&model, b, target},
                          Measured{level.triangleCount(), deviation(model, level, builderName(b))})
                 .first;
      }
      return it->second;
    };
    for (const Model& model : models) {
      if (!model.mesh.hasColours()) continue;
      const std::size_t target = model.mesh.triangleCount() / 10;
      // The third pair is for information (not the target's definition): collapse with
      // colourWeight = 0 still weighs UVs, which on a textured model partly stand for colour.
      struct ColourPair {
        Builder aware, blind;
        bool counts;
      };
      const ColourPair pairs[] = {{Builder::CollapseDefault, Builder::CollapseColourBlind, true},
                                  {Builder::ClusterDefault, Builder::ClusterColourBlind, true},
                                  {Builder::CollapseDefault, Builder::CollapseGeometry, false}};
      const MeshoptResult reference = meshoptSimplify(model.mesh, target);
      const auto dReference = deviation(model, reference.mesh, "meshopt");
      for (const auto& [aware, blind, counts] : pairs) {
        const auto& [awareTriangles, da] = measuredAt(model, aware, target);
        const auto& [blindTriangles, dc] = measuredAt(model, blind, target);
        const double ratio = da.colourRms / dc.colourRms;
        const bool ok = ratio <= kColourTarget;
        if (counts) colourMisses += !ok;
        std::printf("%-8s %-20s %7zu %10.4f | %-20s %7zu %10.4f | %7.3f %-5s | %7zu %10.4f\n", model.name.c_str(),
                    builderName(aware), awareTriangles, da.colourRms, builderName(blind), blindTriangles, dc.colourRms,
                    ratio,
                    !counts ? "info"
                    : ok    ? "ok"
                            : "MISS",
                    reference.mesh.triangleCount(), dReference.colourRms);
        report["colour"].push_back({{"model", model.name},
                                    {"builder", builderKey(aware)},
                                    {"blind_builder", builderKey(blind)},
                                    {"counts_for_target", counts},
                                    {"target_triangles", target},
                                    {"aware_triangles", awareTriangles},
                                    {"aware_colour_rms", da.colourRms},
                                    {"aware_hausdorff", da.hausdorff},
                                    {"aware_rms", da.rms},
                                    {"blind_triangles", blindTriangles},
                                    {"blind_colour_rms", dc.colourRms},
                                    {"blind_hausdorff", dc.hausdorff},
                                    {"blind_rms", dc.rms},
                                    {"ratio", ratio},
                                    {"meshopt_triangles", reference.mesh.triangleCount()},
                                    {"meshopt_colour_rms", dReference.colourRms}});
      }
    }
    rule(width2);

    // How the ratio depends on the triangle count: where it falls with more triangles, the
    // target's count holds too few vertices to trace the colour borders at all.
    std::printf("\n   Ratio by share of the triangles kept (info): aware / colour-blind, same builder\n");
    const double shares[] = {0.05, 0.1, 0.2, 0.3, 0.5};
    std::printf("%-14s %-10s", "model", "builder");
    for (double share : shares) std::printf(" %7.0f%%", share * 100.0);
    std::printf("\n");
    for (const Model& model : models) {
      if (!model.mesh.hasColours()) continue;
      for (const auto& [aware, blind] : {std::pair{Builder::CollapseDefault, Builder::CollapseColourBlind},
                                         std::pair{Builder::ClusterDefault, Builder::ClusterColourBlind}}) {
        std::printf("%-14s %-10s", model.name.c_str(), isCollapse(aware) ? "collapse" : "cluster");
        for (double share : shares) {
          const auto target = static_cast<std::size_t>(double(model.mesh.triangleCount()) * share);
          const double awareRms = measuredAt(model, aware, target).deviation.colourRms;
          const double blindRms = measuredAt(model, blind, target).deviation.colourRms;
          std::printf(" %8.3f", awareRms / blindRms);
          report["colour_by_share"].push_back({{"model", model.name},
                                               {"builder", builderKey(aware)},
                                               {"share", share},
                                               {"aware_colour_rms", awareRms},
                                               {"blind_colour_rms", blindRms},
                                               {"ratio", awareRms / blindRms}});
        }
        std::printf("\n");
      }
    }
  }

  // One row of the speed tables: the whole sequence's median build time over `caseRuns`
  // runs, against meshopt_simplify to the same base count; true when it meets the target.
  struct SpeedCase {
    const Model* model;
    Builder builder;
    std::uint32_t stopAt;
  };
  const int speedWidth = 132;
  auto printSpeedHeader = [&]() {
    rule(speedWidth);
    std::printf("%-8s %-20s %8s %8s %7s | %9s %9s %9s | %10s %9s %s\n", "model", "builder", "in_tris", "base", "steps",
                "steps_ms", "total_ms", "M tri/s", "meshopt_ms", "mopt M/s", "check");
    rule(speedWidth);
  };
  auto timeSpeedCase = [&](const SpeedCase& sc, int caseRuns, const char* reportKey) {
    const Model& model = *sc.model;
    std::vector<double> stepsTimes, totalTimes, meshoptTimes;
    std::uint32_t base = 0;
    std::size_t stepCount = 0;
    for (int run = 0; run < caseRuns; ++run) {
      const auto start = Clock::now();
      check(buildSteps(model.mesh, sc.builder, sc.stopAt), model.name + " " + builderName(sc.builder));
      stepsTimes.push_back(secondsSince(start));
      double seconds = 0.0;
      auto pm = buildSequence(model, sc.builder, sc.stopAt, &seconds);
      totalTimes.push_back(seconds);
      base = baseTriangles(*pm);
      stepCount = pm->stepCount();
    }
    std::size_t meshoptTriangles = 0;
    for (int run = 0; run < caseRuns; ++run) {
      const MeshoptResult r = meshoptSimplify(model.mesh, base);
      meshoptTimes.push_back(r.seconds);
      meshoptTriangles = r.mesh.triangleCount();
    }
    const double steps = median(stepsTimes), total = median(totalTimes), mo = median(meshoptTimes);
    const double rate = model.mesh.triangleCount() / total / 1e6;
    const double moRate = model.mesh.triangleCount() / mo / 1e6;
    bool ok = rate >= kSpeedTarget;
    std::string label = builderName(sc.builder);
    if (sc.stopAt) {
      ok = total < kBunny500Seconds;
      label = std::string(isCollapse(sc.builder) ? "collapse" : "cluster") +
              (sc.builder == Builder::CollapseGeometry ? " geo" : "") + " ->" + std::to_string(sc.stopAt);
    }
    std::printf("%-8s %-20s %8zu %8u %7zu | %9.2f %9.2f %9.2f | %10.2f %9.2f %s%s\n", model.name.c_str(), label.c_str(),
                model.mesh.triangleCount(), base, stepCount, steps * 1e3, total * 1e3, rate, mo * 1e3, moRate,
                ok ? "ok" : "MISS",
                sc.stopAt ? (" (target < " + std::to_string(int(kBunny500Seconds * 1000)) + " ms)").c_str() : "");
    report[reportKey].push_back({{"model", model.name},
                                 {"builder", builderKey(sc.builder)},
                                 {"stop_at_triangles", sc.stopAt},
                                 {"input_triangles", model.mesh.triangleCount()},
                                 {"base_triangles", base},
                                 {"steps", stepCount},
                                 {"steps_ms", steps * 1e3},
                                 {"total_ms", total * 1e3},
                                 {"m_triangles_per_s", rate},
                                 {"meshopt_ms", mo * 1e3},
                                 {"meshopt_triangles", meshoptTriangles},
                                 {"meshopt_m_triangles_per_s", moRate},
                                 {"ok", ok}});
    return ok;
  };

  // ---------------------------------------------------------------- 3. speed
  if (section("speed")) {
    std::printf(
        "\n3. Build speed: whole sequence (buildProgressiveMesh: steps, assembled on a second thread as they come),\n"
        "   median of %d runs; M input triangles/s (target >= %.1f); steps_ms: the builder alone;\n"
        "   meshopt_simplify to the same base triangle count for reference\n",
        runs, kSpeedTarget);
    printSpeedHeader();
    std::vector<SpeedCase> speedCases;
    for (const Model& model : models)
      for (Builder b : {Builder::CollapseGeometry, Builder::CollapseDefault, Builder::ClusterDefault})
        speedCases.push_back({&model, b, 0});
    for (Builder b : {Builder::CollapseGeometry, Builder::CollapseDefault, Builder::ClusterDefault})
      speedCases.push_back({&models[0], b, 500});
    for (const SpeedCase& sc : speedCases) speedMisses += !timeSpeedCase(sc, runs, "speed");
    rule(speedWidth);
  }

  // ---------------------------------------------------------------- 4. level moves
  if (section("moves")) {
    std::printf(
        "\n4. Level moves (the paper's Table 2): base (level 0) -> full -> base, setLevel(0, levels) then setLevel(0, "
        "0);\n"
        "   median over %d round trips; changed = triangles (corners) whose vertex changes, per level\n",
        trips);
    const int width4 = 132;
    rule(width4);
    std::printf("%-8s %-20s %7s %7s %7s | %8s %8s %8s | %9s %9s %9s %9s\n", "model", "builder", "base", "full",
                "levels", "tri/lvl", "crn/lvl", "writes", "trip_us", "up_us", "down_us", "ns/write");
    rule(width4);
    for (const Model& model : models) {
      for (Builder b : {Builder::CollapseGeometry, Builder::CollapseDefault, Builder::ClusterDefault}) {
        const auto& pm = sequence(model, b);
        const polder::mesh::RegionSequence& seq = pm.region(0);
        const std::uint32_t levels = seq.levelCount();
        std::size_t changedTriangles = 0, changedCorners = 0;
        std::unordered_set<std::uint32_t> touched;
        for (std::size_t step = 0; step < levels; ++step) {
          touched.clear();
          for (const auto& c : seq.cornerChanges(step)) touched.insert(c.slot / 3);
          changedTriangles += touched.size();
          changedCorners += seq.cornerChanges(step).size();
        }
        const double trianglesPerLevel = levels ? double(changedTriangles) / levels : 0.0;
        const double cornersPerLevel = levels ? double(changedCorners) / levels : 0.0;

        polder::mesh::ProgressiveMeshInstance instance(pm);
        instance.setLevel(0, 0);
        for (int warm = 0; warm < 5; ++warm) {
          instance.setLevel(0, levels);
          instance.setLevel(0, 0);
        }
        std::vector<double> tripTimes, upTimes, downTimes;
        const std::uint64_t writesBefore = instance.writes();
        for (int trip = 0; trip < trips; ++trip) {
          const auto t0 = Clock::now();
          instance.setLevel(0, levels);
          const auto t1 = Clock::now();
          instance.setLevel(0, 0);
          const auto t2 = Clock::now();
          benchmark::DoNotOptimize(instance.indices(0).data());
          upTimes.push_back(std::chrono::duration<double>(t1 - t0).count());
          downTimes.push_back(std::chrono::duration<double>(t2 - t1).count());
          tripTimes.push_back(std::chrono::duration<double>(t2 - t0).count());
        }
        const double writesPerTrip = double(instance.writes() - writesBefore) / trips;
        const double trip = median(tripTimes);
        std::printf("%-8s %-20s %7u %7u %7u | %8.2f %8.2f %8.0f | %9.2f %9.2f %9.2f %9.2f\n", model.name.c_str(),
                    builderName(b), seq.trianglesAt(0), seq.trianglesAt(levels), levels, trianglesPerLevel,
                    cornersPerLevel, writesPerTrip, trip * 1e6, median(upTimes) * 1e6, median(downTimes) * 1e6,
                    writesPerTrip > 0 ? trip * 1e9 / writesPerTrip : 0.0);
        report["round_trip"].push_back({{"model", model.name},
                                        {"builder", builderKey(b)},
                                        {"base_triangles", seq.trianglesAt(0)},
                                        {"full_triangles", seq.trianglesAt(levels)},
                                        {"levels", levels},
                                        {"triangles_changed_per_level", trianglesPerLevel},
                                        {"corners_changed_per_level", cornersPerLevel},
                                        {"writes_per_round_trip", writesPerTrip},
                                        {"round_trip_us", trip * 1e6},
                                        {"up_us", median(upTimes) * 1e6},
                                        {"down_us", median(downTimes) * 1e6}});
      }
    }
    rule(width4);
  }

  // ---------------------------------------------------------------- 5. terrain scale
  int scaleMisses = 0;
  if (section("scale")) {
    const std::filesystem::path demPath = std::filesystem::path(dataDir) / "dems" / "mt_rainier_90m_srtm3.tif";
    const int scaleRuns = std::min(runs, 3);
    std::printf(
        "\n5. Build speed at terrain scale: %s as one mesh (the scene files' Silvretta model),\n"
        "   centre crops of 261 x 261 and 725 x 725 samples; whole sequence, median of %d runs (target >= %.1f)\n",
        demPath.filename().c_str(), scaleRuns, kSpeedTarget);
    if (!std::filesystem::exists(demPath)) {
      std::printf("   skipped: %s is missing\n", demPath.c_str());
    } else {
      const polder::terrain::Dem dem = check(polder::terrain::readDem(demPath), demPath.string());
      std::vector<Model> terrains;
      for (int side : {261, 725}) {
        Model terrain;
        terrain.name = "dem-" + std::to_string(side);
        terrain.file = demPath.filename().string();
        terrain.mesh = polder::scene::heightfieldMesh(
            check(polder::terrain::cropCentre(dem.field, side, side), demPath.string() + " crop"));
        terrains.push_back(std::move(terrain));
      }
      printSpeedHeader();
      for (const Model& terrain : terrains)
        for (Builder b : {Builder::CollapseDefault, Builder::ClusterDefault})
          scaleMisses += !timeSpeedCase({&terrain, b, 0}, scaleRuns, "scale");
      rule(speedWidth);
    }
  }

  std::printf(
      "\nsummary: %d collapse quality miss(es), %d colour miss(es), %d speed miss(es), %d terrain-scale speed "
      "miss(es)\n",
      qualityMisses, colourMisses, speedMisses, scaleMisses);
  report["summary"] = {{"quality_misses", qualityMisses},
                       {"colour_misses", colourMisses},
                       {"speed_misses", speedMisses},
                       {"scale_misses", scaleMisses}};

  if (!jsonPath.empty()) {
    std::ofstream out(jsonPath);
    out << report.dump(2) << "\n";
    if (!out) fail(jsonPath + ": cannot write the report");
    std::printf("written %s\n", jsonPath.c_str());
  }

  if (benchmarkArgs.size() > 1) {
    int bargc = static_cast<int>(benchmarkArgs.size());
    benchmark::Initialize(&bargc, benchmarkArgs.data());
    registerGoogleBenchmarks(models);
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
  }
  return 0;
}
