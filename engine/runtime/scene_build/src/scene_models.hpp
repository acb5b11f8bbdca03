// The file-reading half of buildScene: DEMs (cropped) and models' meshes, and the
// progressive meshes built from them.
#pragma once

#include <memory>
#include <string>

#include <polder/result.hpp>
#include <polder/scene/build_scene.hpp>
#include <polder/scene/scene.hpp>
#include <polder/scene/scene_description.hpp>
#include <polder/terrain/heightfield.hpp>

namespace polder::scene::detail {

// Errors name `where` ("terrain", "models.NAME"): "WHERE: problem", or "WHERE.crop: ...".
Result<terrain::Heightfield> readDemDescription(const DemDescription& dem, const std::string& where);

// The model's progressive mesh; `triangles` gets its full-resolution triangle count.
Result<std::shared_ptr<const MeshModel>> buildModel(const ModelDescription& model, std::size_t& triangles,
                                                    const SceneBuildProgress& progress);

// `where` and the problem, with the kind of what failed.
Error errorAt(const std::string& where, const Error& error);
Error errorAt(const std::string& where, const std::string& problem);

}  // namespace polder::scene::detail
