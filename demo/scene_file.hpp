// Scene files (docs/scene_format.md): terrain, mesh models, nodes with transforms and
// animation, the camera and the LOD settings, as JSON. Loading builds the scene: it reads the
// DEM and the meshes and builds their progressive meshes (with progress).
#pragma once

#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include <polder/camera.hpp>
#include <polder/camera_path.hpp>
#include <polder/result.hpp>
#include <polder/scene/scene.hpp>
#include <polder/terrain/heightfield.hpp>
#include <polder/terrain_style.hpp>

namespace polder::cli {

struct LoadedScene {
  std::unique_ptr<scene::Scene> scene;
  std::shared_ptr<const terrain::Heightfield> terrain;  // null without terrain
  Camera lens;                                          // size, field of view, clip planes
  std::optional<CameraPath> path;                       // null: the camera stays at `lens`
  TerrainStyle style;
  int frames = 300;
  std::size_t meshTriangles = 0;  // full-resolution triangles over all models' instances
};

Result<LoadedScene> loadSceneFile(const std::filesystem::path& file);

// The camera of frame `index` (60 frames per second of flight).
Camera sceneCamera(const LoadedScene& loaded, int index);

}  // namespace polder::cli
