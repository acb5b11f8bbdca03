#include "scene_file.hpp"

#include <cmath>
#include <limits>
#include <optional>

#include <nlohmann/json.hpp>

#include <polder/file_contents.hpp>

#include "cli_support.hpp"
#include "number_rules.hpp"

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

// Whether a JSON value is a number that keeps the rule.
bool isNumberIn(const json& value, const NumberRule& rule) {
  return value.is_number() && bool(checkNumber(value.get<double>(), rule, ""));
}

// value[key] under the rule the command line applies to the same quantity; `fallback` when
// the key is absent.
Result<double> numberOf(const SceneReader& reader, const json& value, const char* key, double fallback,
                        const NumberRule& rule, const std::string& where) {
  const std::string at = where.empty() ? std::string(key) : where + "." + key;
  if (!value.is_object() || !value.contains(key)) return fallback;
  if (!isNumberIn(value[key], rule)) return reader.error(at, "must be " + describe(rule));
  return value[key].get<double>();
}

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
    if (!value[k].is_number() || !std::isfinite(value[k].get<double>()))
      return reader.error(where, "not a finite number");
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

// "spacing", "z_scale" and "crop" beside a "dem": the DEM options and the central samples kept.
Result<scene::DemDescription> demOf(const SceneReader& reader, const json& value, const std::string& where) {
  if (!value.contains("dem") || !value["dem"].is_string()) return reader.error(where, "needs a \"dem\" file");
  scene::DemDescription dem;
  dem.file = reader.resolve(value["dem"]);
  if (value.contains("spacing")) {
    auto spacing = numberOf(reader, value, "spacing", 1.0, rules::kSpacingM, where);
    if (!spacing) return spacing.error();
    dem.options.spacingM = *spacing;
  }
  auto zScale = numberOf(reader, value, "z_scale", 1.0, rules::kZScale, where);
  if (!zScale) return zScale.error();
  if (*zScale == 0.0) return reader.error(where + ".z_scale", "must not be 0");
  dem.options.zScale = *zScale;
  if (value.contains("crop")) {
    const json& crop = value["crop"];
    constexpr NumberRule kCropSamples{2.0, 2147483647.0, true, false, "samples"};
    if (!crop.is_array() || crop.size() != 2 || !isNumberIn(crop[0], kCropSamples) ||
        !isNumberIn(crop[1], kCropSamples))
      return reader.error(where + ".crop", "expected [width, height], each " + describe(kCropSamples));
    dem.cropSamples = glm::ivec2(crop[0].get<int>(), crop[1].get<int>());
  }
  return dem;
}

Result<scene::ModelDescription> modelOf(const SceneReader& reader, const std::string& name, const json& value) {
  const std::string where = "models." + name;
  if (!value.is_object()) return reader.error(where, "expected an object");
  scene::ModelDescription model;
  model.name = name;
  if (value.contains("file")) {
    if (!value["file"].is_string()) return reader.error(where + ".file", "expected a path");
    scene::MeshFileDescription file;
    file.file = reader.resolve(value["file"]);
    if (value.contains("texture")) file.bakeTexture = reader.resolve(value["texture"].get<std::string>());
    model.shape = std::move(file);
  } else if (value.contains("dem")) {
    auto dem = demOf(reader, value, where);
    if (!dem) return dem.error();
    model.shape = std::move(*dem);
  } else {
    return reader.error(where, "a model needs a \"file\" (OBJ/PLY) or a \"dem\"");
  }
  if (value.contains("regions")) {
    const json& regions = value["regions"];
    constexpr NumberRule kGridCells{1.0, 1000.0, true, false, ""};
    if (isNumberIn(regions, rules::kRegions)) {
      model.regions.kind = scene::RegionsDescription::Kind::Automatic;
      model.regions.count = regions.get<std::uint32_t>();
    } else if (regions.is_array() && regions.size() == 2 && isNumberIn(regions[0], kGridCells) &&
               isNumberIn(regions[1], kGridCells)) {
      model.regions.kind = scene::RegionsDescription::Kind::Grid;
      model.regions.gridX = regions[0].get<std::uint32_t>();
      model.regions.gridY = regions[1].get<std::uint32_t>();
    } else {
      return reader.error(where + ".regions", "expected a count (1..100000) or a grid [nx, ny] of 1..1000 each");
    }
  }
  const std::string builder = value.value("builder", std::string("collapse"));
  if (builder == "collapse")
    model.builder = scene::ProgressiveMeshBuilder::Collapse;
  else if (builder == "cluster")
    model.builder = scene::ProgressiveMeshBuilder::Cluster;
  else
    return reader.error(where + ".builder", "unknown builder '" + builder + "' (collapse, cluster)");
  return model;
}

