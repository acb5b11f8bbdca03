// polder bench DEM: a recorded flight, headless; prints a table and writes the JSON report
// (keys fixed by the issue that asked for it; later tools read them).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <sstream>

#include <nlohmann/json.hpp>

#include <polder/camera_path.hpp>
#include <polder/enclosed_background.hpp>
#include <polder/query/frame_cracks.hpp>
#include <polder/query/query_scene.hpp>
#include <polder/query/screen_error.hpp>
#include <polder/terrain/full_resolution_mesh.hpp>
#include <polder/terrain/heightfield_crop.hpp>
#include <polder/terrain/watertight.hpp>
#include <polder/terrain_engine.hpp>

#include "bench_statistics.hpp"
#include "cli_support.hpp"
#include "commands.hpp"
#include "terrain_drawing.hpp"

namespace polder::cli {
namespace {

struct BenchArguments {
  DemArguments dem;
  std::string preset;
  std::string path = "flyover";
  int frames = 600;
  double tauPx = 1.0;
  std::string size = "1280x720";
  double fovDeg = 60.0;
  std::string render = "none";
  int measureEvery = 30;
  bool compareCache = false;
  bool countCracks = false;
  std::string mode = "error";
  std::uint64_t budget = 200000;
  double alpha = 3.0;
  double altitudeM = 300.0;
  double speedMps = 150.0;
  int blockSamples = 33;
  double cacheMb = 256.0;
  std::string json;
  std::string scene;
  bool framesGiven = false;
};

// What one pass over the path measured, frame by frame.
struct PassResult {
  std::vector<double> selectMs, lodMs, dikesMs, piecesMs, totalMs, renderMs, uploadBytes;
  std::vector<double> triangles, dikeTriangles, visible, culled;
  std::uint64_t lookups = 0, hits = 0, rebuilds = 0;
  std::uint64_t piecesCreated = 0, piecesChanged = 0, piecesRetired = 0;
  double pieceBytes = 0.0;  // vertex and index bytes the created and changed pieces carry
  std::size_t enclosedBackground = 0, cracks = 0;  // --count-cracks, over the rendered frames
  double errorMax = 0.0, errorP99 = 0.0;
  int framesMeasured = 0;
  int framesChecked = 0;
  std::size_t openEdges = 0, tJunctions = 0;
  double dikeBoundMaxPx = 0.0;            // the dike check's largest bound over the frames
  int dikeFramesOverTau = 0;              // frames the check left a dike triangle over tau
  std::size_t dikeTrianglesOverTauMax = 0;
};

// Reads the frame back and adds its enclosed background pixels and, among them, its cracks
// (query/frame_cracks.hpp); the frame's mesh is ray cast only when something is enclosed.
void countCracks(render::Renderer& renderer, TerrainEngine& engine, const Camera& camera, PassResult& result) {
  RgbaImage image;
  if (!renderer.readPixels(image).ok() || countEnclosedBackground(image) == 0) return;
  auto frameMesh = query::QueryScene::createFromMeshes(engine.frameMeshes());
  if (!frameMesh) return;
  const query::FrameCracks found = query::findFrameCracks(image, **frameMesh, camera);
  result.enclosedBackground += found.enclosedBackground;
  result.cracks += found.cracks;
}

Result<CameraPath> makePath(const BenchArguments& arguments, const terrain::Heightfield& field,
                            const query::QueryScene& truth) {
  auto ground = [&truth](double x, double y) { return truth.height(x, y).value_or(0.0); };
  if (arguments.path == "flyover") {
    FlyoverOptions options;
    options.altitudeM = arguments.altitudeM;
    options.speedMps = arguments.speedMps;
    return makeFlyoverLoop(field.extentX(), field.extentY(), ground, options);
  }
  if (arguments.path == "orbit") {
    OrbitOptions options;
    options.altitudeM = arguments.altitudeM;
    options.speedMps = arguments.speedMps;
    return makeOrbitLoop(field.extentX(), field.extentY(), ground, options);
  }
  std::ifstream file(arguments.path);
  if (!file) return makeError(ErrorKind::Io, arguments.path + ": cannot open the camera path (give flyover, orbit or a file)");
  std::stringstream text;
  text << file.rdbuf();
  auto path = CameraPath::parse(text.str());
  if (!path) return makeError(path.error().kind, arguments.path + ": " + path.error().message);
  return path;
}

PassResult runPass(TerrainEngine& engine, const CameraPath& path, const Camera& lens, const BenchArguments& arguments,
                   const query::QueryScene* truth, HeadlessRenderer* headless, const TerrainStyle& style, bool progressBar) {
  PassResult result;
  std::optional<TerrainDrawer> drawer;
  if (headless) drawer.emplace(*headless->renderer);
  const double frameTimeS = 1.0 / 60.0;
  std::vector<double> errorMaxima, errorP99s;
  std::optional<ProgressBar> progress;
  if (progressBar) progress.emplace(std::string(engine.options().cacheEnabled ? "flying" : "flying without cache"));
  for (int frameIndex = 0; frameIndex < arguments.frames; ++frameIndex) {
    const Camera camera = path.at(frameIndex * frameTimeS).placed(lens);
    const TerrainFrame& frame = engine.update(camera);
    const TerrainFrameStats& stats = frame.stats;
    result.selectMs.push_back(stats.selectMs);
    result.lodMs.push_back(stats.lodMs);
    result.dikesMs.push_back(stats.dikesMs);
    result.piecesMs.push_back(stats.piecesMs);
    result.totalMs.push_back(stats.totalMs);
    result.piecesCreated += stats.piecesCreated;
    result.piecesChanged += stats.piecesChanged;
    result.piecesRetired += stats.piecesRetired;
    result.pieceBytes += double(stats.pieceBytesProduced);
    result.triangles.push_back(double(stats.triangles()));
    result.dikeTriangles.push_back(double(stats.dikeTriangles));
    result.visible.push_back(double(stats.visibleBlocks));
    result.culled.push_back(double(stats.culledBlocks));
    result.lookups += stats.cacheLookups;
    result.hits += stats.cacheHits;
    result.rebuilds += stats.cacheRebuilds;
    result.dikeBoundMaxPx = std::max(result.dikeBoundMaxPx, stats.dikeErrorPx);
    result.dikeFramesOverTau += stats.dikeTrianglesOverTau > 0;
    result.dikeTrianglesOverTauMax = std::max(result.dikeTrianglesOverTauMax, stats.dikeTrianglesOverTau);

    const bool measure = truth && arguments.measureEvery > 0 && frameIndex % arguments.measureEvery == 0;
    if (headless) {
      // Render time counts the uploads of the frame's new and changed pieces, and waits for
      // the rasteriser to finish.
      const auto start = std::chrono::steady_clock::now();
      (void)drawer->sync(frame);
      headless->renderer->beginFrame(camera, style);
      drawer->draw(frame);
      (void)headless->renderer->endFrame();
      headless->renderer->finish();
      result.renderMs.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
      result.uploadBytes.push_back(double(drawer->stats().uploadedBytes));
      if (arguments.countCracks) countCracks(*headless->renderer, engine, camera, result);
    }
    if (measure) {
      const std::span<const MeshData> meshes = engine.frameMeshes();
      if (auto lodScene = query::QueryScene::createFromMeshes(meshes)) {
        const query::ScreenError error = query::measureScreenError(**lodScene, *truth, camera);
        errorMaxima.push_back(error.maxPx);
        errorP99s.push_back(error.p99Px);
        ++result.framesMeasured;
      }
      const terrain::WatertightReport report = engine.checkWatertight();
      result.openEdges += report.openEdges;
      result.tJunctions += report.tJunctions;
      ++result.framesChecked;
    }
    if (progress) progress->update(float(frameIndex + 1) / float(arguments.frames));
  }
  for (double e : errorMaxima) result.errorMax = std::max(result.errorMax, e);
  for (double e : errorP99s) result.errorP99 = std::max(result.errorP99, e);
  return result;
}

// Median over the frames of (pieces ms) / (the rest of update()'s ms).
double hostDataRatio(const PassResult& pass) {
  std::vector<double> ratios;
  for (std::size_t i = 0; i < pass.piecesMs.size(); ++i)
    ratios.push_back(pass.piecesMs[i] / std::max(pass.totalMs[i] - pass.piecesMs[i], 1e-9));
  return percentiles(ratios).median;
}

double sum(const std::vector<double>& values) {
  double total = 0.0;
  for (double v : values) total += v;
  return total;
}

int runBench(BenchArguments arguments) {
  // Validate everything cheap before reading the DEM.
  if (arguments.frames < 1 || arguments.frames > 1000000)
    return reportError(makeError(ErrorKind::InvalidArgument, "--frames must be between 1 and 1000000"));
  if (!(arguments.tauPx > 0.0) || !std::isfinite(arguments.tauPx))
    return reportError(makeError(ErrorKind::InvalidArgument, "--tau must be a positive number of pixels"));
  if (arguments.mode != "error" && arguments.mode != "budget")
    return reportError(makeError(ErrorKind::InvalidArgument, "--mode must be 'error' or 'budget'"));
  if (arguments.mode == "budget" && (arguments.budget < 100 || arguments.budget > 100000000))
    return reportError(makeError(ErrorKind::InvalidArgument, "--budget must be between 100 and 100000000 triangles"));
  if (!(arguments.alpha > 0.0) || !std::isfinite(arguments.alpha))
    return reportError(makeError(ErrorKind::InvalidArgument, "--alpha must be a positive number"));
  if (arguments.render != "none" && arguments.render != "gl")
    return reportError(makeError(ErrorKind::InvalidArgument, "--render must be 'none' or 'gl'"));
  if (arguments.countCracks && arguments.render != "gl")
    return reportError(makeError(ErrorKind::InvalidArgument, "--count-cracks needs --render gl"));
  if (arguments.measureEvery < 0)
    return reportError(makeError(ErrorKind::InvalidArgument, "--measure-every must be 0 (never) or more"));
  if (!(arguments.cacheMb > 0.0) || arguments.cacheMb > 1e6)
    return reportError(makeError(ErrorKind::InvalidArgument, "--cache-mb must be between 0 and 1000000"));
  int blockK = 0;
  for (int k = 4; k <= 7; ++k)
    if (arguments.blockSamples == (1 << k) + 1) blockK = k;
  if (blockK == 0) return reportError(makeError(ErrorKind::InvalidArgument, "--block must be 17, 33, 65 or 129"));
  if (!arguments.preset.empty() && arguments.preset != "seed002")
    return reportError(makeError(ErrorKind::InvalidArgument, "--preset must be 'seed002'"));

  if (arguments.preset == "seed002") {
    // Chuang 2001's experiment: 20 x 20 blocks of 33 x 33 samples at 40 m, flown about 1000 m
    // above the ground with a 40 degree field of view in an 800 x 800 window.
    arguments.dem.spacingM = 40.0;
    arguments.blockSamples = 33;
    blockK = 5;
    arguments.altitudeM = 1000.0;
    arguments.fovDeg = 40.0;
    arguments.size = "800x800";
  }
  auto size = parseImageSize(arguments.size);
  if (!size) return reportError(size.error());
  if (!(arguments.fovDeg > 1.0 && arguments.fovDeg < 179.0))
    return reportError(makeError(ErrorKind::InvalidArgument, "--fov must be between 1 and 179 degrees"));

  auto dem = loadDem(arguments.dem);
  if (!dem) return reportError(dem.error());
  auto field = std::make_shared<terrain::Heightfield>(std::move(dem->field));
  if (arguments.preset == "seed002") {
    auto crop = terrain::cropCentre(*field, 660, 660);
    if (!crop) return reportError(makeError(ErrorKind::InvalidData, arguments.dem.path + ": " + crop.error().message));
    *field = std::move(*crop);
  }
  const auto [low, high] = field->heightRange();

  auto truth = query::QueryScene::create(*field);
  if (!truth) return reportError(truth.error());
  auto path = makePath(arguments, *field, **truth);
  if (!path) return reportError(path.error());

  TerrainEngineOptions options;
  options.blockK = blockK;
  options.tauPx = arguments.tauPx;
  options.mode = arguments.mode == "budget" ? LodMode::TriangleBudget : LodMode::PixelError;
  options.budgetTriangles = arguments.budget;
  options.alpha = arguments.alpha;
  options.cacheBytes = std::size_t(arguments.cacheMb * 1048576.0);
  Result<std::unique_ptr<TerrainEngine>> engine = makeError(ErrorKind::InvalidData, "not built");
  {
    ProgressBar progress("preparing blocks");
    engine = TerrainEngine::create(field, options, [&](float f) { progress.update(f); });
  }
  if (!engine) return reportError(engine.error());

  Camera lens;
  lens.widthPx = size->first;
  lens.heightPx = size->second;
  lens.fovYDeg = arguments.fovDeg;
  lens.position = path->at(0.0).position;
  fitClipPlanes(lens, *field);

  std::optional<HeadlessRenderer> headless;
  TerrainStyle style;
  style.minHeightM = low;
  style.maxHeightM = std::max(high, low + 1.0f);
  if (arguments.render == "gl") {
    auto created = createHeadlessRenderer(lens.widthPx, lens.heightPx);
    if (!created) return reportError(created.error());
    headless = std::move(*created);
  }

  const PassResult cached = runPass(**engine, *path, lens, arguments, truth->get(), headless ? &*headless : nullptr, style, true);
  std::optional<PassResult> uncached;
  if (arguments.compareCache) {
    TerrainEngineOptions without = options;
    without.cacheEnabled = false;
    (*engine)->setOptions(without);
    uncached = runPass(**engine, *path, lens, arguments, nullptr, nullptr, style, true);
    (*engine)->setOptions(options);
  }

  const double fullResolution = double(terrain::fullResolutionTriangleCount(*field));
  nlohmann::json report = {
      {"dem",
       {{"path", arguments.dem.path},
        {"width", field->width},
        {"height", field->height},
        {"spacing_m", {field->spacingX, field->spacingY}},
        {"min_m", low},
        {"max_m", high}}},
      {"config",
       {{"tau_px", arguments.tauPx},
        {"width_px", lens.widthPx},
        {"height_px", lens.heightPx},
        {"fov_deg", lens.fovYDeg},
        {"block_samples", arguments.blockSamples},
        {"mode", arguments.mode},
        {"budget_tris", arguments.mode == "budget" ? nlohmann::json(arguments.budget) : nlohmann::json(nullptr)},
        {"cache", true},
        {"frames", arguments.frames},
        {"path", arguments.path}}},
      {"triangles",
       {{"mean", mean(cached.triangles)},
        {"max", cached.triangles.empty() ? 0.0 : *std::max_element(cached.triangles.begin(), cached.triangles.end())},
        {"full_res", fullResolution},
        {"dikes_mean", mean(cached.dikeTriangles)}}},
      {"blocks", {{"visible_mean", mean(cached.visible)}, {"culled_mean", mean(cached.culled)}}},
      {"lod_cache",
       {{"reuse_rate", cached.lookups ? double(cached.hits) / double(cached.lookups) : 0.0},
        {"rebuilds", cached.rebuilds},
        {"lookups", cached.lookups}}},
      {"cpu_ms",
       {{"select", percentileJson(cached.selectMs)},
        {"lod", percentileJson(cached.lodMs)},
        {"dikes", percentileJson(cached.dikesMs)},
        {"pieces", percentileJson(cached.piecesMs)},
        {"total", percentileJson(cached.totalMs)}}},
      // Host-ready vertex data (what replaces rebuilding every visible block's world mesh per
      // frame): its cost against the rest of update(), frame by frame.
      {"pieces",
       {{"created", cached.piecesCreated},
        {"changed", cached.piecesChanged},
        {"retired", cached.piecesRetired},
        {"bytes_per_frame_mean", cached.pieceBytes / std::max(1, arguments.frames)},
        {"host_data_ratio", hostDataRatio(cached)}}},
      {"render_ms", cached.renderMs.empty() ? nlohmann::json(nullptr) : percentileJson(cached.renderMs)},
      {"upload_bytes_per_frame",
       cached.uploadBytes.empty()
           ? nlohmann::json(nullptr)
           : nlohmann::json{{"mean", mean(cached.uploadBytes)},
                            {"median", percentiles(cached.uploadBytes).median},
                            {"p99", percentiles(cached.uploadBytes).p99},
                            {"zero_frames", std::count(cached.uploadBytes.begin(), cached.uploadBytes.end(), 0.0)}}},
      {"cracks", arguments.countCracks && arguments.render == "gl"
                     ? nlohmann::json{{"enclosed_background_px", cached.enclosedBackground}, {"crack_px", cached.cracks}}
                     : nlohmann::json(nullptr)},
      {"screen_error_px",
       {{"tau", arguments.tauPx}, {"max", cached.errorMax}, {"p99", cached.errorP99}, {"frames_measured", cached.framesMeasured}}},
      {"watertight",
       {{"frames_checked", cached.framesChecked}, {"open_edges", cached.openEdges}, {"t_junctions", cached.tJunctions}}},
      {"dike_check",
       {{"bound_px_max", cached.dikeBoundMaxPx},
        {"frames_over_tau", cached.dikeFramesOverTau},
        {"triangles_over_tau_max", cached.dikeTrianglesOverTauMax}}},
      {"memory", {{"peak_rss_mb", peakRssMb()}}},
  };
  if (uncached) {
    report["compare_cache"] = {
        {"lod_ms_saved_frac", 1.0 - sum(cached.lodMs) / std::max(sum(uncached->lodMs), 1e-12)},
        {"total_ms_saved_frac", 1.0 - sum(cached.totalMs) / std::max(sum(uncached->totalMs), 1e-12)},
        {"triangles_ratio", mean(cached.triangles) / std::max(mean(uncached->triangles), 1e-12)},
    };
  }

  const Percentiles total = percentiles(cached.totalMs);
  std::printf("\n%-34s %s\n", "DEM", arguments.dem.path.c_str());
  std::printf("%-34s %d x %d samples, %.1f m spacing%s\n", "", field->width, field->height, field->spacingX,
              arguments.preset.empty() ? "" : "  (preset seed002: central 660 x 660)");
  std::printf("%-34s %d frames of '%s', %dx%d, fov %.0f, %s\n", "flight", arguments.frames, arguments.path.c_str(),
              lens.widthPx, lens.heightPx, lens.fovYDeg,
              arguments.mode == "budget" ? ("budget " + std::to_string(arguments.budget) + " triangles").c_str()
                                         : ("tau " + std::to_string(arguments.tauPx) + " px").c_str());
  std::printf("%-34s %.0f mean, %.0f max (%.2f%% of %.0f full resolution)\n", "triangles per frame", mean(cached.triangles),
              report["triangles"]["max"].get<double>(), 100.0 * mean(cached.triangles) / fullResolution, fullResolution);
  std::printf("%-34s %.1f%% of the triangles\n", "dikes", 100.0 * mean(cached.dikeTriangles) / std::max(mean(cached.triangles), 1.0));
  std::printf("%-34s %.1f visible, %.1f culled\n", "blocks per frame", mean(cached.visible), mean(cached.culled));
  std::printf("%-34s %.3f median, %.3f p99 (select %.3f, lod %.3f, dikes %.3f)\n", "cpu ms per frame", total.median,
              total.p99, percentiles(cached.selectMs).median, percentiles(cached.lodMs).median,
              percentiles(cached.dikesMs).median);
  std::printf("%-34s %.3f ms median, x%.2f of the rest of the frame; %.0f KB per frame\n", "host data (pieces)",
              percentiles(cached.piecesMs).median, hostDataRatio(cached), cached.pieceBytes / 1024.0 / std::max(1, arguments.frames));
  if (!cached.renderMs.empty()) {
    std::printf("%-34s %.1f median, %.1f p99\n", "render ms per frame (OSMesa)", percentiles(cached.renderMs).median,
                percentiles(cached.renderMs).p99);
    std::printf("%-34s %.0f KB mean, %.0f KB median; %lld of %d frames upload nothing\n", "uploaded per frame",
                mean(cached.uploadBytes) / 1024.0, percentiles(cached.uploadBytes).median / 1024.0,
                static_cast<long long>(std::count(cached.uploadBytes.begin(), cached.uploadBytes.end(), 0.0)), arguments.frames);
  }
  if (arguments.countCracks && arguments.render == "gl")
    std::printf("%-34s %zu cracks (%zu enclosed background pixels, silhouette notches included)\n", "pixel cracks",
                cached.cracks, cached.enclosedBackground);
  std::printf("%-34s %.1f%% reused, %llu rebuilds\n", "LOD cache", 100.0 * report["lod_cache"]["reuse_rate"].get<double>(),
              static_cast<unsigned long long>(cached.rebuilds));
  std::printf("%-34s max %.3f px, p99 %.3f px over %d frames (tau %.2f)\n", "measured screen-space error",
              cached.errorMax, cached.errorP99, cached.framesMeasured, arguments.tauPx);
  std::printf("%-34s %zu open edges, %zu T-junctions over %d frames\n", "watertight", cached.openEdges,
              cached.tJunctions, cached.framesChecked);
  if (arguments.mode != "budget")
    std::printf("%-34s bound max %.3f px; %d of %d frames left dike triangles over tau (at most %zu)\n", "dike check",
                cached.dikeBoundMaxPx, cached.dikeFramesOverTau, arguments.frames, cached.dikeTrianglesOverTauMax);
  if (uncached)
    std::printf("%-34s lod %.1f%% faster, total %.1f%% faster, triangles x%.3f\n", "cache vs no cache",
                100.0 * report["compare_cache"]["lod_ms_saved_frac"].get<double>(),
                100.0 * report["compare_cache"]["total_ms_saved_frac"].get<double>(),
                report["compare_cache"]["triangles_ratio"].get<double>());
  std::printf("%-34s %.0f MB\n", "peak memory", peakRssMb());

  if (!arguments.json.empty()) {
    std::ofstream out(arguments.json);
    out << report.dump(2) << "\n";
    if (!out) return reportError(makeError(ErrorKind::Io, arguments.json + ": cannot write the report"));
    std::printf("%-34s %s\n", "report", arguments.json.c_str());
  }
  const bool withinTau = cached.errorMax <= arguments.tauPx || arguments.mode == "budget";
  return withinTau && cached.openEdges == 0 && cached.tJunctions == 0 ? 0 : kExitData;
}

}  // namespace

void addBenchCommand(CLI::App& app, int& exitCode) {
  auto arguments = std::make_shared<BenchArguments>();
  CLI::App* command = app.add_subcommand("bench", "Fly a recorded path headless and report LOD, cache, error and timing figures");
  addDemArguments(*command, arguments->dem);
  command->add_option("--preset", arguments->preset, "seed002: the seed's 20x20 blocks of 33x33 at 40 m, 1000 m up, fov 40, 800x800");
  command->add_option("--path", arguments->path, "flyover, orbit, or a file of 't x y z yaw pitch' lines")->capture_default_str();
  command->add_option("--frames", arguments->frames, "Frames at 60 per second of flight")->capture_default_str();
  command->add_option("--tau", arguments->tauPx, "Screen-space error tolerance in pixels")->capture_default_str();
  command->add_option("--size", arguments->size, "Viewport WxH")->capture_default_str();
  command->add_option("--fov", arguments->fovDeg, "Vertical field of view in degrees")->capture_default_str();
  command->add_option("--render", arguments->render, "none or gl (draw every frame with OSMesa and time it)")->capture_default_str();
  command->add_option("--measure-every", arguments->measureEvery, "Frames between error and watertightness checks (0: never)")
      ->capture_default_str();
  command->add_flag("--compare-cache", arguments->compareCache, "Fly the path again without the LOD cache and compare");
  command->add_flag("--count-cracks", arguments->countCracks,
                    "With --render gl: read every frame back and count pixel cracks between triangles");
  command->add_option("--mode", arguments->mode, "error (tau) or budget (triangle budget)")->capture_default_str();
  command->add_option("--budget", arguments->budget, "Triangles per frame in budget mode, dikes included")->capture_default_str();
  command->add_option("--alpha", arguments->alpha, "Attenuation exponent of the budget allocator")->capture_default_str();
  command->add_option("--altitude", arguments->altitudeM, "Metres above the ground")->capture_default_str();
  command->add_option("--speed", arguments->speedMps, "Metres per second")->capture_default_str();
  command->add_option("--block", arguments->blockSamples, "Block size in samples: 17, 33, 65 or 129")->capture_default_str();
  command->add_option("--cache-mb", arguments->cacheMb, "LOD cache budget in MiB")->capture_default_str();
  command->add_option("--json", arguments->json, "Write the report here");
  command->add_option("--scene", arguments->scene,
                      "Run a scene file (terrain and mesh objects, docs/scene_format.md) instead of a DEM flight");
  command->get_option("dem")->required(false);
  command->callback([arguments, command, &exitCode] {
    arguments->framesGiven = command->count("--frames") > 0;
    if (!arguments->scene.empty()) {
      exitCode = benchScene(arguments->scene, arguments->framesGiven ? std::optional<int>(arguments->frames) : std::nullopt,
                            arguments->json);
    } else if (arguments->dem.path.empty()) {
      std::fprintf(stderr, "polder: error: bench needs a DEM or --scene SCENE.json\n");
      exitCode = kExitUsage;
    } else {
      exitCode = runBench(*arguments);
    }
  });
}

}  // namespace polder::cli
