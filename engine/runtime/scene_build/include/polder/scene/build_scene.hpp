// Building a scene from its description (polder/scene/scene_description.hpp): reads the
// terrain's DEM (cropped) into a TerrainEngine, reads or takes each model's mesh and builds
// its progressive mesh over its regions, adds the nodes with their copies, sets the LOD
// policy, makes the camera path, and fits clip planes and a style to what the scene holds.
//
//   auto built = scene::buildScene(description, [](std::string_view stage, float f) { ... });
//   for (int i = 0; i < built->frames; ++i) built->scene->update(built->cameraAtFrame(i), i / 60.0);
//
// Errors name the description's part ("models.ball: ...", "nodes[2].parent: ...") and keep
// the kind of what failed below (Io for a missing file, InvalidData for bad content).
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <string_view>

#include <polder/camera.hpp>
#include <polder/camera_path.hpp>
#include <polder/result.hpp>
#include <polder/scene/scene.hpp>
#include <polder/scene/scene_description.hpp>
#include <polder/terrain/heightfield.hpp>
#include <polder/terrain_style.hpp>

namespace polder::scene {

struct BuiltScene {
  std::unique_ptr<Scene> scene;
  std::shared_ptr<const terrain::Heightfield> terrain;  // null without terrain
  Camera lens;                                          // viewport, field of view, clip planes
  std::optional<CameraPath> path;                       // none: the camera stays at `lens`
  TerrainStyle style;
  int frames = 300;
  std::size_t meshTriangles = 0;  // full-resolution triangles over every node's model

  // The camera of frame `index`, 60 frames per second along the path.
  Camera cameraAtFrame(int index) const;
};

// Called with the stage ("preparing blocks", "building NAME") and the share of it done.
using SceneBuildProgress = std::function<void(std::string_view stage, float fraction)>;

Result<BuiltScene> buildScene(const SceneDescription& description, const SceneBuildProgress& progress = {});

}  // namespace polder::scene
