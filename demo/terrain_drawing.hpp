// Drawing a DEM at full resolution in the demo program: the style it is shaded with, its
// meshes on the GPU, and a headless (OSMesa) renderer to draw them with.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <polder/platform/osmesa_context.hpp>
#include <polder/render/renderer.hpp>
#include <polder/terrain/dem.hpp>
#include <polder/terrain_engine.hpp>
#include <polder/terrain_style.hpp>

namespace polder::cli {

// The elevation ramp spans the DEM's height range; fog half-hides terrain at about 60% of
// the DEM's diagonal.
TerrainStyle makeTerrainStyle(const terrain::Dem& dem);
TerrainStyle makeTerrainStyle(const terrain::Heightfield& field);

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

// Debug colouring of LOD frames (`--debug`).
enum class DebugView { None, Lod, Dikes, Wire };
Result<DebugView> parseDebugView(const std::string& text);

// Draws a LOD frame's blocks and dikes in the terrain's own colours.
void drawTerrainMeshes(render::Renderer& renderer, const TerrainFrameMeshes& meshes);

// Draws a LOD frame: its blocks and its dikes, coloured per `debug`.
void drawLodFrame(render::Renderer& renderer, const TerrainFrame& frame, const TerrainFrameMeshes& meshes, DebugView debug);

// An offscreen OpenGL context with a renderer in it.
struct HeadlessRenderer {
  std::unique_ptr<platform::OsmesaContext> context;
  std::unique_ptr<render::Renderer> renderer;
};
Result<HeadlessRenderer> createHeadlessRenderer(int width, int height);

}  // namespace polder::cli
