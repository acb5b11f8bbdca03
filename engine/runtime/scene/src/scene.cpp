#include "polder/scene/scene.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

namespace polder::scene {

namespace {

using Clock = std::chrono::steady_clock;

double millisecondsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

bool isFinite(const Pose& pose) {
  for (int k = 0; k < 3; ++k)
    if (!std::isfinite(pose.translation[k]) || !std::isfinite(pose.scale[k])) return false;
  return std::isfinite(pose.rotation.w) && std::isfinite(pose.rotation.x) && std::isfinite(pose.rotation.y) &&
         std::isfinite(pose.rotation.z);
}

// The region box carried by the node's world matrix: an oriented box (exact for rotation
// and scale) and the axis-aligned box around it (for culling).
struct WorldBox {
  lod::OrientedBox oriented;
  Aabb aligned;
};

WorldBox transformBox(const Aabb& local, const glm::dmat4& world) {
  WorldBox box;
  const glm::dvec3 centre = 0.5 * (local.minCorner + local.maxCorner);
  const glm::dvec3 half = 0.5 * (local.maxCorner - local.minCorner);
  box.oriented.centre = glm::dvec3(world * glm::dvec4(centre, 1.0));
  glm::dvec3 reach(0.0);
  for (int k = 0; k < 3; ++k) {
    const glm::dvec3 column(world[k]);
    const double length = glm::length(column);
    box.oriented.axes[k] = length > 0.0 ? column / length : glm::dvec3(k == 0, k == 1, k == 2);
    box.oriented.halfExtents[k] = half[k] * length;
    reach += glm::abs(column) * half[k];
  }
  box.aligned = Aabb{box.oriented.centre - reach, box.oriented.centre + reach};
  return box;
}

double largestScale(const glm::dmat4& world) {
  return std::max(
      {glm::length(glm::dvec3(world[0])), glm::length(glm::dvec3(world[1])), glm::length(glm::dvec3(world[2]))});
}

// Distinct, readable colours for debug region tints.
glm::vec3 regionTint(std::uint32_t region) {
  const float hue = std::fmod(float(region) * 0.61803398875f, 1.0f) * 6.0f;
  const float x = 1.0f - std::abs(std::fmod(hue, 2.0f) - 1.0f);
  glm::vec3 rgb = hue < 1   ? glm::vec3(1, x, 0)
                  : hue < 2 ? glm::vec3(x, 1, 0)
                  : hue < 3 ? glm::vec3(0, 1, x)
                  : hue < 4 ? glm::vec3(0, x, 1)
                  : hue < 5 ? glm::vec3(x, 0, 1)
                            : glm::vec3(1, 0, x);
  return 0.35f + 0.65f * rgb;
}

}  // namespace

MeshModel::MeshModel(std::string name, mesh::ProgressiveMesh mesh) : m_name(std::move(name)), m_mesh(std::move(mesh)) {
  const auto& positions = m_mesh.vertices().positions;
  m_regionBoxes.resize(m_mesh.regionCount());
  for (std::uint32_t r = 0; r < m_mesh.regionCount(); ++r) {
    Aabb box{glm::dvec3(std::numeric_limits<double>::max()), glm::dvec3(std::numeric_limits<double>::lowest())};
    for (std::uint32_t v : m_mesh.region(r).fullIndices()) {
      box.minCorner = glm::min(box.minCorner, glm::dvec3(positions[v]));
      box.maxCorner = glm::max(box.maxCorner, glm::dvec3(positions[v]));
    }
    if (box.minCorner.x > box.maxCorner.x) box = Aabb{};  // a region without triangles
    m_regionBoxes[r] = box;
  }
}

Scene::Scene(std::unique_ptr<TerrainEngine> terrain) : m_terrain(std::move(terrain)) {
  [[maybe_unused]] const Status defaultsAreValid = setOptions(m_options);
}
Scene::~Scene() = default;

int Scene::addModel(std::shared_ptr<const MeshModel> model) {
  m_models.push_back(std::move(model));
  return static_cast<int>(m_models.size() - 1);
}

Result<int> Scene::addNode(SceneNode node) {
  const int index = static_cast<int>(m_nodes.size());
  if (node.parent >= index || node.parent < -1)
    return makeError(ErrorKind::InvalidArgument, "scene node '" + node.name + "': its parent must be an earlier node");
  if (node.model >= static_cast<int>(m_models.size()) || node.model < -1 || (node.model >= 0 && !m_models[node.model]))
    return makeError(ErrorKind::InvalidArgument, "scene node '" + node.name + "': unknown model");
  if (!isFinite(node.pose))
    return makeError(ErrorKind::InvalidArgument, "scene node '" + node.name + "': non-finite pose");
  NodeState state;
  state.node = std::move(node);
  if (state.node.model >= 0) {
    const mesh::ProgressiveMesh& mesh = m_models[state.node.model]->mesh();
    state.instance = std::make_unique<mesh::ProgressiveMeshInstance>(mesh);
    for (std::uint32_t r = 0; r < mesh.regionCount(); ++r) state.instance->setLevel(r, 0);
    state.instance->resolveBorders();
    state.regionVisible.assign(mesh.regionCount(), 0);
    state.allocation.assign(mesh.regionCount(), 0);
    state.regionDistance.assign(mesh.regionCount(), 0.0);
    m_demands.reserve(m_demands.capacity() + mesh.regionCount());
    m_demandRegion.reserve(m_demandRegion.capacity() + mesh.regionCount());
    m_drawItems.reserve(m_drawItems.capacity() + mesh.regionCount());
  }
  m_nodes.push_back(std::move(state));
  return index;
}

Status Scene::setOptions(const SceneOptions& options) {
  if (!(options.tauPx > 0.0) || !std::isfinite(options.tauPx))
    return makeError(ErrorKind::InvalidArgument, "the pixel tolerance must be positive");
  if (!(options.alpha > 0.0) || !std::isfinite(options.alpha))
    return makeError(ErrorKind::InvalidArgument, "the allocator's alpha must be positive");
  m_options = options;
  if (m_terrain) {
    TerrainEngineOptions terrainOptions = m_terrain->options();
    terrainOptions.mode = options.mode;
    terrainOptions.tauPx = options.tauPx;
    terrainOptions.alpha = options.alpha;
    terrainOptions.budgetTriangles = options.budgetTriangles;
    m_terrain->setOptions(terrainOptions);
  }
  return {};
}

std::uint32_t Scene::regionAllocation(int index, std::uint32_t region) const {
  return m_nodes[index].allocation[region];
}

const SceneStats& Scene::update(const Camera& camera, double timeS) {
  const auto frameStart = Clock::now();
  m_stats = SceneStats{};
  animate(timeS);
  std::span<const lod::RegionDemand> terrainDemands;
  if (m_terrain) terrainDemands = m_terrain->beginFrame(camera);
  const auto objectsStart = Clock::now();
  cullAndWeigh(camera);
  chooseLevels(camera, terrainDemands);
  double objectsMs = millisecondsSince(objectsStart) - m_stats.allocatorMs;
  if (m_terrain) {
    const TerrainFrame& frame = m_terrain->finishFrame(camera, m_terrainShare);
    m_stats.terrain = frame.stats;
    m_stats.terrainTriangles = frame.stats.triangles();
  }

  const auto instancesStart = Clock::now();
  m_drawItems.clear();
  for (NodeState& state : m_nodes) {
    if (!state.instance) continue;
    ++m_stats.objects;
    state.instance->resolveBorders();
    const mesh::TriangleMesh& vertices = state.instance->mesh().vertices();
    const glm::dvec3 origin(state.world[3]);
    const glm::mat3 linear{glm::dmat3(state.world)};
    bool anyVisible = false;
    for (std::uint32_t r = 0; r < state.regionVisible.size(); ++r) {
      if (!state.regionVisible[r]) continue;
      anyVisible = true;
      ++m_stats.regions;
      m_stats.objectTriangles += state.instance->triangleCount(r);
      const glm::vec3 tint = state.node.tintRegions ? state.node.tint * regionTint(r) : state.node.tint;
      m_drawItems.push_back(
          DrawItem{origin, vertices.positions, vertices.normals, state.instance->indices(r), tint, linear});
    }
    m_stats.visibleObjects += anyVisible;
  }
  objectsMs += millisecondsSince(instancesStart);
  m_stats.objectsMs = objectsMs;
  m_stats.totalMs = millisecondsSince(frameStart);
  return m_stats;
}

void Scene::animate(double timeS) {
  for (NodeState& state : m_nodes) {
    const glm::dmat4 local = state.node.animation.evaluate(state.node.pose, timeS).matrix();
    state.world = state.node.parent >= 0 ? m_nodes[state.node.parent].world * local : local;
  }
}

void Scene::cullAndWeigh(const Camera& camera) {
  const Frustum frustum = Frustum::fromCamera(camera);
  const lod::AreaView areaView = lod::makeAreaView(camera);
  m_demandRegion.clear();
  m_demands.clear();
  for (std::uint32_t n = 0; n < m_nodes.size(); ++n) {
    NodeState& state = m_nodes[n];
    if (!state.instance) continue;
    const MeshModel& model = *m_models[state.node.model];
    for (std::uint32_t r = 0; r < model.mesh().regionCount(); ++r) {
      const WorldBox box = transformBox(model.regionBox(r), state.world);
      const bool visible = frustum.intersects(box.aligned);
      state.regionVisible[r] = visible;
      state.allocation[r] = 0;
      if (!visible) continue;
      state.regionDistance[r] =
          distanceToOrigin(Aabb{box.aligned.minCorner - camera.position, box.aligned.maxCorner - camera.position});
      const mesh::RegionSequence& sequence = model.mesh().region(r);
      const double weight = lod::visibleAreaPx(box.oriented, areaView);
      m_demands.push_back(lod::RegionDemand{std::max(weight, 1e-9), sequence.trianglesAt(0),
                                            sequence.trianglesAt(sequence.levelCount())});
      m_demandRegion.emplace_back(n, r);
    }
  }
}

void Scene::chooseLevels(const Camera& camera, std::span<const lod::RegionDemand> terrainDemands) {
  if (m_options.mode == LodMode::TriangleBudget) {
    // One allocation over terrain blocks and mesh regions (ASLOD section 3): the terrain's
    // blocks first, then the objects' regions.
    const auto start = Clock::now();
    const std::size_t objectDemands = m_demands.size();
    m_demands.insert(m_demands.begin(), terrainDemands.begin(), terrainDemands.end());
    m_allocation.resize(m_demands.size());
    lod::allocateTriangles(m_demands, m_options.budgetTriangles, m_options.alpha, m_allocation, m_scratch);
    m_stats.allocatorMs = millisecondsSince(start);
    m_stats.allocatedRegions = m_demands.size();
    m_terrainShare = 0;
    for (std::size_t i = 0; i < terrainDemands.size(); ++i) m_terrainShare += m_allocation[i];
    // With no visible terrain block the terrain still draws its dikes' share of nothing.
    for (std::size_t i = 0; i < objectDemands; ++i) {
      const auto [n, r] = m_demandRegion[i];
      m_nodes[n].allocation[r] = m_allocation[terrainDemands.size() + i];
    }
  }
  const double projection = camera.errorProjectionConstant();
  for (NodeState& state : m_nodes) {
    if (!state.instance) continue;
    const mesh::ProgressiveMesh& mesh = state.instance->mesh();
    const double scale = largestScale(state.world);
    for (std::uint32_t r = 0; r < mesh.regionCount(); ++r) {
      const mesh::RegionSequence& sequence = mesh.region(r);
      std::uint32_t level = 0;  // regions out of view wait at their coarsest
      if (state.regionVisible[r]) {
        if (m_options.mode == LodMode::TriangleBudget) {
          level = sequence.levelForTriangles(state.allocation[r]);
        } else {
          // Projected error K * e * scale / d within tau.
          const double distance = state.regionDistance[r];
          level = distance > 0.0 && scale > 0.0
                      ? sequence.levelForError(static_cast<float>(m_options.tauPx * distance / (projection * scale)))
                      : sequence.levelCount();
        }
      }
      state.instance->setLevel(r, level);
    }
  }
}

std::size_t Scene::instanceBytes(int index) const {
  const NodeState& state = m_nodes[index];
  std::size_t bytes = state.regionVisible.capacity() * sizeof(std::uint8_t) +
                      state.allocation.capacity() * sizeof(std::uint32_t) +
                      state.regionDistance.capacity() * sizeof(double);
  if (state.instance) bytes += sizeof(mesh::ProgressiveMeshInstance) + state.instance->memoryBytes();
  return bytes;
}

}  // namespace polder::scene
