// The scene graph with the allocator at its root (ASLOD, D. Schmalstieg and A. Fuhrmann, "Coarse View-Dependent Levels
// of Detail for Hierarchical and Deformable Models", 1999, sections 3, 4 and 6): nodes with hierarchical, animated
// transforms; nodes that show a model hold their own instance of its progressive mesh (their own LOD cache), so several
// instances of one model sit at different levels; terrain blocks and mesh regions are the
// same kind of region, and one allocator splits one triangle budget over all of those in
// view, weighted by their projected oriented-bounding-box area (attenuated by alpha). In
// error mode every region takes its own pixel tolerance instead.
//
//   Scene scene(std::move(terrainEngine));            // or no terrain
//   int bunny = scene.addModel(model);                // a shared MeshModel
//   scene.addNode({.name = "bunny", .model = bunny, .pose = ...});
//   const SceneStats& stats = scene.update(camera, t);
//   for (const DrawItem& item : scene.objectDrawItems()) renderer.drawTransient(item);
//
// Instances are rigid: each draws its model's shared vertex table with its own matrix
// (DrawItem::origin and DrawItem::linear), so an instance holds only its LOD cache (index
// buffers and border tables) and no vertex of its own; instanceBytes() says how much.
// Thread contract as TerrainEngine: one frame thread.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <polder/camera.hpp>
#include <polder/frustum.hpp>
#include <polder/lod/allocator.hpp>
#include <polder/lod/projected_area.hpp>
#include <polder/mesh/progressive_mesh.hpp>
#include <polder/mesh/progressive_mesh_instance.hpp>
#include <polder/mesh_data.hpp>
#include <polder/result.hpp>
#include <polder/scene/pose.hpp>
#include <polder/terrain_engine.hpp>

namespace polder::scene {

// A progressive mesh and the local bounding box of each region (its triangles' vertices,
// border triangles included), shared by every node that shows it.
class MeshModel {
 public:
  MeshModel(std::string name, mesh::ProgressiveMesh mesh);
  const std::string& name() const { return m_name; }
  const mesh::ProgressiveMesh& mesh() const { return m_mesh; }
  const Aabb& regionBox(std::uint32_t region) const { return m_regionBoxes[region]; }

 private:
  std::string m_name;
  mesh::ProgressiveMesh m_mesh;
  std::vector<Aabb> m_regionBoxes;
};

struct SceneNode {
  std::string name;
  int parent = -1;  // an earlier node, or -1 for the root
  Pose pose;        // rest pose, relative to the parent
  Animation animation;
  int model = -1;  // index from Scene::addModel, or -1 for a pure transform node
  glm::vec3 tint{1.0f};
  bool tintRegions = false;  // debug: every region its own colour
};

struct SceneOptions {
  LodMode mode = LodMode::TriangleBudget;
  double tauPx = 1.0;
  std::uint64_t budgetTriangles = 200000;  // terrain (dikes included) and objects together
  double alpha = 3.0;
};

struct SceneStats {
  std::size_t objects = 0;         // nodes showing a model
  std::size_t visibleObjects = 0;  // with at least one region in view
  std::size_t regions = 0;         // mesh regions in view
  std::uint64_t objectTriangles = 0;
  std::uint64_t terrainTriangles = 0;
  std::size_t allocatedRegions = 0;  // terrain blocks + mesh regions the allocator split over
  double allocatorMs = 0.0;
  double objectsMs = 0.0;  // levels and border lookups
  double totalMs = 0.0;
  TerrainFrameStats terrain;
  std::uint64_t triangles() const { return objectTriangles + terrainTriangles; }
};

class Scene {
 public:
  explicit Scene(std::unique_ptr<TerrainEngine> terrain = nullptr);
  ~Scene();
  Scene(const Scene&) = delete;
  Scene& operator=(const Scene&) = delete;

  int addModel(std::shared_ptr<const MeshModel> model);
  // Errors: a parent that is not an earlier node, an unknown model, a non-finite pose.
  Result<int> addNode(SceneNode node);

  Status setOptions(const SceneOptions& options);
  const SceneOptions& options() const { return m_options; }

  // Animates, culls, allocates and updates every instance for this camera at this time.
  const SceneStats& update(const Camera& camera, double timeS);

  // The last update's visible mesh regions: the model's vertices, placed by each item's
  // origin and linear part.
  std::span<const DrawItem> objectDrawItems() const { return m_drawItems; }
  TerrainEngine* terrain() { return m_terrain.get(); }
  const TerrainEngine* terrain() const { return m_terrain.get(); }

  std::size_t nodeCount() const { return m_nodes.size(); }
  const MeshModel& model(int index) const { return *m_models[index]; }
  // Whether the node's region was in view at the last update.
  bool regionVisible(int index, std::uint32_t region) const { return m_nodes[index].regionVisible[region] != 0; }
  const SceneNode& node(int index) const { return m_nodes[index].node; }
  const glm::dmat4& worldMatrix(int index) const { return m_nodes[index].world; }
  // The node's instance of its model (asserts the node shows one).
  const mesh::ProgressiveMeshInstance& instance(int index) const { return *m_nodes[index].instance; }
  // Heap bytes the node holds beyond its shared model: its LOD cache and per-region state.
  std::size_t instanceBytes(int index) const;
  // The triangles the allocator gave each visible region of the node last frame (budget mode).
  std::uint32_t regionAllocation(int index, std::uint32_t region) const;

 private:
  struct NodeState {
    SceneNode node;
    glm::dmat4 world{1.0};
    std::unique_ptr<mesh::ProgressiveMeshInstance> instance;
    std::vector<std::uint8_t> regionVisible;
    std::vector<std::uint32_t> allocation;
    std::vector<double> regionDistance;
  };
  void animate(double timeS);
  void cullAndWeigh(const Camera& camera);
  void chooseLevels(const Camera& camera, std::span<const lod::RegionDemand> terrainDemands);

  std::unique_ptr<TerrainEngine> m_terrain;
  std::vector<std::shared_ptr<const MeshModel>> m_models;
  std::vector<NodeState> m_nodes;
  SceneOptions m_options;
  SceneStats m_stats;
  std::vector<lod::RegionDemand> m_demands;
  std::vector<std::uint32_t> m_allocation;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> m_demandRegion;  // (node, region) per object demand
  lod::AllocationScratch m_scratch;
  std::uint64_t m_terrainShare = 0;
  std::vector<DrawItem> m_drawItems;
};

}  // namespace polder::scene
