// Polder for a host program, in one include (CMake target polder::engine).
//
//   auto dem = polder::terrain::readDem("terrain.tif");          // or terrain::generateTerrain
//   auto field = std::make_shared<const polder::terrain::Heightfield>(std::move(dem->field));
//   auto engine = polder::TerrainEngine::create(field);          // Result: check engine.ok()
//   const polder::TerrainFrame& frame = (*engine)->update(camera);  // every frame
//   // Either draw with Polder's GL renderer in the host's current context ...
//   auto renderer = polder::render::Renderer::create(glfwGetProcAddress);
//   polder::TerrainDrawer drawer(**renderer);
//   drawer.sync(frame);
//   (*renderer)->beginFrame(camera, polder::defaultTerrainStyle(*field));
//   drawer.draw(frame);
//   (*renderer)->endFrame();
//   // ... or keep the pieces in the host's own renderer: upload frame.pieces[i] for i in
//   // frame.created and frame.changed, free frame.retired, draw frame.pieces with one
//   // matrix (polder/grid_mesh.hpp, polder/terrain_frame.hpp).
//
// Mesh objects go through polder::scene::Scene, which owns the terrain engine and splits one
// triangle budget over terrain blocks and object regions. Parts whose third-party library a
// build or an install left out (OpenImageIO, Embree, Assimp, OpenGL) are simply not here:
// each comes with its own component (find_package(Polder CONFIG COMPONENTS ...)).
#pragma once

#include <polder/camera.hpp>
#include <polder/camera_path.hpp>
#include <polder/grid_mesh.hpp>
#include <polder/result.hpp>
#include <polder/terrain/generator.hpp>
#include <polder/terrain/heightfield.hpp>
#include <polder/terrain_engine.hpp>
#include <polder/terrain_frame.hpp>
#include <polder/terrain_style.hpp>

#if __has_include(<polder/terrain/dem_reader.hpp>)  // polder::terrain_io (OpenImageIO)
#include <polder/terrain/dem_reader.hpp>
#endif
#if __has_include(<polder/scene/scene.hpp>)  // polder::scene
#include <polder/scene/scene.hpp>
#endif
#if __has_include(<polder/terrain_drawer.hpp>)  // polder::terrain_draw (OpenGL)
#include <polder/render/renderer.hpp>
#include <polder/terrain_drawer.hpp>
#endif
#if __has_include(<polder/query/query_scene.hpp>)  // polder::query (Embree)
#include <polder/query/query_scene.hpp>
#endif
