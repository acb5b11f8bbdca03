// Polder's LOD terrain in the host's own GLFW window: read a DEM, fly east along its middle.
// Usage: embed_window DEM [FRAMES]
#include <GLFW/glfw3.h>

#include <cstdio>
#include <cstdlib>
#include <memory>

#include <polder/polder.hpp>

int main(int argc, char** argv) {
  auto dem = polder::terrain::readDem(argc > 1 ? argv[1] : "terrain.png");
  if (!dem) return std::fprintf(stderr, "%s\n", dem.error().message.c_str()), 1;
  auto field = std::make_shared<const polder::terrain::Heightfield>(std::move(dem->field));
  auto engine = polder::TerrainEngine::create(field);
  if (!engine) return std::fprintf(stderr, "%s\n", engine.error().message.c_str()), 1;
  glfwSetErrorCallback([](int code, const char* text) { std::fprintf(stderr, "GLFW error %d: %s\n", code, text); });
  if (!glfwInit()) return 1;
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  GLFWwindow* window = glfwCreateWindow(1280, 720, "Polder", nullptr, nullptr);
  if (!window) return 1;
  glfwMakeContextCurrent(window);
  {
    auto renderer = polder::render::Renderer::create(glfwGetProcAddress);
    if (!renderer) return std::fprintf(stderr, "%s\n", renderer.error().message.c_str()), 1;
    polder::TerrainDrawer drawer(**renderer);
    const polder::TerrainStyle style = polder::defaultTerrainStyle(*field);
    polder::Camera camera;
    camera.pitchDeg = -20.0, camera.yawDeg = 90.0, camera.farM = 4.0 * (field->extentX() + field->extentY());
    const int frames = argc > 2 ? std::atoi(argv[2]) : 600;
    const double cruiseM = field->heightRange().second + 500.0;
    for (int frame = 0; frame < frames && !glfwWindowShouldClose(window); ++frame) {
      camera.position = {0.2 * field->extentX() + 50.0 * frame, 0.5 * field->extentY(), cruiseM};
      glfwGetFramebufferSize(window, &camera.widthPx, &camera.heightPx);
      const polder::TerrainFrame& terrain = (*engine)->update(camera);
      (void)drawer.sync(terrain);  // uploads only the pieces that are new or changed
      (*renderer)->beginFrame(camera, style);
      drawer.draw(terrain);
      if (polder::Status drawn = (*renderer)->endFrame(); !drawn)
        return std::fprintf(stderr, "%s\n", drawn.error().message.c_str()), 1;
      glfwSwapBuffers(window);
      glfwPollEvents();
    }
    std::printf("drew %d frames, %zu pieces resident\n", frames, drawer.stats().residentPieces);
  }
  glfwTerminate();
  return 0;
}
