// A scene as plain data: the terrain, the models, the nodes that show them, the LOD policy
// and the camera. buildScene (polder/scene/build_scene.hpp) reads the files it names and
// makes the scene; a scene file (docs/scene_format.md) maps onto it key by key, and the
// builder's errors name the keys: "terrain.crop", "models.NAME", "nodes[i].parent", ...
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include <glm/glm.hpp>

#include <polder/camera.hpp>
#include <polder/mesh/triangle_mesh.hpp>
#include <polder/scene/pose.hpp>
#include <polder/scene/scene.hpp>
#include <polder/terrain/dem.hpp>

namespace polder::scene {

// A DEM file and what to keep of it.
struct DemDescription {
  std::filesystem::path file;
  terrain::DemOptions options;            // spacing, height scale, ...
  std::optional<glm::ivec2> cropSamples;  // keep the central width x height samples
};

struct TerrainDescription {
  DemDescription dem;
  int blockK = 5;  // blocks of 2^k + 1 samples (TerrainEngineOptions::blockK)
};

// An OBJ or PLY file; `bakeTexture` (when not empty) is sampled at the mesh's texture
// coordinates into its vertex colours.
struct MeshFileDescription {
  std::filesystem::path file;
  std::filesystem::path bakeTexture;
};

// How a model's triangles split into regions (polder/mesh/progressive_mesh_build.hpp).
struct RegionsDescription {
  enum class Kind { Single, Automatic, Grid };
  Kind kind = Kind::Single;
  std::uint32_t count = 1;             // Automatic: that many compact regions
  std::uint32_t gridX = 1, gridY = 1;  // Grid: over the two longest axes
};

enum class ProgressiveMeshBuilder { Collapse, Cluster };

struct ModelDescription {
  std::string name;
  // A mesh file, a DEM as one mesh (two triangles per cell), or a mesh already in memory.
  std::variant<MeshFileDescription, DemDescription, mesh::TriangleMesh> shape;
  RegionsDescription regions;
  ProgressiveMeshBuilder builder = ProgressiveMeshBuilder::Collapse;
};

// `count` copies of a node, named NAME#k when there is more than one; copy k is shifted by
// k steps: orbit phase, radius and period, and height.
struct NodeRepeat {
  int count = 1;
  double phaseStepDeg = 0.0;
  double radiusStep = 0.0;
  double periodStepS = 0.0;
  double heightStep = 0.0;
};

struct NodeDescription {
  std::string name;
  std::string parent;  // an earlier node's name (a copy's: NAME#k); empty: the root
  std::string model;   // a model's name; empty: the node only carries a transform
  Pose pose;
  Animation animation;
  glm::vec3 tint{1.0f};
  bool tintRegions = false;
  NodeRepeat repeat;
};

struct CameraPathDescription {
  enum class Kind { Static, Flyover, Orbit, File };
  Kind kind = Kind::Static;  // Static: the lens's own pose
  double altitudeM = 300.0;  // Flyover and Orbit, over the terrain (which they need)
  double speedMps = 150.0;
  std::filesystem::path file;  // File: "t x y z yaw pitch" lines (CameraPath::parse)
};

struct SceneDescription {
  std::optional<TerrainDescription> terrain;
  std::vector<ModelDescription> models;  // names unique
  std::vector<NodeDescription> nodes;    // parents before children
  SceneOptions lod;
  Camera lens;  // viewport, field of view and the static pose; buildScene fits the clip planes
  CameraPathDescription cameraPath;
  int frames = 300;  // the scene's own length, at 60 frames per second
};

}  // namespace polder::scene