Result<scene::NodeDescription> nodeOf(const SceneReader& reader, const json& value, const std::string& where) {
  if (!value.is_object()) return reader.error(where, "expected an object");
  scene::NodeDescription node;
  node.name = value.value("name", where);
  if (value.contains("model")) node.model = value["model"].get<std::string>();
  if (value.contains("parent")) node.parent = value["parent"].get<std::string>();
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
  constexpr NumberRule kStep{-1e7, 1e7, false, false, ""};
  auto count = numberOf(reader, repeat, "count", 1.0, rules::kRepeat, where + ".repeat");
  auto phase = numberOf(reader, repeat, "phase_step_deg", 0.0, kStep, where + ".repeat");
  auto radius = numberOf(reader, repeat, "radius_step", 0.0, kStep, where + ".repeat");
  auto period = numberOf(reader, repeat, "period_step_s", 0.0, kStep, where + ".repeat");
  auto height = numberOf(reader, repeat, "height_step", 0.0, kStep, where + ".repeat");
  for (const auto* step : {&count, &phase, &radius, &period, &height})
    if (!*step) return step->error();
  node.repeat.count = int(*count);
  node.repeat.phaseStepDeg = *phase;
  node.repeat.radiusStep = *radius;
  node.repeat.periodStepS = *period;
  node.repeat.heightStep = *height;
  return node;
}

Result<scene::SceneOptions> lodOf(const SceneReader& reader, const json& root) {
  const json lod = root.value("lod", json::object());
  scene::SceneOptions options;
  const std::string mode = lod.value("mode", std::string("budget"));
  if (mode != "budget" && mode != "error") return reader.error("lod.mode", "budget or error");
  options.mode = mode == "budget" ? LodMode::TriangleBudget : LodMode::PixelError;
  auto budget = numberOf(reader, lod, "budget", 200000.0, rules::kBudgetTriangles, "lod");
  auto tau = numberOf(reader, lod, "tau", 1.0, rules::kTauPx, "lod");
  auto alpha = numberOf(reader, lod, "alpha", 3.0, rules::kAlpha, "lod");
  for (const auto* number : {&budget, &tau, &alpha})
    if (!*number) return number->error();
  options.budgetTriangles = std::uint64_t(*budget);
  options.tauPx = *tau;
  options.alpha = *alpha;
  return options;
}

// "camera": the lens (size, fov, pose) and the path.
Status cameraOf(const SceneReader& reader, const json& root, scene::SceneDescription& description) {
  const json camera = root.value("camera", json::object());
  auto size = parseImageSize(camera.value("size", std::string("1280x720")));
  if (!size) return reader.error("camera.size", size.error().message);
  Camera& lens = description.lens;
  lens.widthPx = size->first;
  lens.heightPx = size->second;
  auto fov = numberOf(reader, camera, "fov", 60.0, rules::kFovDeg, "camera");
  if (!fov) return fov.error();
  lens.fovYDeg = *fov;
  if (camera.contains("pose")) {
    const json& pose = camera["pose"];
    const auto coordinate = [](const json& n) { return isNumberIn(n, rules::kCoordinateM); };
    if (!pose.is_array() || pose.size() != 5 || !std::all_of(pose.begin(), pose.end(), coordinate))
      return reader.error("camera.pose", "expected [x, y, z, yaw, pitch], each " + describe(rules::kCoordinateM));
    if (!checkNumber(pose[4].get<double>(), rules::kPitchDeg, ""))
      return reader.error("camera.pose", "the pitch must be " + describe(rules::kPitchDeg));
    lens.position = {pose[0].get<double>(), pose[1].get<double>(), pose[2].get<double>()};
    lens.yawDeg = pose[3].get<double>();
    lens.pitchDeg = pose[4].get<double>();
  }
  using Kind = scene::CameraPathDescription::Kind;
  scene::CameraPathDescription& path = description.cameraPath;
  const std::string name = camera.value("path", std::string("static"));
  path.kind = name == "static"    ? Kind::Static
              : name == "flyover" ? Kind::Flyover
              : name == "orbit"   ? Kind::Orbit
                                  : Kind::File;
  if (path.kind == Kind::File) path.file = reader.resolve(name);
  if (path.kind == Kind::Flyover || path.kind == Kind::Orbit) {
    auto altitude = numberOf(reader, camera, "altitude", 300.0, rules::kAltitudeM, "camera");
    auto speed = numberOf(reader, camera, "speed", 150.0, rules::kSpeedMps, "camera");
    if (!altitude) return altitude.error();
    if (!speed) return speed.error();
    path.altitudeM = *altitude;
    path.speedMps = *speed;
  }
  return {};
}

