#include "scene_file.hpp"

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

#include <polder/mesh/cluster_builder.hpp>
#include <polder/mesh/collapse_builder.hpp>
#include <polder/mesh/progressive_mesh_build.hpp>
#include <polder/mesh_io/mesh_file.hpp>
#include <polder/terrain_drawer.hpp>
#include <polder/scene/heightfield_mesh.hpp>
#include <polder/terrain/heightfield_crop.hpp>

#include "cli_support.hpp"
#include "terrain_drawing.hpp"

namespace polder::cli {
namespace {

using nlohmann::json;

// Errors name the scene file and where in it the problem is.
struct SceneReader {
  std::filesystem::path file;
  std::filesystem::path folder;

  Error error(const std::string& where, const std::string& problem) const {
    return makeError(ErrorKind::InvalidData, file.string() + ": " + where + ": " + problem);
  }
  std::filesystem::path resolve(const std::string& path) const {
    const std::filesystem::path p(path);
    return p.is_absolute() ? p : folder / p;
  }
};

Result<glm::dvec3> vec3Of(const SceneReader& reader, const json& value, const std::string& where) {
  if (value.is_number()) {
    const double v = value.get<double>();
    if (!std::isfinite(v)) return reader.error(where, "not a finite number");
    return glm::dvec3(v);
  }
  if (!value.is_array() || value.size() < 2 || value.size() > 3)
    return reader.error(where, "expected [x, y] or [x, y, z]");
  glm::dvec3 out(0.0);
  for (std::size_t k = 0; k < value.size(); ++k) {
    if (!value[k].is_number() || !std::isfinite(value[k].get<double>())) return reader.error(where, "not a finite number");
    out[int(k)] = value[k].get<double>();
  }
  return out;
}

// yaw about z (clockwise from north like the camera), pitch about x, roll about y.
glm::dquat rotationFromDegrees(const glm::dvec3& yawPitchRoll) {
  return glm::angleAxis(glm::radians(-yawPitchRoll.x), glm::dvec3(0, 0, 1)) *
         glm::angleAxis(glm::radians(yawPitchRoll.y), glm::dvec3(1, 0, 0)) *
         glm::angleAxis(glm::radians(yawPitchRoll.z), glm::dvec3(0, 1, 0));
}

Result<scene::Pose> poseOf(const SceneReader& reader, const json& node, const std::string& where) {
  scene::Pose pose;
  if (node.contains("translate")) {
    auto t = vec3Of(reader, node["translate"], where + ".translate");
    if (!t) return t.error();
    pose.translation = *t;
  }
  if (node.contains("rotate_deg")) {
    auto r = vec3Of(reader, node["rotate_deg"], where + ".rotate_deg");
    if (!r) return r.error();
    pose.rotation = rotationFromDegrees(node["rotate_deg"].is_number() ? glm::dvec3(r->x, 0, 0) : *r);
  }
  if (node.contains("scale")) {
    auto s = vec3Of(reader, node["scale"], where + ".scale");
    if (!s) return s.error();
    if (node["scale"].is_array() && node["scale"].size() == 2) s->z = 1.0;
    if (s->x <= 0 || s->y <= 0 || s->z <= 0) return reader.error(where + ".scale", "must be positive");
    pose.scale = *s;
  }
  return pose;
}

Result<scene::Animation> animationOf(const SceneReader& reader, const json& value, const std::string& where) {
  scene::Animation animation;
  if (!value.is_object() || !value.contains("type") || !value["type"].is_string())
    return reader.error(where, "an animation needs a \"type\": spin, orbit or keyframes");
  const std::string type = value["type"];
  auto number = [&](const char* key, double fallback) -> Result<double> {
    if (!value.contains(key)) return fallback;
    if (!value[key].is_number() || !std::isfinite(value[key].get<double>()))
      return reader.error(where + "." + key, "not a finite number");
    return value[key].get<double>();
  };
  if (type == "spin") {
    animation.kind = scene::Animation::Kind::Spin;
    if (value.contains("axis")) {
      auto axis = vec3Of(reader, value["axis"], where + ".axis");
      if (!axis) return axis.error();
      animation.axis = *axis;
    }
    auto rate = number("deg_per_s", 30.0);
    if (!rate) return rate.error();
    animation.degreesPerSecond = *rate;
  } else if (type == "orbit") {
    animation.kind = scene::Animation::Kind::Orbit;
    if (value.contains("centre")) {
      auto centre = vec3Of(reader, value["centre"], where + ".centre");
      if (!centre) return centre.error();
      animation.centre = *centre;
    }
    auto radius = number("radius", 100.0), period = number("period_s", 10.0), phase = number("phase_deg", 0.0);
    if (!radius) return radius.error();
    if (!period) return period.error();
    if (!phase) return phase.error();
    animation.radius = *radius;
    animation.periodS = *period;
    animation.phase = glm::radians(*phase);
  } else if (type == "keyframes") {
    animation.kind = scene::Animation::Kind::Keyframes;
    animation.loop = value.value("loop", true);
    if (!value.contains("keys") || !value["keys"].is_array() || value["keys"].empty())
      return reader.error(where + ".keys", "keyframes need a non-empty \"keys\" list");
    double last = -std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < value["keys"].size(); ++i) {
      const json& key = value["keys"][i];
      const std::string at = where + ".keys[" + std::to_string(i) + "]";
      if (!key.is_object() || !key.contains("t") || !key["t"].is_number())
        return reader.error(at, "a key needs a time \"t\"");
      const double t = key["t"];
      if (!(t > last)) return reader.error(at, "key times must increase");
      last = t;
      auto pose = poseOf(reader, key, at);
      if (!pose) return pose.error();
      animation.keys.push_back(scene::Keyframe{t, *pose});
    }
  } else {
    return reader.error(where + ".type", "unknown animation '" + type + "' (spin, orbit, keyframes)");
  }
  return animation;
}

Result<terrain::Heightfield> demOf(const SceneReader& reader, const json& value, const std::string& where) {
  if (!value.contains("dem") || !value["dem"].is_string()) return reader.error(where, "needs a \"dem\" file");
  DemArguments arguments;
  arguments.path = reader.resolve(value["dem"]).string();
  if (value.contains("spacing")) arguments.spacingM = value["spacing"].get<double>();
  arguments.zScale = value.value("z_scale", 1.0);
  auto dem = loadDem(arguments);
  if (!dem) return dem.error();
  terrain::Heightfield field = std::move(dem->field);
  if (value.contains("crop")) {
    const json& crop = value["crop"];
    if (!crop.is_array() || crop.size() != 2 || !crop[0].is_number_integer() || !crop[1].is_number_integer())
      return reader.error(where + ".crop", "expected [width, height] in samples");
    auto cropped = terrain::cropCentre(field, crop[0].get<int>(), crop[1].get<int>());
    if (!cropped) return reader.error(where + ".crop", cropped.error().message);
    field = std::move(*cropped);
  }
  return field;
}

Result<std::shared_ptr<const scene::MeshModel>> modelOf(const SceneReader& reader, const std::string& name,
                                                        const json& value, std::size_t& triangles) {
  const std::string where = "models." + name;
  if (!value.is_object()) return reader.error(where, "expected an object");
  mesh::TriangleMesh shape;
  if (value.contains("file")) {
    if (!value["file"].is_string()) return reader.error(where + ".file", "expected a path");
    mesh_io::MeshReadOptions options;
    if (value.contains("texture")) options.bakeTexture = reader.resolve(value["texture"].get<std::string>());
    auto read = mesh_io::readMesh(reader.resolve(value["file"]), options);
    if (!read) return read.error();
    shape = std::move(*read);
  } else if (value.contains("dem")) {
    auto field = demOf(reader, value, where);
    if (!field) return field.error();
    shape = scene::heightfieldMesh(*field);
  } else {
    return reader.error(where, "a model needs a \"file\" (OBJ/PLY) or a \"dem\"");
  }
  if (shape.triangleCount() == 0) return reader.error(where, "the mesh has no triangles");
  triangles = shape.triangleCount();
  mesh::RegionPartition partition = mesh::singleRegion();
  if (value.contains("regions")) {
    const json& regions = value["regions"];
    if (regions.is_number_integer() && regions.get<int>() >= 1 && regions.get<int>() <= 100000) {
      partition = mesh::automaticPartition(shape.positions, regions.get<std::uint32_t>());
    } else if (regions.is_array() && regions.size() == 2 && regions[0].is_number_integer() &&
               regions[1].is_number_integer() && regions[0].get<int>() >= 1 && regions[1].get<int>() >= 1) {
      partition = mesh::gridPartition(shape.positions, {regions[0].get<std::uint32_t>(), regions[1].get<std::uint32_t>(), 1});
    } else {
      return reader.error(where + ".regions", "expected a count (1..100000) or a grid [nx, ny]");
    }
  }
  const std::string builder = value.value("builder", std::string("collapse"));
  Result<mesh::ProgressiveMesh> progressive =
      reader.error(where + ".builder", "unknown builder '" + builder + "' (collapse, cluster)");
  {
    ProgressBar progress("building " + name);
    const auto report = [&progress](double f) { progress.update(float(f)); };
    if (builder == "collapse") {
      mesh::CollapseOptions options;
      options.progress = report;
      progressive = mesh::buildProgressiveMesh(shape, partition, options);
    } else if (builder == "cluster") {
      mesh::ClusterOptions options;
      options.progress = report;
      progressive = mesh::buildProgressiveMesh(shape, partition, options);
    }
  }
  if (!progressive) return progressive.error();
  return std::make_shared<const scene::MeshModel>(name, std::move(*progressive));
}

double groundAt(const terrain::Heightfield& field, double x, double y) {
  const int i = std::clamp(int(std::lround(x / field.spacingX)), 0, field.width - 1);
  const int j = std::clamp(int(std::lround(y / field.spacingY)), 0, field.height - 1);
  return field.at(i, j);
}

}  // namespace

