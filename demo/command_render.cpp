// polder render DEM --camera X,Y,Z,YAW,PITCH --out IMG.png: one frame, headless. OpenGL
// through OSMesa by default; --reference ray casts the same view with Embree.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>

#include <polder/query/query_scene.hpp>
#include <polder/query/reference_renderer.hpp>
#include <polder/terrain/image_writer.hpp>

#include "cli_support.hpp"
#include "commands.hpp"
#include "number_rules.hpp"
#include "terrain_drawing.hpp"

namespace polder::cli {
namespace {

struct RenderArguments {
  DemArguments dem;
  std::string camera;
  double fovDeg = 60.0;
  std::string size = "1280x720";
  std::string out;
  bool reference = false;
  bool wireframe = false;
  std::optional<double> tauPx;  // LOD mesh within this many pixels instead of full resolution
  std::string debug;
};

int runRender(RenderArguments arguments) {
  auto camera = parseCamera(arguments.camera, arguments.fovDeg, arguments.size);
  if (!camera) return reportError(camera.error());
  auto debug = parseDebugView(arguments.debug);
  if (!debug) return reportError(debug.error());
  if (*debug == TerrainDebugView::Wire) arguments.wireframe = true;
  if (arguments.reference && (arguments.wireframe || arguments.tauPx))
    return reportError(
        makeError(ErrorKind::InvalidArgument, "--wire and --tau draw meshes; the --reference ray caster has none"));
  if ((*debug == TerrainDebugView::Lod || *debug == TerrainDebugView::Dikes) && !arguments.tauPx)
    return reportError(makeError(ErrorKind::InvalidArgument, "--debug lod|dikes colours the LOD mesh: give --tau too"));
  if (arguments.tauPx && !(*arguments.tauPx > 0.0 && std::isfinite(*arguments.tauPx)))
    return reportError(makeError(ErrorKind::InvalidArgument, "--tau must be a positive number of pixels"));
  auto dem = loadDem(arguments.dem);
  if (!dem) return reportError(dem.error());
  fitClipPlanes(*camera, dem->field);
  TerrainStyle style = defaultTerrainStyle(dem->field);
  style.wireframe = arguments.wireframe;

  const auto start = std::chrono::steady_clock::now();
  RgbaImage image;
  std::size_t triangles = 0;
  if (arguments.reference) {
    auto scene = query::QueryScene::create(dem->field);
    if (!scene) return reportError(scene.error());
    image = query::renderReference(**scene, dem->field, *camera, style);
  } else {
    auto headless = createHeadlessRenderer(camera->widthPx, camera->heightPx);
    if (!headless) return reportError(headless.error());
    render::Renderer& renderer = *headless->renderer;
    if (arguments.tauPx) {
      TerrainEngineOptions options;
      options.tauPx = *arguments.tauPx;
      // The engine keeps the heights; nothing below reads dem->field again.
      auto engine = TerrainEngine::create(std::make_shared<terrain::Heightfield>(std::move(dem->field)), options);
      if (!engine) return reportError(engine.error());
      // One picture: wait for the blocks it shows rather than draw their ancestors.
      const TerrainFrame& frame = (*engine)->updateSettled(*camera);
      TerrainDrawer drawer(renderer);
      if (Status synced = drawer.sync(frame); !synced) return reportError(synced.error());
      renderer.beginFrame(*camera, style);
      drawer.draw(frame, *debug);
      triangles = frame.stats.triangles();
    } else {
      auto meshes = TerrainMeshes::upload(renderer, dem->field);
      if (!meshes) return reportError(meshes.error());
      renderer.beginFrame(*camera, style);
      meshes->draw(renderer);
      triangles = meshes->triangleCount();
    }
    if (Status frame = renderer.endFrame(); !frame) return reportError(frame.error());
    if (Status read = renderer.readPixels(image); !read) return reportError(read.error());
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  makeOpaque(image);
  if (Status written = terrain::writeRgbaPng(arguments.out, image); !written) return reportError(written.error());
  if (arguments.reference)
    std::printf("wrote %s (%dx%d, Embree reference, %.2f s)\n", arguments.out.c_str(), image.width, image.height,
                seconds);
  else
    std::printf("wrote %s (%dx%d, %zu triangles %s, %.2f s)\n", arguments.out.c_str(), image.width, image.height,
                triangles,
                arguments.tauPx ? ("within " + std::to_string(*arguments.tauPx) + " px").c_str() : "at full resolution",
                seconds);
  return 0;
}

}  // namespace

void addRenderCommand(CLI::App& app, int& exitCode) {
  auto arguments = std::make_shared<RenderArguments>();
  CLI::App* command =
      app.add_subcommand("render", "Render one frame headless (OpenGL via OSMesa, or Embree reference)");
  addDemArguments(*command, arguments->dem);
  command->add_option("--camera", arguments->camera, "X,Y,Z,YAW,PITCH: metres and degrees (yaw clockwise from north)")
      ->required();
  addNumberOption(*command, "--fov", arguments->fovDeg, "Vertical field of view in degrees", rules::kFovDeg);
  command->add_option("--size", arguments->size, "Image size WxH")->capture_default_str();
  command->add_option("--out", arguments->out, "Output PNG")->required();
  command->add_flag("--reference", arguments->reference, "Ray cast with Embree instead of rasterising with OpenGL");
  command->add_flag("--wire", arguments->wireframe, "Overlay triangle edges");
  command->add_option("--tau", arguments->tauPx, "Draw the LOD mesh within this screen-space error (pixels)")
      ->check(numberIn(rules::kTauPx));
  command->add_option("--debug", arguments->debug, "Colouring: lod (blocks by quadtree level), dikes, wire");
  command->callback([arguments, &exitCode] { exitCode = runRender(*arguments); });
}

}  // namespace polder::cli
