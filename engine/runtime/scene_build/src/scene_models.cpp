#include "scene_models.hpp"

#include <polder/mesh/cluster_builder.hpp>
#include <polder/mesh/collapse_builder.hpp>
#include <polder/mesh/progressive_mesh_build.hpp>
#include <polder/mesh_io/mesh_file.hpp>
#include <polder/scene/heightfield_mesh.hpp>
#include <polder/terrain/dem_reader.hpp>
#include <polder/terrain/heightfield_crop.hpp>

namespace polder::scene::detail {
namespace {

Result<mesh::TriangleMesh> readShape(const ModelDescription& model, const std::string& where) {
  if (const auto* file = std::get_if<MeshFileDescription>(&model.shape)) {
    mesh_io::MeshReadOptions options;
    options.bakeTexture = file->bakeTexture;
    auto read = mesh_io::readMesh(file->file, options);
    if (!read) return errorAt(where, read.error());
    return read;
  }
  if (const auto* dem = std::get_if<DemDescription>(&model.shape)) {
    auto field = readDemDescription(*dem, where);
    if (!field) return field.error();
    return heightfieldMesh(*field);
  }
  return std::get<mesh::TriangleMesh>(model.shape);
}

Result<mesh::RegionPartition> partitionOf(const ModelDescription& model, const mesh::TriangleMesh& shape,
                                          const std::string& where) {
  const RegionsDescription& regions = model.regions;
  switch (regions.kind) {
    case RegionsDescription::Kind::Single:
      return mesh::singleRegion();
    case RegionsDescription::Kind::Automatic:
      if (regions.count < 1) return errorAt(where + ".regions", "needs at least 1 region");
      return mesh::automaticPartition(shape.positions, regions.count);
    case RegionsDescription::Kind::Grid:
      if (regions.gridX < 1 || regions.gridY < 1)
        return errorAt(where + ".regions", "a grid needs at least 1 x 1 cells");
      return mesh::gridPartition(shape.positions, {regions.gridX, regions.gridY, 1});
  }
  return errorAt(where + ".regions", "unknown kind of partition");
}

}  // namespace

Error errorAt(const std::string& where, const Error& error) {
  return makeError(error.kind, where + ": " + error.message);
}

Error errorAt(const std::string& where, const std::string& problem) {
  return makeError(ErrorKind::InvalidData, where + ": " + problem);
}

Result<terrain::Heightfield> readDemDescription(const DemDescription& dem, const std::string& where) {
  auto read = terrain::readDem(dem.file, dem.options);
  if (!read) return errorAt(where, read.error());
  if (!dem.cropSamples) return std::move(read->field);
  auto cropped = terrain::cropCentre(read->field, dem.cropSamples->x, dem.cropSamples->y);
  if (!cropped) return errorAt(where + ".crop", cropped.error().message);
  return cropped;
}

Result<std::shared_ptr<const MeshModel>> buildModel(const ModelDescription& model, std::size_t& triangles,
                                                    const SceneBuildProgress& progress) {
  const std::string where = "models." + model.name;
  auto shape = readShape(model, where);
  if (!shape) return shape.error();
  if (shape->triangleCount() == 0) return errorAt(where, "the mesh has no triangles");
  triangles = shape->triangleCount();
  auto partition = partitionOf(model, *shape, where);
  if (!partition) return partition.error();

  const std::string stage = "building " + model.name;
  const auto report = [&](double fraction) {
    if (progress) progress(stage, float(fraction));
  };
  report(0.0);
  Result<mesh::ProgressiveMesh> progressive = errorAt(where + ".builder", "unknown builder");
  if (model.builder == ProgressiveMeshBuilder::Collapse) {
    mesh::CollapseOptions options;
    options.progress = report;
    progressive = mesh::buildProgressiveMesh(*shape, *partition, options);
  } else if (model.builder == ProgressiveMeshBuilder::Cluster) {
    mesh::ClusterOptions options;
    options.progress = report;
    progressive = mesh::buildProgressiveMesh(*shape, *partition, options);
  }
  if (!progressive) return errorAt(where, progressive.error());
  return std::make_shared<const MeshModel>(model.name, std::move(*progressive));
}

}  // namespace polder::scene::detail
