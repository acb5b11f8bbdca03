// Scene files (docs/scene_format.md): terrain, mesh models, nodes with transforms and
// animation, the camera and the LOD settings, as JSON. Reading maps the file onto a scene
// description (polder/scene/scene_description.hpp); loading also builds it, with progress.
#pragma once

#include <filesystem>
#include <string_view>

#include <polder/result.hpp>
#include <polder/scene/build_scene.hpp>
#include <polder/scene/scene_description.hpp>

namespace polder::cli {

// Errors name the file and the key ("scene.json: nodes[3].parent: ...").
Result<scene::SceneDescription> readSceneFile(const std::filesystem::path& file);

// The text of a scene file; `file` names it in errors and is the folder paths resolve from.
Result<scene::SceneDescription> parseSceneText(std::string_view text, const std::filesystem::path& file);

// readSceneFile, then scene::buildScene with a progress bar per stage.
Result<scene::BuiltScene> loadSceneFile(const std::filesystem::path& file);

}  // namespace polder::cli
