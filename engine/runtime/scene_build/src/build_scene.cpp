#include <polder/scene/build_scene.hpp>

#include <algorithm>
#include <cmath>
#include <map>

#include "scene_models.hpp"

namespace polder::scene {
namespace {

using detail::errorAt;

constexpr double kFramesPerSecond = 60.0;

// The nearest sample's height: the ground a flyover or orbit keeps its altitude above.
double groundAt(const terrain::Heightfield& field, double x, double y) {
  const int i = std::clamp(int(std::lround(x / field.spacingX)), 0, field.width - 1);
  const int j = std::clamp(int(std::lround(y / field.spacingY)), 0, field.height - 1);
  return field.at(i, j);
}

Result<std::unique_ptr<TerrainEngine>> buildTerrain(const TerrainDescription& description, BuiltScene& built,
                                                    const SceneBuildProgress& progress) {
  auto field = detail::readDemDescription(description.dem, "terrain");
  if (!field) return field.error();
  auto shared = std::make_shared<terrain::Heightfield>(std::move(*field));
  built.terrain = shared;
  TerrainEngineOptions options;
  options.blockK = description.blockK;
  const char* stage = "preparing blocks";
  if (progress) progress(stage, 0.0f);
  auto engine = TerrainEngine::create(shared, options, [&](float fraction) {
    if (progress) progress(stage, fraction);
  });
  if (!engine) return errorAt("terrain", engine.error());
  return engine;
}

// Adds the node's copies; `nodeIndex` learns their names, `meshTriangles` their models' triangles.
Status addNodes(const NodeDescription& description, const std::string& where,
                const std::map<std::string, int>& modelIndex, const std::vector<std::size_t>& modelTriangles,
                std::map<std::string, int>& nodeIndex, BuiltScene& built) {
  SceneNode node;
  node.name = description.name;
  if (!description.model.empty()) {
    const auto model = modelIndex.find(description.model);
    if (model == modelIndex.end()) return errorAt(where + ".model", "no model named '" + description.model + "'");
    node.model = model->second;
  }
  if (!description.parent.empty()) {
    const auto parent = nodeIndex.find(description.parent);
    if (parent == nodeIndex.end())
      return errorAt(where + ".parent", "no earlier node named '" + description.parent + "'");
    node.parent = parent->second;
  }
  node.pose = description.pose;
  node.animation = description.animation;
  node.tint = description.tint;
  node.tintRegions = description.tintRegions;
  const NodeRepeat& repeat = description.repeat;
  if (repeat.count < 1) return errorAt(where + ".repeat.count", "must be at least 1");
  for (int c = 0; c < repeat.count; ++c) {
    SceneNode copy = node;
    if (repeat.count > 1) copy.name = node.name + "#" + std::to_string(c);
    copy.animation.phase += glm::radians(repeat.phaseStepDeg) * c;
    copy.animation.radius += repeat.radiusStep * c;
    copy.animation.periodS += repeat.periodStepS * c;
    copy.pose.translation.z += repeat.heightStep * c;
    auto added = built.scene->addNode(copy);
    if (!added) return errorAt(where, added.error().message);
    nodeIndex[copy.name] = *added;
    if (copy.model >= 0) built.meshTriangles += modelTriangles[std::size_t(copy.model)];
  }
  return {};
}

Result<std::optional<CameraPath>> buildCameraPath(const CameraPathDescription& description,
                                                  const terrain::Heightfield* terrain) {
  using Kind = CameraPathDescription::Kind;
  if (description.kind == Kind::Static) return std::optional<CameraPath>();
  if (description.kind == Kind::File) {
    auto path = CameraPath::readFile(description.file);
    if (!path) return errorAt("camera.path", path.error().message);
    return std::optional<CameraPath>(std::move(*path));
  }
  const terrain::Heightfield& field = *terrain;
  auto ground = [&field](double x, double y) { return groundAt(field, x, y); };
  if (description.kind == Kind::Flyover) {
    FlyoverOptions fly;
    fly.altitudeM = description.altitudeM;
    fly.speedMps = description.speedMps;
    auto loop = makeFlyoverLoop(field.extentX(), field.extentY(), ground, fly);
    if (!loop) return loop.error();
    return std::optional<CameraPath>(std::move(*loop));
  }
  OrbitOptions orbit;
  orbit.altitudeM = description.altitudeM;
  orbit.speedMps = description.speedMps;
  auto loop = makeOrbitLoop(field.extentX(), field.extentY(), ground, orbit);
  if (!loop) return loop.error();
  return std::optional<CameraPath>(std::move(*loop));
}

// Clip planes and shading from whatever the scene holds.
void fitLensAndStyle(BuiltScene& built) {
  double extent = built.terrain ? std::hypot(built.terrain->extentX(), built.terrain->extentY()) : 1000.0;
  extent = std::max(extent, 4.0 * glm::length(built.lens.position));
  built.lens.nearM = std::max(0.05, extent * 1e-5);
  built.lens.farM = extent * 4.0;
  if (built.terrain) {  // the elevation ramp over the terrain's heights
    const auto [low, high] = built.terrain->heightRange();
    built.style.minHeightM = float(low);
    built.style.maxHeightM = float(std::max(double(high), double(low) + 1.0));
  } else {  // objects alone: the ramp's top colour, their tints show as they are
    built.style.minHeightM = 0.0f;
    built.style.maxHeightM = 1.0f;
  }
  built.style.fogDensity = fogDensityForDistance(float(0.6 * extent));
}

}  // namespace

Camera BuiltScene::cameraAtFrame(int index) const {
  return path ? path->at(index / kFramesPerSecond).placed(lens) : lens;
}

Result<BuiltScene> buildScene(const SceneDescription& description, const SceneBuildProgress& progress) {
  // What needs no file first.
  using Kind = CameraPathDescription::Kind;
  const Kind pathKind = description.cameraPath.kind;
  if (!description.terrain && (pathKind == Kind::Flyover || pathKind == Kind::Orbit))
    return errorAt("camera.path", "flyover and orbit need a terrain");
  if (description.frames < 1) return errorAt("frames", "must be at least 1");

  BuiltScene built;
  built.lens = description.lens;
  built.frames = description.frames;
  std::unique_ptr<TerrainEngine> engine;
  if (description.terrain) {
    auto created = buildTerrain(*description.terrain, built, progress);
    if (!created) return created.error();
    engine = std::move(*created);
  }
  built.scene = std::make_unique<Scene>(std::move(engine));

  std::map<std::string, int> modelIndex;
  std::vector<std::size_t> modelTriangles;
  for (const ModelDescription& model : description.models) {
    if (modelIndex.contains(model.name)) return errorAt("models." + model.name, "a second model of this name");
    std::size_t triangles = 0;
    auto modelBuilt = detail::buildModel(model, triangles, progress);
    if (!modelBuilt) return modelBuilt.error();
    modelIndex[model.name] = built.scene->addModel(*modelBuilt);
    modelTriangles.push_back(triangles);
  }

  std::map<std::string, int> nodeIndex;
  for (std::size_t i = 0; i < description.nodes.size(); ++i)
    if (Status added = addNodes(description.nodes[i], "nodes[" + std::to_string(i) + "]", modelIndex, modelTriangles,
                                nodeIndex, built);
        !added)
      return added.error();

  if (Status s = built.scene->setOptions(description.lod); !s) return errorAt("lod", s.error().message);
  auto path = buildCameraPath(description.cameraPath, built.terrain.get());
  if (!path) return path.error();
  built.path = std::move(*path);
  fitLensAndStyle(built);
  return built;
}

}  // namespace polder::scene
