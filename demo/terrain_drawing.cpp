#include "terrain_drawing.hpp"

#include <algorithm>
#include <cmath>

#include <polder/terrain/full_resolution_mesh.hpp>

namespace polder::cli {

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

Result<TerrainDebugView> parseDebugView(const std::string& text) {
  if (text.empty() || text == "none") return TerrainDebugView::None;
  if (text == "lod") return TerrainDebugView::Lod;
  if (text == "dikes") return TerrainDebugView::Dikes;
  if (text == "wire") return TerrainDebugView::Wire;
  return makeError(ErrorKind::InvalidArgument, "--debug must be lod, dikes or wire, not '" + text + "'");
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
