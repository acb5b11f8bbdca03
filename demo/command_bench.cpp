// polder bench DEM: a recorded flight, headless; prints a table and writes the JSON report
// (keys fixed by the issue that asked for it; later tools read them).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>

#include <nlohmann/json.hpp>

#include <polder/camera_path.hpp>
#include <polder/enclosed_background.hpp>
#include <polder/file_contents.hpp>
#include <polder/flight_recorder.hpp>
#include <polder/query/frame_cracks.hpp>
#include <polder/query/pyramid_surface.hpp>
#include <polder/query/query_scene.hpp>
#include <polder/query/screen_error.hpp>
#include <polder/terrain/full_resolution_mesh.hpp>
#include <polder/terrain/heightfield_crop.hpp>
#include <polder/terrain_engine.hpp>

#include "bench_report.hpp"
#include "cli_support.hpp"
#include "commands.hpp"
#include "memory_budget.hpp"
#include "number_rules.hpp"
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
  bool flatOut = false;
  std::string mode = "error";
  std::uint64_t budget = 200000;
  double alpha = 3.0;
  double altitudeM = 300.0;
  double speedMps = 150.0;
  int blockSamples = 33;
  double cacheMb = 256.0;
  double memoryMb = 0.0;  // 0: no overall budget, --cache-mb and the engine's own for block data
  std::string json;
  std::string scene;
  bool framesGiven = false;
};

// Reads the drawn frame back and counts its enclosed background pixels and, among them, its
// cracks (query/frame_cracks.hpp); the frame's mesh is ray cast only when something is enclosed.
FramePixelCracks countCracks(render::Renderer& renderer, TerrainEngine& engine, const Camera& camera) {
  RgbaImage image;
  if (!renderer.readPixels(image).ok() || countEnclosedBackground(image) == 0) return {};
  auto frameMesh = query::QueryScene::createFromMeshes(engine.frameMeshes());
  if (!frameMesh) return {};
  const query::FrameCracks found = query::findFrameCracks(image, **frameMesh, camera);
  return {found.enclosedBackground, found.cracks};
}

// The frame's screen-space error measured against the full-resolution terrain `truth`.
std::optional<FrameScreenError> frameScreenError(TerrainEngine& engine, const query::TrueSurface& truth,
                                                 const Camera& camera) {
  auto lodScene = query::QueryScene::createFromMeshes(engine.frameMeshes());
  if (!lodScene) return std::nullopt;
  const query::ScreenError error = query::measureScreenError(**lodScene, truth, camera);
  return FrameScreenError{error.maxPx, error.p99Px, error.holePixels};
}

Result<CameraPath> makePath(const BenchArguments& arguments, const DemExtent& extent, const query::TrueSurface& truth) {
  auto ground = [&truth](double x, double y) { return truth.height(x, y).value_or(0.0); };
  if (arguments.path == "flyover") {
    FlyoverOptions options;
    options.altitudeM = arguments.altitudeM;
    options.speedMps = arguments.speedMps;
    return makeFlyoverLoop(extent.extentX(), extent.extentY(), ground, options);
  }
  if (arguments.path == "orbit") {
    OrbitOptions options;
    options.altitudeM = arguments.altitudeM;
    options.speedMps = arguments.speedMps;
    return makeOrbitLoop(extent.extentX(), extent.extentY(), ground, options);
  }
  return CameraPath::readFile(arguments.path);
}

// The recorded pass: every frame drawn with `headless` (when given) and timed, every
// --measure-every frames measured against `truth` and checked for watertightness.
Result<FlightRecord> flyMeasured(FlightRecorder& recorder, const BenchArguments& arguments,
                                 const query::TrueSurface& truth, HeadlessRenderer* headless, const TerrainStyle& style,
                                 std::vector<RssSample>& rssSamples) {
  ProgressBar progress("flying");
  FlightHooks hooks;
  if (arguments.measureEvery > 0) rssSamples.reserve(std::size_t(arguments.frames / arguments.measureEvery + 1));
  hooks.afterCheck = [&rssSamples](int frameIndex) {
    rssSamples.push_back({frameIndex, residentMbInUse(), heapInUseMb()});
  };
  hooks.progress = [&progress](float fraction) { progress.update(fraction); };
  hooks.measureError = [&truth](TerrainEngine& engine, const Camera& camera) {
    return frameScreenError(engine, truth, camera);
  };
  std::optional<TerrainDrawer> drawer;
  if (headless) {
    // Render time counts the uploads of the frame's new and changed pieces, and waits for
    // the rasteriser to finish.
    drawer.emplace(*headless->renderer);
    hooks.draw = [&](const TerrainFrame& frame, const Camera& camera) {
      (void)drawer->sync(frame);
      headless->renderer->beginFrame(camera, style);
      drawer->draw(frame);
      (void)headless->renderer->endFrame();
      headless->renderer->finish();
      return drawer->stats().uploadedBytes;
    };
    if (arguments.countCracks)
      hooks.countCracks = [headless](TerrainEngine& engine, const Camera& camera) {
        return countCracks(*headless->renderer, engine, camera);
      };
  }
  FlightOptions options;
  options.frames = arguments.frames;
  options.checkEvery = arguments.measureEvery;
  options.paced = !arguments.flatOut;
  options.settleFirstFrame = true;
  return recorder.fly(options, hooks);
}