Result<scene::SceneDescription> describe(const SceneReader& reader, const json& root) {
  scene::SceneDescription description;
  if (root.contains("terrain")) {
    auto dem = demOf(reader, root["terrain"], "terrain");
    if (!dem) return dem.error();
    const json block = root["terrain"].value("block", json(33));
    const int k = !block.is_number_integer() ? 0
                  : block == 17              ? 4
                  : block == 33              ? 5
                  : block == 65              ? 6
                  : block == 129             ? 7
                                             : 0;
    if (k == 0) return reader.error("terrain.block", "must be 17, 33, 65 or 129 samples");
    description.terrain = scene::TerrainDescription{std::move(*dem), k};
  }
  if (root.contains("models")) {
    if (!root["models"].is_object()) return reader.error("models", "expected an object of named models");
    for (const auto& [name, value] : root["models"].items()) {
      auto model = modelOf(reader, name, value);
      if (!model) return model.error();
      description.models.push_back(std::move(*model));
    }
  }
  if (root.contains("nodes")) {
    if (!root["nodes"].is_array()) return reader.error("nodes", "expected a list");
    for (std::size_t i = 0; i < root["nodes"].size(); ++i) {
      auto node = nodeOf(reader, root["nodes"][i], "nodes[" + std::to_string(i) + "]");
      if (!node) return node.error();
      description.nodes.push_back(std::move(*node));
    }
  }
  auto lod = lodOf(reader, root);
  if (!lod) return lod.error();
  description.lod = *lod;
  auto frames = numberOf(reader, root, "frames", 300.0, rules::kFrames, "");
  if (!frames) return frames.error();
  description.frames = int(*frames);
  if (Status camera = cameraOf(reader, root, description); !camera) return camera.error();
  return description;
}

}  // namespace

// A scene file describes, it does not hold data: far more than any hand-written scene.
constexpr std::uint64_t kMaxSceneFileBytes = 16 << 20;

Result<scene::SceneDescription> parseSceneText(std::string_view text, const std::filesystem::path& file) {
  SceneReader reader{file, file.parent_path()};
  json root;
  try {
    root = json::parse(text);
  } catch (const json::exception& e) {
    return makeError(ErrorKind::InvalidData, file.string() + ": not valid JSON (" + e.what() + ")");
  }
  if (!root.is_object()) return reader.error("top level", "expected an object");
  try {
    return describe(reader, root);
  } catch (const json::exception& e) {
    return makeError(ErrorKind::InvalidData, file.string() + ": a value has the wrong type (" + e.what() + ")");
  }
}

Result<scene::SceneDescription> readSceneFile(const std::filesystem::path& file) {
  auto text = core::readFileContents(file, kMaxSceneFileBytes);
  if (!text) return makeError(text.error().kind, file.string() + ": " + text.error().message);
  return parseSceneText(*text, file);
}

Result<scene::BuiltScene> loadSceneFile(const std::filesystem::path& file) {
  auto description = readSceneFile(file);
  if (!description) return description.error();
  std::optional<ProgressBar> progress;
  std::string stage;
  auto built = scene::buildScene(*description, [&](std::string_view now, float fraction) {
    if (!progress || now != stage) {
      progress.reset();  // the last stage's bar ends before the next begins
      stage = now;
      progress.emplace(stage);
    }
    progress->update(fraction);
  });
  if (!built) return makeError(built.error().kind, file.string() + ": " + built.error().message);
  return built;
}

}  // namespace polder::cli