Result<LoadedScene> loadSceneFile(const std::filesystem::path& file) {
  SceneReader reader{file, file.parent_path()};
  std::ifstream in(file);
  if (!in) return makeError(ErrorKind::Io, file.string() + ": cannot open the scene file");
  json root;
  try {
    root = json::parse(in);
  } catch (const json::exception& e) {
    return makeError(ErrorKind::InvalidData, file.string() + ": not valid JSON (" + e.what() + ")");
  }
  if (!root.is_object()) return reader.error("top level", "expected an object");

  try {
    LoadedScene loaded;
    std::unique_ptr<TerrainEngine> engine;
    if (root.contains("terrain")) {
      auto field = demOf(reader, root["terrain"], "terrain");
      if (!field) return field.error();
      auto shared = std::make_shared<terrain::Heightfield>(std::move(*field));
      loaded.terrain = shared;
      TerrainEngineOptions options;
      const int block = root["terrain"].value("block", 33);
      options.blockK = block == 17 ? 4 : block == 65 ? 6 : block == 129 ? 7 : 5;
      ProgressBar progress("preparing blocks");
      auto created = TerrainEngine::create(shared, options, [&](float f) { progress.update(f); });
      if (!created) return created.error();
      engine = std::move(*created);
    }
    loaded.scene = std::make_unique<scene::Scene>(std::move(engine));

    std::map<std::string, int> modelIndex;
    std::map<std::string, std::size_t> modelTriangles;
    if (root.contains("models")) {
      if (!root["models"].is_object()) return reader.error("models", "expected an object of named models");
      for (const auto& [name, value] : root["models"].items()) {
        std::size_t triangles = 0;
        auto model = modelOf(reader, name, value, triangles);
        if (!model) return model.error();
        modelIndex[name] = loaded.scene->addModel(*model);
        modelTriangles[name] = triangles;
      }
    }

    std::map<std::string, int> nodeIndex;
    if (root.contains("nodes")) {
      if (!root["nodes"].is_array()) return reader.error("nodes", "expected a list");
      for (std::size_t i = 0; i < root["nodes"].size(); ++i) {
        const json& value = root["nodes"][i];
        const std::string where = "nodes[" + std::to_string(i) + "]";
        if (!value.is_object()) return reader.error(where, "expected an object");
        scene::SceneNode node;
        node.name = value.value("name", where);
        if (value.contains("model")) {
          const std::string model = value["model"];
          if (!modelIndex.contains(model)) return reader.error(where + ".model", "no model named '" + model + "'");
          node.model = modelIndex[model];
        }
        if (value.contains("parent")) {
          const std::string parent = value["parent"];
          if (!nodeIndex.contains(parent)) return reader.error(where + ".parent", "no earlier node named '" + parent + "'");
          node.parent = nodeIndex[parent];
        }
        auto pose = poseOf(reader, value, where);
        if (!pose) return pose.error();
        node.pose = *pose;
        if (value.contains("animation")) {
          auto animation = animationOf(reader, value["animation"], where + ".animation");
          if (!animation) return animation.error();
          node.animation = *animation;
        }
        if (value.contains("tint")) {
          auto tint = vec3Of(reader, value["tint"], where + ".tint");
          if (!tint) return tint.error();
          node.tint = glm::vec3(*tint);
        }
        node.tintRegions = value.value("tint_regions", false);
        // "repeat": copies of an orbiting node, each a little further out and phase-shifted.
        const json repeat = value.value("repeat", json::object());
        const int copies = repeat.value("count", 1);
        if (copies < 1 || copies > 100000) return reader.error(where + ".repeat.count", "must be 1..100000");
        for (int c = 0; c < copies; ++c) {
          scene::SceneNode copy = node;
          if (copies > 1) copy.name = node.name + "#" + std::to_string(c);
          copy.animation.phase += glm::radians(repeat.value("phase_step_deg", 0.0)) * c;
          copy.animation.radius += repeat.value("radius_step", 0.0) * c;
          copy.animation.periodS += repeat.value("period_step_s", 0.0) * c;
          copy.pose.translation.z += repeat.value("height_step", 0.0) * c;
          auto added = loaded.scene->addNode(copy);
          if (!added) return reader.error(where, added.error().message);
          nodeIndex[copy.name] = *added;
          if (copy.model >= 0) {
            for (const auto& [name, index] : modelIndex)
              if (index == copy.model) loaded.meshTriangles += modelTriangles[name];
          }
        }
      }
    }

    const json lod = root.value("lod", json::object());
    scene::SceneOptions options;
    const std::string mode = lod.value("mode", std::string("budget"));
    if (mode != "budget" && mode != "error") return reader.error("lod.mode", "budget or error");
    options.mode = mode == "budget" ? LodMode::TriangleBudget : LodMode::PixelError;
    options.budgetTriangles = lod.value("budget", std::uint64_t(200000));
    options.tauPx = lod.value("tau", 1.0);
    options.alpha = lod.value("alpha", 3.0);
    if (options.budgetTriangles == 0) return reader.error("lod.budget", "must be at least 1");
    if (Status s = loaded.scene->setOptions(options); !s) return reader.error("lod", s.error().message);

    const json camera = root.value("camera", json::object());
    loaded.frames = root.value("frames", 300);
    if (loaded.frames < 1) return reader.error("frames", "must be at least 1");
    auto size = parseImageSize(camera.value("size", std::string("1280x720")));
    if (!size) return reader.error("camera.size", size.error().message);
    loaded.lens.widthPx = size->first;
    loaded.lens.heightPx = size->second;
    loaded.lens.fovYDeg = camera.value("fov", 60.0);
    if (!(loaded.lens.fovYDeg > 1.0 && loaded.lens.fovYDeg < 179.0)) return reader.error("camera.fov", "must lie in 1..179");
    if (camera.contains("pose")) {
      const json& pose = camera["pose"];
      if (!pose.is_array() || pose.size() != 5) return reader.error("camera.pose", "expected [x, y, z, yaw, pitch]");
      loaded.lens.position = {pose[0].get<double>(), pose[1].get<double>(), pose[2].get<double>()};
      loaded.lens.yawDeg = pose[3].get<double>();
      loaded.lens.pitchDeg = pose[4].get<double>();
    }
    const std::string path = camera.value("path", std::string("static"));
    if (path != "static") {
      if (!loaded.terrain && (path == "flyover" || path == "orbit"))
        return reader.error("camera.path", "flyover and orbit need a terrain");
      if (path == "flyover" || path == "orbit") {
        const terrain::Heightfield& field = *loaded.terrain;
        auto ground = [&field](double x, double y) { return groundAt(field, x, y); };
        if (path == "flyover") {
          FlyoverOptions fly;
          fly.altitudeM = camera.value("altitude", 300.0);
          fly.speedMps = camera.value("speed", 150.0);
          loaded.path = makeFlyoverLoop(field.extentX(), field.extentY(), ground, fly);
        } else {
          OrbitOptions orbit;
          orbit.altitudeM = camera.value("altitude", 300.0);
          orbit.speedMps = camera.value("speed", 150.0);
          loaded.path = makeOrbitLoop(field.extentX(), field.extentY(), ground, orbit);
        }
      } else {
        std::ifstream pathFile(reader.resolve(path));
        if (!pathFile) return reader.error("camera.path", "cannot open '" + path + "' (static, flyover, orbit or a file)");
        std::stringstream text;
        text << pathFile.rdbuf();
        auto parsed = CameraPath::parse(text.str());
        if (!parsed) return reader.error("camera.path", parsed.error().message);
        loaded.path = std::move(*parsed);
      }
    }
    // Clip planes and shading from whatever the scene holds.
    double extent = loaded.terrain ? std::hypot(loaded.terrain->extentX(), loaded.terrain->extentY()) : 1000.0;
    extent = std::max(extent, 4.0 * glm::length(loaded.lens.position));
    loaded.lens.nearM = std::max(0.05, extent * 1e-5);
    loaded.lens.farM = extent * 4.0;
    if (loaded.terrain) {
      loaded.style = defaultTerrainStyle(*loaded.terrain);
    } else {  // objects alone: the ramp's top colour, their tints show as they are
      loaded.style.minHeightM = 0.0f;
      loaded.style.maxHeightM = 1.0f;
    }
    loaded.style.fogDensity = fogDensityForDistance(float(0.6 * extent));
    return loaded;
  } catch (const json::exception& e) {
    return makeError(ErrorKind::InvalidData, file.string() + ": a value has the wrong type (" + e.what() + ")");
  }
}

Camera sceneCamera(const LoadedScene& loaded, int index) {
  return loaded.path ? loaded.path->at(index / 60.0).placed(loaded.lens) : loaded.lens;
}

}  // namespace polder::cli
