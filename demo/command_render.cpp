// polder render DEM --camera X,Y,Z,YAW,PITCH --out IMG.png: one frame, headless. OpenGL
// through OSMesa by default; --reference ray casts the same view with Embree.
#include <chrono>
#include <cstdio>
#include <memory>

#include <polder/query/query_scene.hpp>
#include <polder/query/reference_renderer.hpp>
#include <polder/terrain/image_writer.hpp>

#include "cli_support.hpp"
#include "commands.hpp"
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
};

int runRender(const RenderArguments& arguments) {
  auto camera = parseCamera(arguments.camera, arguments.fovDeg, arguments.size);
  if (!camera) return reportError(camera.error());
  if (arguments.reference && arguments.wireframe)
    return reportError(makeError(ErrorKind::InvalidArgument, "--wire draws triangle edges; the --reference ray caster has none"));
  auto dem = loadDem(arguments.dem);
  if (!dem) return reportError(dem.error());
  fitClipPlanes(*camera, dem->field);
  TerrainStyle style = makeTerrainStyle(*dem);
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
    auto meshes = TerrainMeshes::upload(renderer, dem->field);
    if (!meshes) return reportError(meshes.error());
    renderer.beginFrame(*camera, style);
    meshes->draw(renderer);
    if (Status frame = renderer.endFrame(); !frame) return reportError(frame.error());
    if (Status read = renderer.readPixels(image); !read) return reportError(read.error());
    triangles = meshes->triangleCount();
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  makeOpaque(image);
  if (Status written = terrain::writeRgbaPng(arguments.out, image); !written) return reportError(written.error());
  if (arguments.reference)
    std::printf("wrote %s (%dx%d, Embree reference, %.2f s)\n", arguments.out.c_str(), image.width, image.height, seconds);
  else
    std::printf("wrote %s (%dx%d, %zu triangles at full resolution, %.2f s)\n", arguments.out.c_str(), image.width,
                image.height, triangles, seconds);
  return 0;
}

}  // namespace

void addRenderCommand(CLI::App& app, int& exitCode) {
  auto arguments = std::make_shared<RenderArguments>();
  CLI::App* command = app.add_subcommand("render", "Render one frame headless (OpenGL via OSMesa, or Embree reference)");
  addDemArguments(*command, arguments->dem);
  command->add_option("--camera", arguments->camera, "X,Y,Z,YAW,PITCH: metres and degrees (yaw clockwise from north)")
      ->required();
  command->add_option("--fov", arguments->fovDeg, "Vertical field of view in degrees")->capture_default_str();
  command->add_option("--size", arguments->size, "Image size WxH")->capture_default_str();
  command->add_option("--out", arguments->out, "Output PNG")->required();
  command->add_flag("--reference", arguments->reference, "Ray cast with Embree instead of rasterising with OpenGL");
  command->add_flag("--wire", arguments->wireframe, "Overlay triangle edges");
  command->callback([arguments, &exitCode] { exitCode = runRender(*arguments); });
}

}  // namespace polder::cli
