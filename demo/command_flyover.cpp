// polder flyover DEM: the flight over a terrain, in a window (GLFW) or rendered headless to
// PNG frames (--headless --frames N --out DIR). The built-in path is a smooth closed loop
// at --altitude metres above the ground, looking ahead and slightly down.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>

#include <polder/camera_path.hpp>
#include <polder/query/pyramid_surface.hpp>
#include <polder/query/query_scene.hpp>
#include <polder/terrain/image_writer.hpp>
#if POLDER_HAVE_GLFW
#include <polder/platform/glfw_window.hpp>
#endif

#include "cli_support.hpp"
#include "commands.hpp"
#include "memory_budget.hpp"
#include "number_rules.hpp"
#include "terrain_drawing.hpp"

namespace polder::cli {
namespace {

struct FlyoverArguments {
  DemArguments dem;
  bool headless = false;
  int frames = 8;
  double fps = 0.0;  // 0: spread the frames over one loop
  std::string out = "out/flyover";
  std::string size = "1280x720";
  double fovDeg = 60.0;
  double tauPx = 1.0;
  double memoryMb = 0.0;  // 0: the engine's own budgets for block data
  bool fullResolution = false;
  std::string debug;
  FlyoverOptions flight;
};

struct Flight {
  std::shared_ptr<const terrain::Heightfield> field;  // shared with the LOD engine; null when streamed
  std::shared_ptr<const terrain::Pyramid> pyramid;    // streamed by the LOD engine, when the DEM is one
  std::string name;
  DemExtent extent;
  std::unique_ptr<query::TrueSurface> ground;  // under the path and the camera
  CameraPath path;
  TerrainStyle style;
};

// What a flight draws each frame: the LOD frame of a TerrainEngine, or the full-resolution
// meshes uploaded once (--full-res).
class FlightDrawing {
 public:
  static Result<FlightDrawing> create(render::Renderer& renderer,
                                      const std::shared_ptr<const terrain::Heightfield>& field,
                                      const std::shared_ptr<const terrain::Pyramid>& pyramid,
                                      const FlyoverArguments& arguments) {
    FlightDrawing drawing;
    auto debug = parseDebugView(arguments.debug);
    if (!debug) return debug.error();
    drawing.m_debug = *debug;
    if (arguments.fullResolution) {
      auto meshes = TerrainMeshes::upload(renderer, *field);
      if (!meshes) return meshes.error();
      drawing.m_fullResolution = std::move(*meshes);
      return drawing;
    }
    TerrainEngineOptions options;
    options.tauPx = arguments.tauPx;
    auto engine = createEngineWithin(field, pyramid, options, arguments.memoryMb);
    if (!engine) return engine.error();
    drawing.m_engine = std::move(*engine);
    drawing.m_drawer = std::make_unique<TerrainDrawer>(renderer);
    return drawing;
  }

  // Before the renderer's frame: the LOD frame for `camera`, its pieces brought to the GPU.
  // `settled`: every block at its selected level, waiting for the loads (frames rendered to
  // files); otherwise the frame never waits. Returns the triangles the frame draws.
  std::size_t prepare(const Camera& camera, bool settled) {
    if (m_fullResolution) return m_fullResolution->triangleCount();
    m_frame = settled ? &m_engine->updateSettled(camera) : &m_engine->update(camera);
    (void)m_drawer->sync(*m_frame);  // a piece the GPU refused stays undrawn; the flight goes on
    return m_frame->stats.triangles();
  }
  // Between beginFrame and endFrame.
  void draw(render::Renderer& renderer) {
    if (m_fullResolution) return m_fullResolution->draw(renderer);
    m_drawer->draw(*m_frame, m_debug);
  }

  // Bytes the last prepare() sent to the GPU (pieces created or changed); 0 at full resolution.
  std::size_t uploadedBytes() const { return m_drawer ? m_drawer->stats().uploadedBytes : 0; }

  TerrainDebugView debug() const { return m_debug; }

