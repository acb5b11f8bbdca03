// The scene graph with the allocator at its root: terrain blocks and mesh regions share one
// budget; instances of one model take their own levels; transforms nest and animate.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "allocation_counter.hpp"
#include "mesh_test_shapes.hpp"
#include "polder/mesh/collapse_builder.hpp"
#include "polder/scene/heightfield_mesh.hpp"
#include "polder/scene/scene.hpp"
#include "polder/terrain/generator.hpp"

namespace polder::scene {
namespace {

std::shared_ptr<const MeshModel> model(const mesh::TriangleMesh& shape, const mesh::RegionPartition& partition,
                                       const char* name) {
  auto steps = mesh::buildCollapseSteps(shape, partition);
  EXPECT_TRUE(steps.ok());
  auto pm = mesh::ProgressiveMesh::assemble(shape, partition, *steps);
  EXPECT_TRUE(pm.ok());
  return std::make_shared<MeshModel>(name, std::move(*pm));
}

std::unique_ptr<TerrainEngine> generatedTerrain(int size, std::uint64_t seed) {
  terrain::GeneratorOptions options;
  options.size = size;
  options.seed = seed;
  options.spacingM = 30.0;
  auto field = terrain::generateTerrain(options);
  EXPECT_TRUE(field.ok());
  auto engine = TerrainEngine::create(std::make_shared<terrain::Heightfield>(std::move(*field)));
  EXPECT_TRUE(engine.ok());
  return std::move(*engine);
}

Camera lookingAt(const glm::dvec3& position, double yawDeg, double pitchDeg) {
  Camera camera;
  camera.position = position;
  camera.yawDeg = yawDeg;
  camera.pitchDeg = pitchDeg;
  camera.widthPx = 640;
  camera.heightPx = 480;
  camera.fovYDeg = 60.0;
  camera.nearM = 0.5;
  camera.farM = 1e6;
  return camera;
}

TEST(Pose, NodesNestAndAnimate) {
  Scene scene;
  SceneNode parent;
  parent.name = "carrier";
  parent.pose.translation = {100.0, 0.0, 0.0};
  parent.animation.kind = Animation::Kind::Spin;
  parent.animation.degreesPerSecond = 90.0;
  const int p = *scene.addNode(parent);
  SceneNode child;
  child.name = "rider";
  child.parent = p;
  child.pose.translation = {10.0, 0.0, 0.0};
  child.animation.kind = Animation::Kind::Keyframes;
  child.animation.keys = {Keyframe{0.0, Pose{{10.0, 0.0, 0.0}}}, Keyframe{2.0, Pose{{10.0, 0.0, 4.0}}}};
  child.animation.loop = false;
  const int c = *scene.addNode(child);
  scene.update(lookingAt({0, -50, 0}, 0, 0), 1.0);
  // After 1 s the carrier has turned 90 degrees: the rider's +x offset points along +y,
  // and it is halfway up its keyframed climb.
  const glm::dvec3 rider(scene.worldMatrix(c)[3]);
  EXPECT_NEAR(rider.x, 100.0, 1e-9);
  EXPECT_NEAR(rider.y, 10.0, 1e-9);
  EXPECT_NEAR(rider.z, 2.0, 1e-9);
  scene.update(lookingAt({0, -50, 0}, 0, 0), 5.0);  // past the last key, no loop: stays at the end
  EXPECT_NEAR(glm::dvec3(scene.worldMatrix(c)[3]).z, 4.0, 1e-9);

  Animation orbit;
  orbit.kind = Animation::Kind::Orbit;
  orbit.centre = {5.0, 5.0, 0.0};
  orbit.radius = 3.0;
  orbit.periodS = 8.0;
  const Pose quarter = orbit.evaluate(Pose{{0.0, 0.0, 7.0}}, 2.0);
  EXPECT_NEAR(quarter.translation.x, 5.0, 1e-9);
  EXPECT_NEAR(quarter.translation.y, 8.0, 1e-9);
  EXPECT_NEAR(quarter.translation.z, 7.0, 1e-9);

  SceneNode orphan;
  orphan.parent = 7;
  EXPECT_FALSE(scene.addNode(orphan).ok());
  SceneNode unknownModel;
  unknownModel.model = 3;
  EXPECT_FALSE(scene.addNode(unknownModel).ok());
}

TEST(Scene, InstancesOfOneModelTakeTheirOwnLevels) {
  Scene scene;
  const int sphere = scene.addModel(model(test::bumpySphere(30, 40), mesh::singleRegion(), "sphere"));
  SceneNode near, far;
  near.model = far.model = sphere;
  near.pose.translation = {0.0, 6.0, 0.0};
  far.pose.translation = {0.0, 200.0, 0.0};
  const int n = *scene.addNode(near);
  const int f = *scene.addNode(far);
  SceneOptions options;
  options.budgetTriangles = 1500;
  options.alpha = 1.0;
  ASSERT_TRUE(scene.setOptions(options).ok());
  const SceneStats& stats = scene.update(lookingAt({0, 0, 0}, 0, 0), 0.0);
  EXPECT_EQ(stats.objects, 2u);
  EXPECT_EQ(stats.regions, 2u);
  EXPECT_GT(scene.instance(n).triangleCount(), 4 * scene.instance(f).triangleCount());
  EXPECT_LE(stats.objectTriangles, options.budgetTriangles);
  EXPECT_GE(stats.objectTriangles, options.budgetTriangles - 4);
  EXPECT_EQ(scene.regionAllocation(n, 0) + scene.regionAllocation(f, 0), options.budgetTriangles);
  EXPECT_EQ(scene.objectDrawItems().size(), 2u);
}

// Instances share their model: every draw item reads the model's own vertex table, placed by
// the node's matrix, and an instance holds only its LOD cache.
TEST(Scene, InstancesShareTheModelsVerticesAndHoldOnlyTheirCache) {
  Scene scene;
  auto shared =
      model(test::bumpySphere(30, 40), mesh::gridPartition(test::bumpySphere(30, 40).positions, {2, 2, 1}), "sphere");
  const int sphere = scene.addModel(shared);
  std::vector<int> nodes;
  for (int k = 0; k < 3; ++k) {
    SceneNode node;
    node.model = sphere;
    node.pose.translation = {2.0 * k - 2.0, 8.0, 0.5 * k};
    node.pose.scale = glm::dvec3(1.0 + k, 1.0, 2.0);
    node.pose.rotation = glm::angleAxis(0.7 * k, glm::normalize(glm::dvec3(1.0, 2.0, 3.0)));
    nodes.push_back(*scene.addNode(node));
  }
  scene.update(lookingAt({0, 0, 0}, 0, 0), 0.0);
  const mesh::TriangleMesh& vertices = shared->mesh().vertices();
  ASSERT_FALSE(scene.objectDrawItems().empty());
  for (const DrawItem& item : scene.objectDrawItems()) {
    EXPECT_EQ(item.positions.data(), vertices.positions.data());
    EXPECT_EQ(item.normals.data(), vertices.normals.data());
  }
  // Each item places the model's vertices exactly where the node's world matrix does.
  for (int n : nodes) {
    const glm::dmat4& world = scene.worldMatrix(n);
    bool found = false;
    for (const DrawItem& item : scene.objectDrawItems()) {
      if (glm::distance(item.origin, glm::dvec3(world[3])) > 1e-12) continue;
      found = true;
      for (std::size_t v = 0; v < vertices.vertexCount(); v += 37) {
        const glm::dvec3 expected(world * glm::dvec4(glm::dvec3(vertices.positions[v]), 1.0));
        const glm::dvec3 drawn = item.origin + glm::dvec3(item.linear * vertices.positions[v]);
        EXPECT_LT(glm::distance(expected, drawn), 1e-5);
      }
    }
    EXPECT_TRUE(found) << "node " << n;
  }
  // An instance costs its index buffers and tables, not a copy of the vertices.
  const std::size_t vertexBytes = vertices.vertexCount() * (sizeof(glm::vec3) * 2);
  const std::size_t indexBytes = 3 * sizeof(std::uint32_t) * vertices.triangleCount();
  for (int n : nodes) {
    EXPECT_GE(scene.instanceBytes(n), indexBytes);
    EXPECT_LT(scene.instanceBytes(n), indexBytes + vertexBytes / 2) << "node " << n;
  }
}

TEST(Scene, RegionsNearerTheViewpointGetMoreTriangles) {
  // A terrain-like mesh cut into 6 x 6 regions seen from a corner (ASLOD's Silvretta setup).
  mesh::TriangleMesh grid = test::bumpyGrid(90, 0.08f);
  for (glm::vec3& p : grid.positions) p *= 1000.0f;
  const auto partition = mesh::gridPartition(grid.positions, {6, 6, 1});
  Scene scene;
  SceneNode node;
  const auto sharedGrid = model(grid, partition, "grid");
  node.model = scene.addModel(sharedGrid);
  const int g = *scene.addNode(node);
  SceneOptions options;
  options.budgetTriangles = 4000;
  ASSERT_TRUE(scene.setOptions(options).ok());
  const SceneStats& stats = scene.update(lookingAt({-150, -150, 400}, 45, -25), 0.0);
  EXPECT_LE(stats.objectTriangles, options.budgetTriangles);
  EXPECT_GE(stats.objectTriangles, options.budgetTriangles * 9 / 10);
  // The region under the camera's corner gets the most, the opposite corner's far fewer
  // (alpha 3 flattens the split: the weights' cube roots).
  const MeshModel& gridModel = *sharedGrid;
  std::uint32_t nearest = 0, farthest = 0, most = 0;
  for (std::uint32_t r = 0; r < gridModel.mesh().regionCount(); ++r) {
    const glm::dvec3 centre = 0.5 * (gridModel.regionBox(r).minCorner + gridModel.regionBox(r).maxCorner);
    if (centre.x < 170 && centre.y < 170) nearest = r;
    if (centre.x > 830 && centre.y > 830) farthest = r;
    if (scene.instance(g).triangleCount(r) > scene.instance(g).triangleCount(most)) most = r;
  }
  EXPECT_EQ(most, nearest);
  EXPECT_GT(scene.instance(g).triangleCount(nearest), 2 * scene.instance(g).triangleCount(farthest));
}

TEST(Scene, OneBudgetForTerrainAndAHundredMovingObjects) {
  Scene scene(generatedTerrain(257, 4));
  const auto shape = test::bumpySphere(40, 60);
  const int sphere = scene.addModel(model(shape, mesh::automaticPartition(shape.positions, 4), "sphere"));
  const double extent = scene.terrain()->field()->extentX();
  for (int i = 0; i < 100; ++i) {
    SceneNode node;
    node.model = sphere;
    node.pose.translation = {0.0, 0.0, 900.0 + 5.0 * i};
    node.pose.scale = glm::dvec3(60.0);
    node.animation.kind = Animation::Kind::Orbit;
    node.animation.centre = {extent * 0.5, extent * 0.5, 0.0};
    node.animation.radius = extent * (0.1 + 0.004 * i);
    node.animation.periodS = 20.0 + i;
    node.animation.phase = 0.37 * i;
    ASSERT_TRUE(scene.addNode(node).ok());
  }
  SceneOptions options;
  options.budgetTriangles = 200000;
  ASSERT_TRUE(scene.setOptions(options).ok());
  for (int frame = 0; frame < 40; ++frame) {
    const double t = 0.25 * frame;
    const Camera camera = lookingAt({extent * 0.5 - 2500.0 + 60.0 * frame, extent * 0.1, 2200.0}, 20.0 + frame, -30.0);
    const SceneStats& stats = scene.update(camera, t);
    // The terrain's part reaches its share once its blocks are resident, not on their ancestors.
    scene.terrain()->waitForLoads();
    ASSERT_GT(stats.regions, 0u) << "frame " << frame;
    ASSERT_GT(stats.terrain.visibleBlocks, 0u) << "frame " << frame;
    EXPECT_LE(stats.triangles(), options.budgetTriangles) << "frame " << frame;
    EXPECT_GE(stats.triangles(), options.budgetTriangles * 9 / 10) << "frame " << frame;
  }
}

TEST(Scene, ErrorModeHoldsEveryRegionWithinItsPixelTolerance) {
  Scene scene;
  const auto shape = test::bumpySphere(30, 40);
  const auto sphereModel = model(shape, mesh::automaticPartition(shape.positions, 6), "sphere");
  const int sphere = scene.addModel(sphereModel);
  for (int i = 0; i < 5; ++i) {
    SceneNode node;
    node.model = sphere;
    node.pose.translation = {0.0, 5.0 + 12.0 * i * i, 0.0};
    node.pose.scale = glm::dvec3(1.0 + i);
    ASSERT_TRUE(scene.addNode(node).ok());
  }
  SceneOptions options;
  options.mode = LodMode::PixelError;
  options.tauPx = 1.0;
  ASSERT_TRUE(scene.setOptions(options).ok());
  const Camera camera = lookingAt({0, 0, 0}, 0, 0);
  scene.update(camera, 0.0);
  std::uint64_t previous = ~0ull;
  for (int i = 0; i < 5; ++i) {
    const auto& instance = scene.instance(i);
    const double scale = 1.0 + i;
    const glm::dvec3 centre(scene.worldMatrix(i)[3]);  // the camera sits at the origin
    std::uint64_t triangles = 0;
    for (std::uint32_t r = 0; r < instance.mesh().regionCount(); ++r) {
      const auto& sequence = instance.mesh().region(r);
      const Aabb& local = sphereModel->regionBox(r);
      const double nearest = distanceToOrigin(Aabb{centre + scale * local.minCorner, centre + scale * local.maxCorner});
      EXPECT_LE(camera.errorProjectionConstant() * sequence.errorAt(instance.level(r)) * scale / nearest, 1.0 + 1e-6);
      triangles += instance.triangleCount(r);
    }
    // Farther objects need fewer triangles.
    EXPECT_LE(triangles, previous);
    previous = triangles;
  }
}

TEST(Scene, SteadyFramesDoNotAllocateEvenWithObjectsMoving) {
  Scene scene(generatedTerrain(129, 8));
  const auto shape = test::bumpySphere(20, 24);
  const int sphere = scene.addModel(model(shape, mesh::automaticPartition(shape.positions, 4), "sphere"));
  for (int i = 0; i < 10; ++i) {
    SceneNode node;
    node.model = sphere;
    node.pose.translation = {0.0, 0.0, 800.0};
    node.pose.scale = glm::dvec3(40.0);
    node.animation.kind = Animation::Kind::Spin;  // moving in place: same levels, new vertices every frame
    node.animation.degreesPerSecond = 45.0;
    node.animation.axis = {0.3, 0.2, 1.0};
    node.pose.translation.x = 1500.0 + 120.0 * i;
    node.pose.translation.y = 1800.0;
    ASSERT_TRUE(scene.addNode(node).ok());
  }
  const Camera camera = lookingAt({1900.0, 200.0, 1600.0}, 0.0, -30.0);
  for (const LodMode mode : {LodMode::TriangleBudget, LodMode::PixelError}) {
    SceneOptions options;
    options.mode = mode;
    options.budgetTriangles = 30000;
    ASSERT_TRUE(scene.setOptions(options).ok());
    // One whole turn (8 s) to warm up: storage grows to the largest frame of the cycle,
    // then the next turn's frames must fit in it.
    for (int warm = 0; warm < 80; ++warm) {
      (void)scene.update(camera, 0.1 * warm);
      (void)scene.terrain()->frameMeshes();
      scene.terrain()->waitForLoads();  // steady state: every block the view needs resident
    }
    const std::size_t before = test::allocationCount();
    for (int frame = 0; frame < 20; ++frame) {
      const SceneStats& stats = scene.update(camera, 8.0 + 0.1 * frame);
      ASSERT_GT(stats.visibleObjects, 0u);
      (void)scene.terrain()->frameMeshes();
    }
    EXPECT_EQ(test::allocationCount() - before, 0u) << (mode == LodMode::TriangleBudget ? "budget mode" : "error mode");
  }
}

// The Silvretta model: every sample a vertex at its world position, two triangles per cell,
// each facing up, so the mesh is the heightfield's surface and nothing else.
TEST(HeightfieldMesh, EverySampleAVertexAndTwoUpwardTrianglesPerCell) {
  terrain::Heightfield field(4, 3, 30.0, 20.0);
  for (int j = 0; j < field.height; ++j)
    for (int i = 0; i < field.width; ++i) field.at(i, j) = float(100 + 7 * i - 5 * j + (i * j) % 3);
  const mesh::TriangleMesh shape = heightfieldMesh(field);
  ASSERT_EQ(shape.vertexCount(), 12u);
  ASSERT_EQ(shape.triangleCount(), 2u * 3u * 2u);
  for (int j = 0; j < field.height; ++j)
    for (int i = 0; i < field.width; ++i) {
      const glm::dvec3 expected = field.worldPosition(i, j);
      const glm::vec3& p = shape.positions[std::size_t(j * field.width + i)];
      EXPECT_EQ(glm::dvec3(p), expected) << i << "," << j;
    }
  double area = 0.0;
  for (std::size_t t = 0; t < shape.triangleCount(); ++t) {
    const glm::dvec3 a = shape.positions[shape.indices[3 * t]], b = shape.positions[shape.indices[3 * t + 1]],
                     c = shape.positions[shape.indices[3 * t + 2]];
    const glm::dvec3 n = glm::cross(b - a, c - a);
    EXPECT_GT(n.z, 0.0) << "triangle " << t << " faces down";
    area += 0.5 * n.z;  // projected onto the ground plane
  }
  EXPECT_NEAR(area, field.extentX() * field.extentY(), 1e-9);  // the cells tile the ground once
  ASSERT_EQ(shape.normals.size(), shape.positions.size());
  for (const glm::vec3& n : shape.normals) EXPECT_GT(n.z, 0.5f);
  EXPECT_EQ(heightfieldMesh(terrain::Heightfield(1, 5, 1.0, 1.0)).triangleCount(), 0u);
}

}  // namespace
}  // namespace polder::scene
