#include "terrain_drawing.hpp"

#include <algorithm>
#include <cmath>

#include <polder/terrain/full_resolution_mesh.hpp>

namespace polder::cli {

namespace {

TerrainStyle styleFor(double lowM, double highM, double diagonalM) {
  TerrainStyle style;
  style.minHeightM = float(lowM);
  style.maxHeightM = float(std::max(highM, lowM + 1.0));
  style.fogDensity = fogDensityForDistance(float(0.6 * diagonalM));
  return style;
}

}  // namespace

TerrainStyle makeTerrainStyle(const terrain::Dem& dem) {
  return styleFor(dem.info.minM, dem.info.maxM, std::hypot(dem.field.extentX(), dem.field.extentY()));
}

TerrainStyle makeTerrainStyle(const terrain::Heightfield& field) {
  const auto [low, high] = field.heightRange();
  return styleFor(low, high, std::hypot(field.extentX(), field.extentY()));
}

Result<TerrainMeshes> TerrainMeshes::upload(render::Renderer& renderer, const terrain::Heightfield& field) {
  TerrainMeshes meshes;
  for (const MeshData& chunk : terrain::buildFullResolutionMeshes(field)) {
    auto handle = renderer.upload(chunk);
    if (!handle) {
      for (auto uploaded : meshes.m_meshes) renderer.release(uploaded);
      return handle.error();
    }
    meshes.m_meshes.push_back(*handle);
    meshes.m_triangles += chunk.triangleCount();
  }
  return meshes;
}

void TerrainMeshes::draw(render::Renderer& renderer) const {
  for (auto mesh : m_meshes) renderer.draw(mesh);
}

void makeOpaque(RgbaImage& image) {
  for (std::size_t i = 3; i < image.pixels.size(); i += 4) image.pixels[i] = 255;
}

Result<DebugView> parseDebugView(const std::string& text) {
  if (text.empty() || text == "none") return DebugView::None;
  if (text == "lod") return DebugView::Lod;
  if (text == "dikes") return DebugView::Dikes;
  if (text == "wire") return DebugView::Wire;
  return makeError(ErrorKind::InvalidArgument, "--debug must be lod, dikes or wire, not '" + text + "'");
}

void drawTerrainMeshes(render::Renderer& renderer, const TerrainFrameMeshes& meshes) {
  for (const MeshData& mesh : meshes.blocks) (void)renderer.drawTransient(drawItemOf(mesh));
  for (const MeshData& mesh : meshes.dikes) (void)renderer.drawTransient(drawItemOf(mesh));
}

void drawLodFrame(render::Renderer& renderer, const TerrainFrame& frame, const TerrainFrameMeshes& meshes, DebugView debug) {
  if (debug == DebugView::None || debug == DebugView::Wire) return drawTerrainMeshes(renderer, meshes);
  // Quadtree levels: level 0 keeps the terrain's colours, coarser levels shift towards
  // blue, violet, orange...; dikes show in red under --debug dikes.
  static constexpr glm::vec3 kLevelTints[] = {{1.0f, 1.0f, 1.0f}, {0.55f, 0.75f, 1.0f}, {0.85f, 0.55f, 1.0f},
                                              {1.0f, 0.7f, 0.4f}, {0.5f, 1.0f, 0.6f},  {1.0f, 0.5f, 0.5f}};
  for (std::size_t b = 0; b < meshes.blocks.size(); ++b) {
    DrawItem item = drawItemOf(meshes.blocks[b]);
    if (debug == DebugView::Lod) item.tint = kLevelTints[std::min<std::size_t>(frame.blocks[b].node.level, 5)];
    if (debug == DebugView::Dikes) item.tint = glm::vec3(0.8f);
    (void)renderer.drawTransient(item);
  }
  for (const MeshData& tile : meshes.dikes) {
    DrawItem item = drawItemOf(tile);
    if (debug == DebugView::Dikes) item.tint = glm::vec3(1.6f, 0.25f, 0.2f);
    (void)renderer.drawTransient(item);
  }
}

Result<HeadlessRenderer> createHeadlessRenderer(int width, int height) {
  HeadlessRenderer headless;
  auto context = platform::OsmesaContext::create(width, height);
  if (!context) return context.error();
  headless.context = std::move(*context);
  auto renderer = render::Renderer::create(&platform::OsmesaContext::getProcAddress);
  if (!renderer) return renderer.error();
  headless.renderer = std::move(*renderer);
  return headless;
}

}  // namespace polder::cli