 private:
  std::unique_ptr<TerrainEngine> m_engine;
  std::unique_ptr<TerrainDrawer> m_drawer;  // holds the engine's pieces on the GPU
  const TerrainFrame* m_frame = nullptr;
  std::optional<TerrainMeshes> m_fullResolution;
  TerrainDebugView m_debug = TerrainDebugView::None;
};

Result<Flight> prepareFlight(const FlyoverArguments& arguments) {
  auto pyramid = pyramidToStream(arguments.dem);
  if (!pyramid) return pyramid.error();
  Flight flight;
  flight.pyramid = std::move(*pyramid);
  if (flight.pyramid && !arguments.fullResolution) {
    // Streamed: the ground comes from the pyramid's level-0 tiles, never the whole DEM.
    flight.name = arguments.dem.path;
    flight.extent = DemExtent::of(flight.pyramid->header());
    flight.ground = std::make_unique<query::PyramidSurface>(flight.pyramid);
  } else {
    auto dem = loadDem(arguments.dem);
    if (!dem) return dem.error();
    auto scene = query::QueryScene::create(dem->field);
    if (!scene) return scene.error();
    flight.name = dem->info.path;
    flight.extent = DemExtent::of(dem->field);
    flight.ground = std::move(*scene);
    flight.field = std::make_shared<const terrain::Heightfield>(std::move(dem->field));
  }
  const query::TrueSurface& surface = *flight.ground;
  auto ground = [&surface](double x, double y) { return surface.height(x, y).value_or(0.0); };
  auto path = makeFlyoverLoop(flight.extent.extentX(), flight.extent.extentY(), ground, arguments.flight);
  if (!path) return makeError(path.error().kind, arguments.dem.path + ": " + path.error().message);
  flight.path = std::move(*path);
  flight.style = defaultTerrainStyle(flight.extent.minHeight, flight.extent.maxHeight, flight.extent.extentX(),
                                     flight.extent.extentY());
  return flight;
}

int runHeadless(const FlyoverArguments& arguments, Flight& flight, Camera lens) {
  if (arguments.frames < 1 || arguments.frames > 100000)
    return reportError(makeError(ErrorKind::InvalidArgument, "--frames must be between 1 and 100000"));
  std::error_code error;
  std::filesystem::create_directories(arguments.out, error);
  if (error)
    return reportError(makeError(ErrorKind::Io, arguments.out + ": cannot create the folder: " + error.message()));

  auto headless = createHeadlessRenderer(lens.widthPx, lens.heightPx);
  if (!headless) return reportError(headless.error());
  render::Renderer& renderer = *headless->renderer;
  auto drawing = FlightDrawing::create(renderer, flight.field, flight.pyramid, arguments);
  if (!drawing) return reportError(drawing.error());
  TerrainStyle style = flight.style;
  style.wireframe = drawing->debug() == TerrainDebugView::Wire;

  const double step = arguments.fps > 0.0 ? 1.0 / arguments.fps : flight.path.durationS() / arguments.frames;
  RgbaImage image;
  double renderSeconds = 0.0;
  std::size_t triangles = 0;
  std::size_t uploaded = 0;
  int framesUploadingNothing = 0;
  ProgressBar progress("rendering " + std::to_string(arguments.frames) + " frames");
  for (int frame = 0; frame < arguments.frames; ++frame) {
    const Camera camera = flight.path.at(frame * step).placed(lens);
    const auto start = std::chrono::steady_clock::now();
    triangles += drawing->prepare(camera, true);
    uploaded += drawing->uploadedBytes();
    framesUploadingNothing += drawing->uploadedBytes() == 0;
    renderer.beginFrame(camera, style);
    drawing->draw(renderer);
    if (Status done = renderer.endFrame(); !done) return reportError(done.error());
    if (Status read = renderer.readPixels(image); !read) return reportError(read.error());
    renderSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    makeOpaque(image);
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04d.png", frame);
    if (Status written = terrain::writeRgbaPng(std::filesystem::path(arguments.out) / name, image); !written)
      return reportError(written.error());
    progress.update(float(frame + 1) / float(arguments.frames));
  }
  progress.finish();
  std::printf(
      "flew %.0f s of a %.0f s loop over %s (%d x %d samples), %zu triangles per frame %s\n",
      (arguments.frames - 1) * step, flight.path.durationS(), flight.name.c_str(), flight.extent.width,
      flight.extent.height, triangles / std::size_t(arguments.frames),
      arguments.fullResolution ? "at full resolution" : ("within " + std::to_string(arguments.tauPx) + " px").c_str());
  std::printf("wrote %d frames (%dx%d) to %s/frame_0000.png ... frame_%04d.png; %.0f ms per frame to draw\n",
              arguments.frames, lens.widthPx, lens.heightPx, arguments.out.c_str(), arguments.frames - 1,
              1000.0 * renderSeconds / arguments.frames);
  if (!arguments.fullResolution)
    std::printf("uploaded %.0f KB per frame to the GPU on average; %d of %d frames uploaded nothing\n",
                double(uploaded) / 1024.0 / arguments.frames, framesUploadingNothing, arguments.frames);
  return 0;
}

#if POLDER_HAVE_GLFW
// Interactive flight: the autopilot follows the loop; W/A/S/D, Q/E (down/up) and the mouse
// (hold the right button) take over, Shift flies faster, Space hands back to the autopilot,
// Escape quits. The camera never goes below 5 m above the ground.
int runWindow(const FlyoverArguments& arguments, Flight& flight, Camera lens) {
  platform::GlfwWindowOptions options;
  options.title = "Polder flyover";
  options.width = lens.widthPx;
  options.height = lens.heightPx;
  auto window = platform::GlfwWindow::create(options);
  if (!window) return reportError(window.error());
  auto renderer = render::Renderer::create(&platform::GlfwWindow::getProcAddress);
  if (!renderer) return reportError(renderer.error());
  auto drawing = FlightDrawing::create(**renderer, flight.field, flight.pyramid, arguments);
  if (!drawing) return reportError(drawing.error());
  TerrainStyle style = flight.style;
  style.wireframe = drawing->debug() == TerrainDebugView::Wire;

  using Key = platform::Key;
  bool autopilot = true;
  double flightTime = 0.0;
  Camera camera = flight.path.at(0.0).placed(lens);
  auto last = std::chrono::steady_clock::now();
  while (!(*window)->shouldClose()) {
    (*window)->pollEvents();
    const auto& input = (*window)->input();
    const auto now = std::chrono::steady_clock::now();
    const double dt = std::min(std::chrono::duration<double>(now - last).count(), 0.1);
    last = now;
    if (input.held(Key::Escape)) break;
    const bool steering = input.held(Key::W) || input.held(Key::A) || input.held(Key::S) || input.held(Key::D) ||
                          input.held(Key::Q) || input.held(Key::E) || input.rightButton;
    if (steering) autopilot = false;
    if (input.held(Key::Space)) autopilot = true;
    if (autopilot) {
      flightTime += dt;
      camera = flight.path.at(flightTime).placed(camera);
    } else {
      const double speed =
          arguments.flight.speedMps * ((input.held(Key::LeftShift) || input.held(Key::RightShift)) ? 5.0 : 1.0);
      if (input.rightButton) {
        camera.yawDeg += 0.15 * input.mouseDelta.x;
        camera.pitchDeg = std::clamp(camera.pitchDeg - 0.15 * input.mouseDelta.y, -89.0, 89.0);
      }
      glm::dvec3 move{0.0};
      if (input.held(Key::W)) move += camera.forward();
      if (input.held(Key::S)) move -= camera.forward();
      if (input.held(Key::D)) move += camera.right();
      if (input.held(Key::A)) move -= camera.right();
      if (input.held(Key::E)) move.z += 1.0;
      if (input.held(Key::Q)) move.z -= 1.0;
      if (glm::length(move) > 0.0) camera.position += glm::normalize(move) * speed * dt;
    }
    if (auto ground = flight.ground->height(camera.position.x, camera.position.y))
      camera.position.z = std::max(camera.position.z, *ground + 5.0);

    const glm::ivec2 size = (*window)->framebufferSize();
    if (size.x <= 0 || size.y <= 0) continue;  // minimised
    camera.widthPx = size.x;
    camera.heightPx = size.y;
    const std::size_t triangles = drawing->prepare(camera, false);
    (*renderer)->beginFrame(camera, style);
    drawing->draw(**renderer);
    if (Status done = (*renderer)->endFrame(); !done) return reportError(done.error());
    (*window)->swapBuffers();
    char title[160];
    std::snprintf(title, sizeof title, "Polder flyover - %s - %.0f fps - %zu triangles - %zu KB uploaded",
                  autopilot ? "autopilot" : "manual", dt > 0.0 ? 1.0 / dt : 0.0, triangles,
                  drawing->uploadedBytes() / 1024);
    (*window)->setTitle(title);
  }
  return 0;
}
#endif

int runFlyover(const FlyoverArguments& arguments) {
  auto size = parseImageSize(arguments.size);
  if (!size) return reportError(size.error());
  if (!(arguments.fovDeg > 1.0 && arguments.fovDeg < 179.0))
    return reportError(makeError(ErrorKind::InvalidArgument, "--fov must be between 1 and 179 degrees"));
  if (!(arguments.flight.speedMps > 0.0) || !(arguments.flight.altitudeM >= 0.0) || arguments.fps < 0.0)
    return reportError(
        makeError(ErrorKind::InvalidArgument, "--speed must be positive, --altitude and --fps not negative"));
  auto flight = prepareFlight(arguments);
  if (!flight) return reportError(flight.error());
  Camera lens;
  lens.widthPx = size->first;
  lens.heightPx = size->second;
  lens.fovYDeg = arguments.fovDeg;
  lens.position = flight->path.at(0.0).position;
  fitClipPlanes(lens, flight->extent.extentX(), flight->extent.extentY());
  if (arguments.headless) return runHeadless(arguments, *flight, lens);
#if POLDER_HAVE_GLFW
  return runWindow(arguments, *flight, lens);
#else
  return reportError(makeError(ErrorKind::Unsupported, "this build has no window platform; use --headless"));
#endif
}

}  // namespace

void addFlyoverCommand(CLI::App& app, int& exitCode) {
  auto arguments = std::make_shared<FlyoverArguments>();
  CLI::App* command = app.add_subcommand("flyover", "Fly over a DEM in a window, or render the flight to PNG frames");
  addDemArguments(*command, arguments->dem);
  command->add_flag("--headless", arguments->headless, "Render frames with OSMesa instead of opening a window");
  addNumberOption(*command, "--frames", arguments->frames, "Frames to render headless", rules::kFrames);
  command->add_option("--fps", arguments->fps, "Frames per second of flight time (default: spread over one loop)")
      ->check(numberIn(rules::kFps));
  command->add_option("--out", arguments->out, "Folder for the PNG frames")->capture_default_str();
  command->add_option("--size", arguments->size, "Image or window size WxH")->capture_default_str();
  addNumberOption(*command, "--fov", arguments->fovDeg, "Vertical field of view in degrees", rules::kFovDeg);
  addNumberOption(*command, "--tau", arguments->tauPx, "Screen-space error tolerance of the LOD mesh, pixels",
                  rules::kTauPx);
  addMemoryBudgetOption(*command, arguments->memoryMb);
  command->add_flag("--full-res", arguments->fullResolution, "Draw every sample instead of the LOD mesh");
  command->add_option("--debug", arguments->debug, "Colouring: lod (blocks by quadtree level), dikes, wire");
  addNumberOption(*command, "--altitude", arguments->flight.altitudeM, "Metres above the ground", rules::kAltitudeM);
  addNumberOption(*command, "--speed", arguments->flight.speedMps, "Metres per second", rules::kSpeedMps);
  command->callback([arguments, &exitCode] { exitCode = runFlyover(*arguments); });
}

}  // namespace polder::cli
