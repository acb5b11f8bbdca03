// Building a scene from its description: what the files and shapes become, the copies of a
// repeated node, the camera and style fitted to the scene, progress, and errors that name the
// part of the description at fault.
#include <polder/scene/build_scene.hpp>

#include <cmath>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "generated_terrain.hpp"
#include "mesh_test_shapes.hpp"
#include "polder/mesh_io/mesh_file.hpp"
#include "polder/terrain/image_writer.hpp"
#include "test_support.hpp"

namespace polder::scene {
namespace {

// A generated 129 x 129 DEM at 30 m, written as a PNG.
std::filesystem::path writeDem(const test::ScratchDir& dir) {
  const std::filesystem::path file = dir.file("relief.png");
  EXPECT_TRUE(terrain::writeHeightPng16(file, test::generatedTerrain(129, 4)).ok());
  return file;
}

SceneDescription terrainOnly(const std::filesystem::path& dem) {
  SceneDescription description;
  description.terrain = TerrainDescription{DemDescription{dem, {}, std::nullopt}, 4};
  description.terrain->dem.options.spacingM = 30.0;
  description.lens.widthPx = 160;
  description.lens.heightPx = 120;
  description.lens.position = {100.0, 200.0, 900.0};
  return description;
}

ModelDescription sphereModel(const std::string& name) {
  ModelDescription model;
  model.name = name;
  model.shape = test::bumpySphere(10, 16);
  model.regions.kind = RegionsDescription::Kind::Automatic;
  model.regions.count = 3;
  return model;
}

TEST(BuildScene, BuildsTerrainModelsAndRepeatedNodes) {
  test::ScratchDir dir;
  const std::filesystem::path dem = writeDem(dir);
  const mesh::TriangleMesh grid = test::bumpyGrid(8);
  ASSERT_TRUE(mesh_io::writeMesh(dir.file("grid.obj"), grid).ok());

  SceneDescription description = terrainOnly(dem);
  description.models.push_back(sphereModel("ball"));
  ModelDescription sheet;
  sheet.name = "sheet";
  sheet.shape = MeshFileDescription{dir.file("grid.obj"), {}};
  sheet.builder = ProgressiveMeshBuilder::Cluster;
  sheet.regions.kind = RegionsDescription::Kind::Grid;
  sheet.regions.gridX = 2;
  sheet.regions.gridY = 2;
  description.models.push_back(sheet);
  ModelDescription ridge;
  ridge.name = "ridge";
  ridge.shape = DemDescription{dem, {}, glm::ivec2(17, 9)};
  description.models.push_back(ridge);

  NodeDescription flock;
  flock.name = "flock";
  flock.model = "ball";
  flock.animation.kind = Animation::Kind::Orbit;
  flock.animation.radius = 100.0;
  flock.repeat = NodeRepeat{4, 90.0, 10.0, 0.5, 2.0};
  description.nodes.push_back(flock);
  NodeDescription rider;
  rider.name = "rider";
  rider.parent = "flock#2";  // a copy's name
  rider.model = "sheet";
  description.nodes.push_back(rider);
  NodeDescription hill;
  hill.name = "hill";
  hill.model = "ridge";
  description.nodes.push_back(hill);
  description.lod.budgetTriangles = 5000;
  description.cameraPath.kind = CameraPathDescription::Kind::Flyover;
  description.frames = 42;

  std::set<std::string> stages;
  auto built = buildScene(description, [&](std::string_view stage, float fraction) {
    stages.insert(std::string(stage));
    EXPECT_GE(fraction, 0.0f);
    EXPECT_LE(fraction, 1.0f);
  });
  ASSERT_TRUE(built.ok()) << built.error().message;
  EXPECT_EQ(stages, (std::set<std::string>{"preparing blocks", "building ball", "building sheet", "building ridge"}));

  Scene& scene = *built->scene;
  ASSERT_NE(scene.terrain(), nullptr);
  EXPECT_EQ(scene.terrain()->layout().k(), 4);  // blocks of 17 samples
  ASSERT_EQ(scene.nodeCount(), 6u);
  for (int c = 0; c < 4; ++c) {
    const SceneNode& copy = scene.node(c);
    EXPECT_EQ(copy.name, "flock#" + std::to_string(c));
    EXPECT_EQ(copy.model, 0);
    EXPECT_NEAR(copy.animation.phase, glm::radians(90.0) * c, 1e-12);
    EXPECT_DOUBLE_EQ(copy.animation.radius, 100.0 + 10.0 * c);
    EXPECT_DOUBLE_EQ(copy.animation.periodS, 10.0 + 0.5 * c);
    EXPECT_DOUBLE_EQ(copy.pose.translation.z, 2.0 * c);
  }
  EXPECT_EQ(scene.node(4).name, "rider");
  EXPECT_EQ(scene.node(4).parent, 2);
  EXPECT_EQ(scene.model(1).mesh().regionCount(), 4u);
  EXPECT_GE(scene.model(0).mesh().regionCount(), 3u);  // at least the count asked for
  EXPECT_EQ(scene.options().budgetTriangles, 5000u);
  const std::size_t ballTriangles = test::bumpySphere(10, 16).triangleCount();
  EXPECT_EQ(built->meshTriangles, 4 * ballTriangles + grid.triangleCount() + 2u * 16u * 8u);

  // The terrain as read, the camera fitted to it, 60 frames per second along the flyover.
  ASSERT_NE(built->terrain, nullptr);
  EXPECT_EQ(built->terrain->width, 129);
  EXPECT_EQ(built->frames, 42);
  const double extent = std::hypot(128 * 30.0, 128 * 30.0);
  EXPECT_DOUBLE_EQ(built->lens.farM, 4.0 * extent);
  EXPECT_DOUBLE_EQ(built->lens.nearM, std::max(0.05, extent * 1e-5));
  const auto [low, high] = built->terrain->heightRange();
  EXPECT_EQ(built->style.minHeightM, low);
  EXPECT_EQ(built->style.maxHeightM, high);
  EXPECT_GT(built->style.fogDensity, 0.0f);
  ASSERT_TRUE(built->path.has_value());
  const Camera at30 = built->cameraAtFrame(30);
  EXPECT_EQ(at30.position, built->path->at(0.5).position);
  EXPECT_EQ(at30.widthPx, 160);
  EXPECT_EQ(at30.farM, built->lens.farM);
  const SceneStats& stats = scene.update(at30, 0.5);
  EXPECT_GT(stats.triangles(), 0u);
  EXPECT_LE(stats.triangles(), 5000u);
}

TEST(BuildScene, ObjectsAloneWithAStaticOrRecordedCamera) {
  test::ScratchDir dir;
  SceneDescription description;
  description.models.push_back(sphereModel("ball"));
  NodeDescription node;
  node.name = "ball";
  node.model = "ball";
  description.nodes.push_back(node);
  description.lens.position = {0.0, -5000.0, 0.0};
  auto still = buildScene(description);
  ASSERT_TRUE(still.ok()) << still.error().message;
  EXPECT_EQ(still->scene->terrain(), nullptr);
  EXPECT_FALSE(still->path.has_value());
  EXPECT_EQ(still->cameraAtFrame(100).position, description.lens.position);
  EXPECT_DOUBLE_EQ(still->lens.farM, 4.0 * 20000.0);  // the extent: 4 x the camera's distance; far: 4 x that
  EXPECT_EQ(still->style.maxHeightM, 1.0f);

  std::ofstream(dir.file("path.txt")) << "0 0 0 100 0 0\n2 0 0 300 90 -10\n";
  description.cameraPath.kind = CameraPathDescription::Kind::File;
  description.cameraPath.file = dir.file("path.txt");
  auto recorded = buildScene(description);
  ASSERT_TRUE(recorded.ok()) << recorded.error().message;
  ASSERT_TRUE(recorded->path.has_value());
  EXPECT_NEAR(recorded->cameraAtFrame(60).position.z, 200.0, 1e-9);
}

std::string failure(const SceneDescription& description) {
  auto built = buildScene(description);
  return built.ok() ? std::string("(built)") : built.error().message;
}

TEST(BuildScene, ErrorsNameThePartOfTheDescription) {
  test::ScratchDir dir;
  const std::filesystem::path dem = writeDem(dir);
  SceneDescription description;
  description.models.push_back(sphereModel("ball"));

  SceneDescription unknownModel = description;
  unknownModel.nodes.push_back(NodeDescription{.name = "a", .model = "bunny"});
  EXPECT_EQ(failure(unknownModel), "nodes[0].model: no model named 'bunny'");

  SceneDescription unknownParent = description;
  unknownParent.nodes.push_back(NodeDescription{.name = "a"});
  unknownParent.nodes.push_back(NodeDescription{.name = "b", .parent = "c"});
  EXPECT_EQ(failure(unknownParent), "nodes[1].parent: no earlier node named 'c'");

  SceneDescription twice = description;
  twice.models.push_back(sphereModel("ball"));
  EXPECT_EQ(failure(twice), "models.ball: a second model of this name");

  SceneDescription flyover = description;
  flyover.cameraPath.kind = CameraPathDescription::Kind::Flyover;
  EXPECT_EQ(failure(flyover), "camera.path: flyover and orbit need a terrain");

  SceneDescription noPath = description;
  noPath.cameraPath.kind = CameraPathDescription::Kind::File;
  noPath.cameraPath.file = dir.file("absent.txt");
  EXPECT_NE(failure(noPath).find("camera.path: " + dir.file("absent.txt").string() + ": the file does not exist"),
            std::string::npos)
      << failure(noPath);
  noPath.cameraPath.file = dir.path();
  EXPECT_NE(failure(noPath).find("is a directory"), std::string::npos) << failure(noPath);

  SceneDescription missingMesh = description;
  missingMesh.models[0].shape = MeshFileDescription{dir.file("missing.obj"), {}};
  auto missing = buildScene(missingMesh);
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().kind, ErrorKind::Io);
  EXPECT_EQ(missing.error().message.rfind("models.ball: ", 0), 0u) << missing.error().message;
  EXPECT_NE(missing.error().message.find("missing.obj"), std::string::npos);

  SceneDescription empty = description;
  empty.models[0].shape = mesh::TriangleMesh{};
  EXPECT_EQ(failure(empty), "models.ball: the mesh has no triangles");

  SceneDescription badCrop = terrainOnly(dem);
  badCrop.terrain->dem.cropSamples = glm::ivec2(500, 500);
  EXPECT_EQ(failure(badCrop).rfind("terrain.crop: ", 0), 0u) << failure(badCrop);

  SceneDescription noFrames = description;
  noFrames.frames = 0;
  EXPECT_EQ(failure(noFrames), "frames: must be at least 1");

  SceneDescription noCopies = description;
  noCopies.nodes.push_back(NodeDescription{.name = "a", .repeat = NodeRepeat{0}});
  EXPECT_EQ(failure(noCopies), "nodes[0].repeat.count: must be at least 1");
}

}  // namespace
}  // namespace polder::scene
