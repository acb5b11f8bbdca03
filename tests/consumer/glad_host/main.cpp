// A host that defines glad's symbols itself: Polder's renderer must still load GL through
// its own (private) loader and draw, and the host's functions stay the host's.
#include <cstdio>
#include <memory>

#include <polder/platform/osmesa_context.hpp>
#include <polder/render/renderer.hpp>

extern "C" {
extern int host_glad_calls;
int gladLoadGLContext(void* context, void* load);
}

int main() {
  if (gladLoadGLContext(nullptr, nullptr) != 0 || host_glad_calls != 1) {
    return std::fprintf(stderr, "the host's gladLoadGLContext is not the host's\n"), 1;
  }
  auto context = polder::platform::OsmesaContext::create(64, 48);
  if (!context) return std::fprintf(stderr, "%s\n", context.error().message.c_str()), 1;
  auto renderer = polder::render::Renderer::create(&polder::platform::OsmesaContext::getProcAddress);
  if (!renderer) return std::fprintf(stderr, "%s\n", renderer.error().message.c_str()), 1;
  if (host_glad_calls != 1) return std::fprintf(stderr, "Polder called the host's glad\n"), 1;

  polder::MeshData ground;  // a flat square under the camera, counter-clockwise from above
  ground.positions = {
      {-5000.0f, -5000.0f, 0.0f}, {5000.0f, -5000.0f, 0.0f}, {5000.0f, 5000.0f, 0.0f}, {-5000.0f, 5000.0f, 0.0f}};
  ground.indices = {0, 1, 2, 0, 2, 3};
  auto mesh = (*renderer)->upload(ground);
  if (!mesh) return std::fprintf(stderr, "%s\n", mesh.error().message.c_str()), 1;
  polder::Camera camera;
  camera.widthPx = 64;
  camera.heightPx = 48;
  camera.position = {0.0, -200.0, 300.0};
  camera.pitchDeg = -50.0;
  (*renderer)->beginFrame(camera, polder::TerrainStyle{});
  (*renderer)->draw(*mesh);
  const polder::Status frame = (*renderer)->endFrame();
  if (!frame.ok()) return std::fprintf(stderr, "%s\n", frame.error().message.c_str()), 1;
  polder::RgbaImage image;
  const polder::Status read = (*renderer)->readPixels(image);
  if (!read.ok()) return std::fprintf(stderr, "%s\n", read.error().message.c_str()), 1;
  int terrainPixels = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) terrainPixels += image.at(x, y)[3] == 255;
  (*renderer)->release(*mesh);
  renderer->reset();
  std::printf("drew %d of %d pixels with Polder's own glad\n", terrainPixels, image.width * image.height);
  return terrainPixels > 0 ? 0 : 1;
}
