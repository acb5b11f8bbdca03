// Drawing in the demo program: a DEM's full-resolution meshes on the GPU, the debug views,
// and a headless (OSMesa) renderer to draw with. LOD frames draw through TerrainDrawer
// (polder/terrain_drawer.hpp).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <polder/platform/osmesa_context.hpp>
#include <polder/render/renderer.hpp>
#include <polder/terrain/dem.hpp>
#include <polder/terrain_drawer.hpp>
#include <polder/terrain_engine.hpp>
#include <polder/terrain_style.hpp>

namespace polder::cli {

// The full-resolution triangulation of a heightfield, uploaded once in chunks.
class TerrainMeshes {
 public:
  static Result<TerrainMeshes> upload(render::Renderer& renderer, const terrain::Heightfield& field);
  void draw(render::Renderer& renderer) const;
  std::size_t triangleCount() const { return m_triangles; }

 private:
  std::vector<render::MeshHandle> m_meshes;
  std::size_t m_triangles = 0;
};

// Alpha carries the terrain/sky mask while rendering; pictures for people are opaque.
void makeOpaque(RgbaImage& image);

// `--debug`: none, lod, dikes or wire.
Result<TerrainDebugView> parseDebugView(const std::string& text);

// An offscreen OpenGL context with a renderer in it.
struct HeadlessRenderer {
  std::unique_ptr<platform::OsmesaContext> context;
  std::unique_ptr<render::Renderer> renderer;
};
Result<HeadlessRenderer> createHeadlessRenderer(int width, int height);

}  // namespace polder::cli