// The same path again without the LOD cache, nothing drawn or checked.
Result<FlightRecord> flyWithoutCache(FlightRecorder& recorder, int frames) {
  ProgressBar progress("flying without cache");
  FlightHooks hooks;
  hooks.progress = [&progress](float fraction) { progress.update(fraction); };
  FlightOptions options;
  options.frames = frames;
  options.checkEvery = 0;
  options.withoutCache = true;
  options.settleFirstFrame = true;
  return recorder.fly(options, hooks);
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

  auto pyramid = arguments.preset.empty() ? pyramidToStream(arguments.dem)
                                          : Result<std::shared_ptr<const terrain::Pyramid>>(nullptr);
  if (!pyramid) return reportError(pyramid.error());
  // The truth the flight is measured against: the full resolution in Embree, or, streamed, the
  // pyramid's level-0 tiles as the measurement reaches them (never the whole DEM at once).
  std::shared_ptr<terrain::Heightfield> field;
  std::unique_ptr<query::TrueSurface> truth;
  const query::PyramidSurface* pyramidTruth = nullptr;
  DemExtent extent;
  if (*pyramid) {
    arguments.blockSamples = (1 << (*pyramid)->header().k) + 1;  // the engine streams its blocks
    extent = DemExtent::of((*pyramid)->header());
    auto tiles = std::make_unique<query::PyramidSurface>(*pyramid);
    pyramidTruth = tiles.get();
    truth = std::move(tiles);
  } else {
    auto dem = loadDem(arguments.dem);
    if (!dem) return reportError(dem.error());
    field = std::make_shared<terrain::Heightfield>(std::move(dem->field));
    if (arguments.preset == "seed002") {
      auto crop = terrain::cropCentre(*field, 660, 660);
      if (!crop)
        return reportError(makeError(ErrorKind::InvalidData, arguments.dem.path + ": " + crop.error().message));
      *field = std::move(*crop);
    }
    extent = DemExtent::of(*field);
    auto scene = query::QueryScene::create(*field);
    if (!scene) return reportError(scene.error());
    truth = std::move(*scene);
  }
  const float low = extent.minHeight, high = extent.maxHeight;
  auto path = makePath(arguments, extent, *truth);
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
    engine = createEngineWithin(field, *pyramid, options, arguments.memoryMb, [&](float f) { progress.update(f); });
  }
  if (!engine) return reportError(engine.error());

  Camera lens;
  lens.widthPx = size->first;
  lens.heightPx = size->second;
  lens.fovYDeg = arguments.fovDeg;
  lens.position = path->at(0.0).position;
  fitClipPlanes(lens, extent.extentX(), extent.extentY());

  std::optional<HeadlessRenderer> headless;
  TerrainStyle style;
  style.minHeightM = low;
  style.maxHeightM = std::max(high, low + 1.0f);
  if (arguments.render == "gl") {
    auto created = createHeadlessRenderer(lens.widthPx, lens.heightPx);
    if (!created) return reportError(created.error());
    headless = std::move(*created);
  }

  FlightRecorder recorder(**engine, *path, lens);
  std::vector<RssSample> rssSamples;
  auto flown = flyMeasured(recorder, arguments, *truth, headless ? &*headless : nullptr, style, rssSamples);
  if (!flown) return reportError(flown.error());
  const FlightRecord& cached = *flown;
  const FlightSummary summary = summarizeFlight(cached);
  std::optional<CacheComparison> comparison;
  if (arguments.compareCache) {
    auto uncached = flyWithoutCache(recorder, arguments.frames);
    if (!uncached) return reportError(uncached.error());
    comparison = compareCache(cached, *uncached);
  }

  const double fullResolution = double(terrain::fullResolutionTriangleCount(extent.width, extent.height));
  const TerrainMemory held = (*engine)->memory();
  auto mb = [](std::size_t bytes) { return double(bytes) / 1048576.0; };
  // Resident memory at the checked frames; the first tenth of the flight warms the caches up.
  const int warmUpFrames = arguments.frames / 10;
  const double rssDrift = rssDriftAfter(rssSamples, warmUpFrames);
  nlohmann::json rssJson = nlohmann::json::array();
  for (const RssSample& sample : rssSamples)
    rssJson.push_back({{"frame", sample.frame}, {"mb", sample.mb}, {"heap_mb", sample.heapMb}});
  // Budget mode ends each frame within 0.9P..P; a frame over P breaks the budget.
  const bool budgetMode = arguments.mode == "budget";
  const auto framesWithinBudget = std::count_if(cached.triangles.begin(), cached.triangles.end(), [&](double t) {
    return endsWithinBudget(std::uint64_t(t), arguments.budget);
  });
  const auto framesOverBudget = std::count_if(cached.triangles.begin(), cached.triangles.end(),
                                              [&](double t) { return std::uint64_t(t) > arguments.budget; });
  const TerrainLoadStats& loads = (*engine)->loadStats();
  const std::vector<double> loadMs(loads.loadMs.begin(), loads.loadMs.end());
  nlohmann::json report = {
      {"dem",
       {{"path", arguments.dem.path},
        {"width", extent.width},
        {"height", extent.height},
        {"spacing_m", {extent.spacingX, extent.spacingY}},
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
        {"paced_fps", arguments.flatOut ? nlohmann::json(nullptr) : nlohmann::json(kFlightFramesPerSecond)},
        {"path", arguments.path}}},
      {"triangles",
       {{"mean", summary.trianglesMean},
        {"max", summary.trianglesMax},
        {"min", cached.triangles.empty() ? 0.0 : *std::min_element(cached.triangles.begin(), cached.triangles.end())},
        {"frames_within_budget", budgetMode ? nlohmann::json(framesWithinBudget) : nlohmann::json(nullptr)},
        {"frames_over_budget", budgetMode ? nlohmann::json(framesOverBudget) : nlohmann::json(nullptr)},
        {"full_res", fullResolution},
        {"dikes_mean", summary.dikeTrianglesMean}}},
      {"blocks", {{"visible_mean", summary.visibleBlocksMean}, {"culled_mean", summary.culledBlocksMean}}},
      {"lod_cache",
       {{"reuse_rate", summary.cacheReuseRate}, {"rebuilds", cached.cacheRebuilds}, {"lookups", cached.cacheLookups}}},
      {"cpu_ms",
       {{"select", percentileJson(summary.selectMs)},
        {"lod", percentileJson(summary.lodMs)},
        {"dikes", percentileJson(summary.dikesMs)},
        {"pieces", percentileJson(summary.piecesMs)},
        {"total", percentileJson(summary.totalMs)}}},
      // Host-ready vertex data (what replaces rebuilding every visible block's world mesh per
      // frame): its cost against the rest of update(), frame by frame.
      {"pieces",
       {{"created", cached.piecesCreated},
        {"changed", cached.piecesChanged},
        {"retired", cached.piecesRetired},
        {"bytes_per_frame_mean", summary.pieceBytesPerFrame},
        {"host_data_ratio", summary.hostDataRatio}}},
      {"render_ms", summary.drawn ? percentileJson(summary.renderMs) : nlohmann::json(nullptr)},
      {"upload_bytes_per_frame", summary.drawn ? nlohmann::json{{"mean", summary.uploadBytesMean},
                                                                {"median", summary.uploadBytes.median},
                                                                {"p99", summary.uploadBytes.p99},
                                                                {"zero_frames", summary.framesUploadingNothing}}
                                               : nlohmann::json(nullptr)},
      {"cracks", arguments.countCracks && arguments.render == "gl"
                     ? nlohmann::json{{"enclosed_background_px", cached.cracks.enclosedBackgroundPx},
                                      {"crack_px", cached.cracks.crackPx}}
                     : nlohmann::json(nullptr)},
      {"screen_error_px",
       {{"tau", arguments.tauPx},
        {"max", cached.errorMaxPx},
        {"p99", cached.errorP99Px},
        {"frames_measured", cached.framesMeasured},
        {"hole_px", cached.holePixels},
        {"frames_with_holes", cached.framesWithHoles}}},
      {"watertight",
       {{"frames_checked", cached.framesChecked},
        {"open_edges", cached.openEdges},
        {"t_junctions", cached.tJunctions}}},
      {"dike_check",
       {{"bound_px_max", cached.dikeBoundMaxPx},
        {"frames_over_tau", cached.dikeFramesOverTau},
        {"triangles_over_tau_max", cached.dikeTrianglesOverTauMax}}},
      {"streaming",
       {{"source", *pyramid ? "pyramid" : "heightfield"},
        {"memory_budget_mb", arguments.memoryMb > 0 ? nlohmann::json(arguments.memoryMb) : nlohmann::json(nullptr)},
        {"loads", cached.loadsArrived},
        {"load_ms", percentileJson(loadMs)},
        {"load_failures", loads.failures},
        {"first_load_failure", loads.failures > 0 ? nlohmann::json(loads.firstFailure) : nlohmann::json(nullptr)},
        {"truth_read_failures", pyramidTruth ? pyramidTruth->readFailures() : 0},
        {"evictions", loads.evictions},
        {"turned_away", loads.turnedAway},
        {"frames_on_ancestor", cached.framesOnAncestor},
        {"holes", cached.holePixels},
        {"frame_waits", cached.frameWaits},
        {"handoffs_deferred", cached.handoffsDeferred},
        {"resident_mb_peak", mb(cached.residentBytesPeak)},
        {"screen_error_on_ancestor_px",
         {{"max", cached.errorOnAncestorMaxPx},
          {"p99", cached.errorOnAncestorP99Px},
          {"frames_measured", cached.framesMeasuredOnAncestor}}}}},
      {"memory",
       {{"peak_rss_mb", peakRssMb()},
        {"rss_mb_at_checks", rssJson},
        {"warm_up_frames", warmUpFrames},
        {"rss_drift_after_warm_up", rssDrift},
        {"engine_mb",
         {{"source", mb(held.sourceBytes)},
          {"quadtree", mb(held.quadtreeBytes)},
          {"block_hierarchies", mb(held.lodDataBytes)},
          {"block_hierarchies_budget", mb(held.lodDataBudgetBytes)},
          {"lod_cache", mb(held.cacheBytes)},
          {"lod_cache_budget", mb(held.cacheBudgetBytes)},
          {"total", mb(held.totalBytes())}}}}},
  };
  if (comparison) {
    report["compare_cache"] = {
        {"lod_ms_saved_frac", comparison->lodMsSavedFraction},
        {"total_ms_saved_frac", comparison->totalMsSavedFraction},
        {"triangles_ratio", comparison->trianglesRatio},
    };
  }

  std::printf("\n%-34s %s\n", "DEM", arguments.dem.path.c_str());
  std::printf("%-34s %d x %d samples, %.1f m spacing%s\n", "", extent.width, extent.height, extent.spacingX,
              arguments.preset.empty() ? "" : "  (preset seed002: central 660 x 660)");
  std::printf("%-34s %d frames of '%s', %dx%d, fov %.0f, %s\n", "flight", arguments.frames, arguments.path.c_str(),
              lens.widthPx, lens.heightPx, lens.fovYDeg,
              arguments.mode == "budget" ? ("budget " + std::to_string(arguments.budget) + " triangles").c_str()
                                         : ("tau " + std::to_string(arguments.tauPx) + " px").c_str());
  std::printf("%-34s %.0f mean, %.0f max (%.2f%% of %.0f full resolution)\n", "triangles per frame",
              summary.trianglesMean, summary.trianglesMax, 100.0 * summary.trianglesMean / fullResolution,
              fullResolution);
  if (budgetMode)
    std::printf("%-34s %lld of %d frames within 0.9P..P, %lld over the budget\n", "budget",
                (long long)framesWithinBudget, arguments.frames, (long long)framesOverBudget);
  std::printf("%-34s %.1f%% of the triangles\n", "dikes",
              100.0 * summary.dikeTrianglesMean / std::max(summary.trianglesMean, 1.0));
  std::printf("%-34s %.1f visible, %.1f culled\n", "blocks per frame", summary.visibleBlocksMean,
              summary.culledBlocksMean);
  std::printf("%-34s %.3f median, %.3f p99 (select %.3f, lod %.3f, dikes %.3f)\n", "cpu ms per frame",
              summary.totalMs.median, summary.totalMs.p99, summary.selectMs.median, summary.lodMs.median,
              summary.dikesMs.median);
  std::printf("%-34s %.3f ms median, x%.2f of the rest of the frame; %.0f KB per frame\n", "host data (pieces)",
              summary.piecesMs.median, summary.hostDataRatio, summary.pieceBytesPerFrame / 1024.0);
  if (summary.drawn) {
    std::printf("%-34s %.1f median, %.1f p99\n", "render ms per frame (OSMesa)", summary.renderMs.median,
                summary.renderMs.p99);
    std::printf("%-34s %.0f KB mean, %.0f KB median; %lld of %d frames upload nothing\n", "uploaded per frame",
                summary.uploadBytesMean / 1024.0, summary.uploadBytes.median / 1024.0,
                static_cast<long long>(summary.framesUploadingNothing), arguments.frames);
  }
  if (arguments.countCracks && arguments.render == "gl")
    std::printf("%-34s %zu cracks (%zu enclosed background pixels, silhouette notches included)\n", "pixel cracks",
                cached.cracks.crackPx, cached.cracks.enclosedBackgroundPx);
  std::printf("%-34s %.1f%% reused, %llu rebuilds\n", "LOD cache", 100.0 * summary.cacheReuseRate,
              static_cast<unsigned long long>(cached.cacheRebuilds));
  std::printf("%-34s max %.3f px, p99 %.3f px over %d frames (tau %.2f); %zu hole pixels\n",
              "measured screen-space error", cached.errorMaxPx, cached.errorP99Px, cached.framesMeasured,
              arguments.tauPx, cached.holePixels);
  if (cached.framesMeasuredOnAncestor > 0)
    std::printf("%-34s max %.3f px, p99 %.3f px over %d frames partly on ancestors\n", "", cached.errorOnAncestorMaxPx,
                cached.errorOnAncestorP99Px, cached.framesMeasuredOnAncestor);
  {
    const Percentiles loadPercentiles = percentiles(loadMs);
    std::printf("%-34s %llu loads (%.2f ms median, %.2f p99); %d frames partly on ancestors; %.0f MB resident peak\n",
                "block loading", static_cast<unsigned long long>(cached.loadsArrived), loadPercentiles.median,
                loadPercentiles.p99, cached.framesOnAncestor, double(cached.residentBytesPeak) / 1048576.0);
    if (loads.turnedAway > 0)
      std::printf("%-34s %llu built blocks turned away: the budget was full of blocks the cut needed\n", "",
                  static_cast<unsigned long long>(loads.turnedAway));
    if (loads.failures > 0)
      std::printf("%-34s %llu failed, drawn from ancestors; the first: %s\n", "",
                  static_cast<unsigned long long>(loads.failures), loads.firstFailure.c_str());
    if (pyramidTruth && pyramidTruth->readFailures() > 0)
      std::printf("%-34s %zu tile reads of the truth failed, their pixels unmeasured; the first: %s\n", "",
                  pyramidTruth->readFailures(), pyramidTruth->firstFailure().c_str());
  }
  std::printf("%-34s %zu open edges, %zu T-junctions over %d frames\n", "watertight", cached.openEdges,
              cached.tJunctions, cached.framesChecked);
  if (arguments.mode != "budget")
    std::printf("%-34s bound max %.3f px; %d of %d frames left dike triangles over tau (at most %zu)\n", "dike check",
                cached.dikeBoundMaxPx, cached.dikeFramesOverTau, arguments.frames, cached.dikeTrianglesOverTauMax);
  if (comparison)
    std::printf("%-34s lod %.1f%% faster, total %.1f%% faster, triangles x%.3f\n", "cache vs no cache",
                100.0 * comparison->lodMsSavedFraction, 100.0 * comparison->totalMsSavedFraction,
                comparison->trianglesRatio);
  std::printf("%-34s %.0f MB; resident after warm-up varies by %.2f%% over %zu checks\n", "peak memory", peakRssMb(),
              100.0 * rssDrift, rssSamples.size());
  std::printf("%-34s %.0f MB%s: %s %.0f, quadtree %.0f, block hierarchies %.0f of %.0f, LOD cache %.0f of %.0f\n",
              "engine holds", mb(held.totalBytes()),
              arguments.memoryMb > 0 ? (" of --memory-mb " + std::to_string(int(arguments.memoryMb))).c_str() : "",
              *pyramid ? "pyramid tables" : "heightfield", mb(held.sourceBytes), mb(held.quadtreeBytes),
              mb(held.lodDataBytes), mb(held.lodDataBudgetBytes), mb(held.cacheBytes), mb(held.cacheBudgetBytes));

  if (!arguments.json.empty()) {
    if (Status written = core::writeFileContents(arguments.json, report.dump(2) + "\n"); !written)
      return reportError(written.error());
    std::printf("%-34s %s\n", "report", arguments.json.c_str());
  }
  const bool withinTau = cached.errorMaxPx <= arguments.tauPx || budgetMode;
  const bool withinBudget = !budgetMode || framesOverBudget == 0;
  return withinTau && withinBudget && cached.openEdges == 0 && cached.tJunctions == 0 && cached.holePixels == 0
             ? 0
             : kExitData;
}

}  // namespace

