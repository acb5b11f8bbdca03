// polder scene SCENE.json: terrain and mesh objects under one triangle budget, rendered
// headless to PNG frames; and `polder bench --scene`, the same frames measured.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <polder/file_contents.hpp>
#include <polder/terrain/image_writer.hpp>
#if POLDER_HAVE_GLFW
#include <polder/platform/glfw_window.hpp>
#endif

#include "bench_report.hpp"
#include "cli_support.hpp"
#include "commands.hpp"
#include "number_rules.hpp"
#include "scene_file.hpp"
#include "terrain_drawing.hpp"

namespace polder::cli {
namespace {

struct SceneArguments {
  std::string file;
  std::optional<int> frames;
  std::string out;
  int every = 1;
  bool window = false;
};

// Draws the scene's last frame: the terrain's pieces through `drawer`, the objects streamed.
void drawScene(render::Renderer& renderer, TerrainDrawer& drawer, scene::Scene& scene, const Camera& camera,
               const TerrainStyle& style) {
  const TerrainEngine* terrain = scene.terrain();
  if (terrain) (void)drawer.sync(terrain->frame());  // a piece the GPU refused stays undrawn
  renderer.beginFrame(camera, style);
  if (terrain) drawer.draw(terrain->frame());
  for (const DrawItem& item : scene.objectDrawItems()) (void)renderer.drawTransient(item);
}

// Per-frame figures of a scene run.
struct RegionShare {
  double distanceM = 0.0;
  std::uint32_t triangles = 0;
};

struct SceneRun {
  std::vector<RegionShare> lastFrameRegions;  // mesh regions in view at the last frame
  std::vector<double> triangles, objectTriangles, regions, allocatorMs, totalMs, visibleObjects, objectsMs, terrainMs;
  int framesWithinBudget = 0;
  std::size_t objects = 0;
  std::size_t allocatedRegionsMax = 0;
};

Result<SceneRun> runScene(scene::BuiltScene& loaded, int frames, const std::string& outDir, int every) {
  std::optional<HeadlessRenderer> headless;
  if (!outDir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(outDir, ec);
    if (ec) return makeError(ErrorKind::Io, outDir + ": cannot create the folder (" + ec.message() + ")");
    auto created = createHeadlessRenderer(loaded.lens.widthPx, loaded.lens.heightPx);
    if (!created) return created.error();
    headless = std::move(*created);
  }
  std::optional<TerrainDrawer> drawer;
  if (headless) drawer.emplace(*headless->renderer);
  SceneRun run;
  const bool budget = loaded.scene->options().mode == LodMode::TriangleBudget;
  const std::uint64_t budgetTriangles = loaded.scene->options().budgetTriangles;
  ProgressBar progress(headless ? "rendering" : "running");
  RgbaImage image;
  for (int index = 0; index < frames; ++index) {
    const Camera camera = loaded.cameraAtFrame(index);
    const scene::SceneStats& stats = loaded.scene->update(camera, index / 60.0);
    run.triangles.push_back(double(stats.triangles()));
    run.objectTriangles.push_back(double(stats.objectTriangles));
    run.regions.push_back(double(stats.regions));
    run.visibleObjects.push_back(double(stats.visibleObjects));
    run.allocatorMs.push_back(stats.allocatorMs);
    run.totalMs.push_back(stats.totalMs);
    run.objectsMs.push_back(stats.objectsMs);
    run.terrainMs.push_back(stats.terrain.totalMs);
    run.objects = stats.objects;
    run.allocatedRegionsMax = std::max(run.allocatedRegionsMax, stats.allocatedRegions);
    run.framesWithinBudget += budget && endsWithinBudget(stats.triangles(), budgetTriangles);
    if (headless && index % every == 0) {
      drawScene(*headless->renderer, *drawer, *loaded.scene, camera, loaded.style);
      if (Status s = headless->renderer->endFrame(); !s) return s.error();
      if (Status s = headless->renderer->readPixels(image); !s) return s.error();
      makeOpaque(image);
      char name[32];
      std::snprintf(name, sizeof name, "frame_%05d.png", index);
      if (Status s = terrain::writeRgbaPng(std::filesystem::path(outDir) / name, image); !s) return s.error();
    }
    progress.update(float(index + 1) / float(frames));
    if (index + 1 == frames) {
      for (std::size_t n = 0; n < loaded.scene->nodeCount(); ++n) {
        const scene::SceneNode& node = loaded.scene->node(int(n));
        if (node.model < 0) continue;
        const scene::MeshModel& model = loaded.scene->model(node.model);
        for (std::uint32_t r = 0; r < model.mesh().regionCount(); ++r) {
          if (!loaded.scene->regionVisible(int(n), r)) continue;
          const Aabb& box = model.regionBox(r);
          const glm::dvec3 centre(loaded.scene->worldMatrix(int(n)) *
                                  glm::dvec4(0.5 * (box.minCorner + box.maxCorner), 1.0));
          run.lastFrameRegions.push_back(
              {glm::length(centre - camera.position), loaded.scene->instance(int(n)).triangleCount(r)});
        }
      }
    }
  }
  return run;
}

void printRun(const scene::BuiltScene& loaded, const SceneRun& run, int frames) {
  const scene::SceneOptions& options = loaded.scene->options();
  const Percentiles allocator = percentiles(run.allocatorMs), total = percentiles(run.totalMs);
  std::printf("%-30s %d frames, %s\n", "scene", frames,
              options.mode == LodMode::TriangleBudget
                  ? ("budget " + std::to_string(options.budgetTriangles) + " triangles").c_str()
                  : ("tau " + std::to_string(options.tauPx) + " px").c_str());
  std::printf("%-30s %.0f mean, %.0f max\n", "triangles per frame", mean(run.triangles),
              run.triangles.empty() ? 0.0 : *std::max_element(run.triangles.begin(), run.triangles.end()));
  if (options.mode == LodMode::TriangleBudget)
    std::printf("%-30s %d of %d\n", "frames within 0.9P..P", run.framesWithinBudget, frames);
  std::printf("%-30s %zu (%.1f visible), %.1f regions in view, %.0f triangles\n", "objects", run.objects,
              mean(run.visibleObjects), mean(run.regions), mean(run.objectTriangles));
  if (run.lastFrameRegions.size() > 1) {
    auto byDistance = run.lastFrameRegions;
    std::sort(byDistance.begin(), byDistance.end(),
              [](const RegionShare& a, const RegionShare& b) { return a.distanceM < b.distanceM; });
    std::uint32_t most = 0;
    for (const RegionShare& r : byDistance) most = std::max(most, r.triangles);
    std::printf("%-30s nearest %u, farthest %u, most %u triangles (last frame, %zu regions)\n",
                "mesh regions by distance", byDistance.front().triangles, byDistance.back().triangles, most,
                byDistance.size());
  }
  std::printf("%-30s %.3f median, %.3f p99 (%zu regions at most)\n", "allocator ms", allocator.median, allocator.p99,
              run.allocatedRegionsMax);
  std::printf("%-30s %.3f median, %.3f p99 (terrain %.3f, objects %.3f median)\n", "cpu ms per frame", total.median,
              total.p99, percentiles(run.terrainMs).median, percentiles(run.objectsMs).median);
}

#if POLDER_HAVE_GLFW
// The scene in a window, in real time: the camera follows the scene's path (or stays put),
// Escape quits; with --frames the window closes after that many frames.
int runSceneWindow(scene::BuiltScene& loaded, std::optional<int> frames) {
  platform::GlfwWindowOptions options;
  options.title = "Polder scene";
  options.width = loaded.lens.widthPx;
  options.height = loaded.lens.heightPx;
  auto window = platform::GlfwWindow::create(options);
  if (!window) return reportError(window.error());
  auto renderer = render::Renderer::create(&platform::GlfwWindow::getProcAddress);
  if (!renderer) return reportError(renderer.error());
  TerrainDrawer drawer(**renderer);
  const auto start = std::chrono::steady_clock::now();
  for (int frame = 0; !(*window)->shouldClose() && (!frames || frame < *frames); ++frame) {
    (*window)->pollEvents();
    if ((*window)->input().held(platform::Key::Escape)) break;
    const double timeS = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    Camera camera = loaded.cameraAtFrame(int(timeS * 60.0));
    const glm::ivec2 size = (*window)->framebufferSize();
    if (size.x <= 0 || size.y <= 0) continue;  // minimised
    camera.widthPx = size.x;
    camera.heightPx = size.y;
    const scene::SceneStats& stats = loaded.scene->update(camera, timeS);
    drawScene(**renderer, drawer, *loaded.scene, camera, loaded.style);
    if (Status done = (*renderer)->endFrame(); !done) return reportError(done.error());
    (*window)->swapBuffers();
    char title[160];
    std::snprintf(title, sizeof title, "Polder scene - %llu triangles (%llu in %zu objects)",
                  static_cast<unsigned long long>(stats.triangles()),
                  static_cast<unsigned long long>(stats.objectTriangles), stats.visibleObjects);
    (*window)->setTitle(title);
  }
  return 0;
}
#endif

int runSceneCommand(const SceneArguments& arguments) {
  if (arguments.frames && *arguments.frames < 1)
    return reportError(makeError(ErrorKind::InvalidArgument, "--frames must be at least 1"));
  if (arguments.every < 1) return reportError(makeError(ErrorKind::InvalidArgument, "--every must be at least 1"));
  auto loaded = loadSceneFile(arguments.file);
  if (!loaded) return reportError(loaded.error());
  if (arguments.window) {
#if POLDER_HAVE_GLFW
    return runSceneWindow(*loaded, arguments.frames);
#else
    return reportError(makeError(ErrorKind::Unsupported, "this build has no window platform; use --out"));
#endif
  }
  const int frames = arguments.frames.value_or(loaded->frames);
  if (frames < 1) return reportError(makeError(ErrorKind::InvalidArgument, "--frames must be at least 1"));
  auto run = runScene(*loaded, frames, arguments.out, arguments.every);
  if (!run) return reportError(run.error());
  printRun(*loaded, *run, frames);
  if (!arguments.out.empty()) std::printf("%-30s %s\n", "frames written to", arguments.out.c_str());
  return 0;
}

}  // namespace

int benchScene(const std::string& sceneFile, std::optional<int> frames, const std::string& jsonPath) {
  auto loaded = loadSceneFile(sceneFile);
  if (!loaded) return reportError(loaded.error());
  const int frameCount = frames.value_or(loaded->frames);
  if (frameCount < 1) return reportError(makeError(ErrorKind::InvalidArgument, "--frames must be at least 1"));
  auto run = runScene(*loaded, frameCount, "", 1);
  if (!run) return reportError(run.error());
  printRun(*loaded, *run, frameCount);
  const scene::SceneOptions& options = loaded->scene->options();
  const nlohmann::json report = {
      {"scene", sceneFile},
      {"config",
       {{"mode", options.mode == LodMode::TriangleBudget ? "budget" : "error"},
        {"budget_tris",
         options.mode == LodMode::TriangleBudget ? nlohmann::json(options.budgetTriangles) : nlohmann::json(nullptr)},
        {"tau_px", options.tauPx},
        {"alpha", options.alpha},
        {"frames", frameCount},
        {"width_px", loaded->lens.widthPx},
        {"height_px", loaded->lens.heightPx}}},
      {"triangles",
       {{"mean", mean(run->triangles)},
        {"max", run->triangles.empty() ? 0.0 : *std::max_element(run->triangles.begin(), run->triangles.end())},
        {"frames_within_budget",
         options.mode == LodMode::TriangleBudget ? nlohmann::json(run->framesWithinBudget) : nlohmann::json(nullptr)}}},
      {"objects",
       {{"count", run->objects},
        {"visible_mean", mean(run->visibleObjects)},
        {"regions", mean(run->regions)},
        {"triangles_mean", mean(run->objectTriangles)}}},
      {"allocator_ms", percentileJson(run->allocatorMs)},
      {"cpu_ms",
       {{"total", percentileJson(run->totalMs)},
        {"terrain", percentileJson(run->terrainMs)},
        {"objects", percentileJson(run->objectsMs)}}},
      {"memory", {{"peak_rss_mb", peakRssMb()}}},
  };
  if (!jsonPath.empty()) {
    if (Status written = core::writeFileContents(jsonPath, report.dump(2) + "\n"); !written)
      return reportError(written.error());
    std::printf("%-30s %s\n", "report", jsonPath.c_str());
  }
  const bool budgetHeld = options.mode != LodMode::TriangleBudget || run->framesWithinBudget == frameCount;
  return budgetHeld ? 0 : kExitData;
}

void addSceneCommand(CLI::App& app, int& exitCode) {
  auto arguments = std::make_shared<SceneArguments>();
  CLI::App* command =
      app.add_subcommand("scene", "Run a scene file (terrain, mesh objects, animation) and render its frames");
  command->add_option("scene", arguments->file, "Scene file (JSON, see docs/scene_format.md)")->required();
  command->add_option("--frames", arguments->frames, "Frames to run (default: the scene's)")
      ->check(numberIn(rules::kFrames));
  command->add_option("--out", arguments->out, "Render frames headless (OSMesa) into this folder as PNG");
  addNumberOption(*command, "--every", arguments->every, "Render every Nth frame", rules::kEvery);
  command->add_flag("--window", arguments->window, "Show the scene in a window in real time (Escape quits)");
  command->callback([arguments, &exitCode] { exitCode = runSceneCommand(*arguments); });
}

}  // namespace polder::cli
