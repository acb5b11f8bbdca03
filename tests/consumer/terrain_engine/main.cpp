// A host program with the terrain engine alone: generate a terrain, run one frame.
#include <cstdio>
#include <memory>

#include <polder/terrain/generator.hpp>
#include <polder/terrain_engine.hpp>

int main() {
  polder::terrain::GeneratorOptions options;
  options.size = 129;
  options.spacingM = 30.0;
  auto field = polder::terrain::generateTerrain(options);
  if (!field) return std::fprintf(stderr, "%s\n", field.error().message.c_str()), 1;
  auto shared = std::make_shared<const polder::terrain::Heightfield>(std::move(*field));
  auto engine = polder::TerrainEngine::create(shared);
  if (!engine) return std::fprintf(stderr, "%s\n", engine.error().message.c_str()), 1;
  polder::Camera camera;
  camera.widthPx = 320;
  camera.heightPx = 240;
  camera.position = {0.5 * shared->extentX(), -0.3 * shared->extentY(), 2500.0};
  camera.pitchDeg = -35.0;
  const polder::TerrainFrame& frame = (*engine)->update(camera);
  std::printf("terrain engine frame: %zu blocks, %zu triangles\n", frame.blocks.size(), frame.stats.triangles());
  return frame.stats.triangles() > 0 ? 0 : 1;
}