void addBenchCommand(CLI::App& app, int& exitCode) {
  auto arguments = std::make_shared<BenchArguments>();
  CLI::App* command =
      app.add_subcommand("bench", "Fly a recorded path headless and report LOD, cache, error and timing figures");
  addDemArguments(*command, arguments->dem);
  command->add_option("--preset", arguments->preset,
                      "seed002: the seed's 20x20 blocks of 33x33 at 40 m, 1000 m up, fov 40, 800x800");
  command->add_option("--path", arguments->path, "flyover, orbit, or a file of 't x y z yaw pitch' lines")
      ->capture_default_str();
  addNumberOption(*command, "--frames", arguments->frames, "Frames at 60 per second of flight", rules::kFrames);
  addNumberOption(*command, "--tau", arguments->tauPx, "Screen-space error tolerance in pixels", rules::kTauPx);
  command->add_option("--size", arguments->size, "Viewport WxH")->capture_default_str();
  addNumberOption(*command, "--fov", arguments->fovDeg, "Vertical field of view in degrees", rules::kFovDeg);
  command->add_option("--render", arguments->render, "none or gl (draw every frame with OSMesa and time it)")
      ->capture_default_str();
  command
      ->add_option("--measure-every", arguments->measureEvery,
                   "Frames between error and watertightness checks (0: never)")
      ->check(numberIn(rules::kMeasureEvery))
      ->capture_default_str();
  command->add_flag("--compare-cache", arguments->compareCache, "Fly the path again without the LOD cache and compare");
  command->add_flag("--count-cracks", arguments->countCracks,
                    "With --render gl: read every frame back and count pixel cracks between triangles");
  command->add_flag("--flat-out", arguments->flatOut,
                    "Frames back to back, not at 60 per second: background loads then lag further behind");
  command->add_option("--mode", arguments->mode, "error (tau) or budget (triangle budget)")->capture_default_str();
  addNumberOption(*command, "--budget", arguments->budget, "Triangles per frame in budget mode, dikes included",
                  rules::kBudgetTriangles);
  addNumberOption(*command, "--alpha", arguments->alpha, "Attenuation exponent of the budget allocator", rules::kAlpha);
  addNumberOption(*command, "--altitude", arguments->altitudeM, "Metres above the ground", rules::kAltitudeM);
  addNumberOption(*command, "--speed", arguments->speedMps, "Metres per second", rules::kSpeedMps);
  command->add_option("--block", arguments->blockSamples, "Block size in samples: 17, 33, 65 or 129")
      ->capture_default_str();
  auto* cacheMb =
      addNumberOption(*command, "--cache-mb", arguments->cacheMb, "LOD cache budget in MiB", rules::kCacheMb);
  addMemoryBudgetOption(*command, arguments->memoryMb)->excludes(cacheMb);
  command->add_option("--json", arguments->json, "Write the report here");
  command->add_option("--scene", arguments->scene,
                      "Run a scene file (terrain and mesh objects, docs/scene_format.md) instead of a DEM flight");
  command->get_option("dem")->required(false);
  command->callback([arguments, command, &exitCode] {
    arguments->framesGiven = command->count("--frames") > 0;
    if (!arguments->scene.empty()) {
      // A scene carries its own terrain, camera and LOD settings: a DEM flight's options with
      // it would be silently ignored.
      for (const CLI::Option* option : command->get_options()) {
        const std::string name = option->get_name();
        if (option->count() > 0 && name != "--scene" && name != "--frames" && name != "--json") {
          std::fprintf(stderr, "polder: error: bench --scene takes only --frames and --json, not %s\n",
                       name == "dem" ? "a DEM" : name.c_str());
          exitCode = kExitUsage;
          return;
        }
      }
      exitCode =
          benchScene(arguments->scene, arguments->framesGiven ? std::optional<int>(arguments->frames) : std::nullopt,
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
