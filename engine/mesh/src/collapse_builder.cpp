#include "polder/mesh/collapse_builder.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "builder_setup.hpp"
#include "indexed_min_heap.hpp"
#include "quadric.hpp"
#include "triangle_planes.hpp"

namespace polder::mesh {

namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
// Colours further apart than this (RGB distance) make a border that collapses keep.
constexpr float kColourDiscontinuity = 0.25f;

enum class VertexKind : std::uint8_t {
  Interior,  // its fan is one closed disk
  Border,    // its fan is one open disk: it may only slide along its boundary edges
  Locked,    // non-manifold or isolated: never removed
};

// One collapse v -> vertex and its cost.
struct Option {
  float cost;
  std::uint32_t vertex;
};

// A neighbour of the vertex being examined and how many of its live triangles share the edge.
struct Neighbour {
  std::uint32_t vertex;
  std::uint32_t sharedTriangles;
};

class CollapseBuilder {
 public:
  CollapseBuilder(const TriangleMesh& mesh, const RegionPartition& partition, const CollapseOptions& options)
      : m_mesh(mesh), m_partition(partition), m_options(options) {}

  SimplificationSteps run() {
    setUp();
    for (std::uint32_t v = 0; v < m_vertexCount; ++v) updateCandidate(v, /*validate=*/false);
    const std::size_t reportEvery = std::max<std::size_t>(1, m_vertexCount / 64);
    SimplificationSteps steps;
    steps.representative.reserve(m_vertexCount);
    steps.removed.reserve(m_vertexCount);
    steps.removedBegin.reserve(m_vertexCount + 1);
    steps.error.reserve(m_vertexCount);
    while (!m_queue.empty() && m_liveTriangles > m_options.stopAtTriangles) {
      const std::uint32_t v = m_queue.top();
      m_queue.remove(v);
      const std::uint32_t u = m_target[v];
      // Candidates are costed without the validity checks; check the cheapest now, and if it
      // fails, queue v's cheapest valid option instead.
      if (!m_alive[u] || !collapseIsValid(v, u)) {
        updateCandidate(v, /*validate=*/true);
        continue;
      }
      collapse(v, u);
      const std::uint32_t removed[1] = {v};
      steps.add(u, removed, clusterError(u));
      if (m_options.progress && steps.size() % reportEvery == 0)
        m_options.progress(double(steps.size()) / double(m_vertexCount));
    }
    return steps;
  }

 private:
  void setUp() {
    m_vertexCount = static_cast<std::uint32_t>(m_mesh.vertexCount());
    NormalizedPositions normalized = normalizePositions(m_mesh.positions);
    m_diagonal = normalized.diagonal;
    m_position = std::move(normalized.positions);

    // Live triangles (degenerate input ones are skipped) and fans.
    collectTriangleFans(m_mesh, m_corner, m_fan);
    const auto triangleCount = static_cast<std::uint32_t>(m_corner.size() / 3);
    m_liveTriangles = triangleCount;
    m_triangleAlive.assign(triangleCount, 1);

    setUpAttributes();
    m_quadric.assign(m_vertexCount, Quadric{});
    for (std::uint32_t t = 0; t < triangleCount; ++t) addTriangle(t);
    setUpAttributeMoments();
    m_markA.assign(m_vertexCount, 0);
    m_markB.assign(m_vertexCount, 0);
    m_slot.assign(m_vertexCount, 0);
    m_alive.assign(m_vertexCount, 1);
    m_kind.assign(m_vertexCount, VertexKind::Interior);
    m_colourBorder.assign(m_vertexCount, 0);
    for (std::uint32_t v = 0; v < m_vertexCount; ++v) classify(v);
    m_target.assign(m_vertexCount, kNone);
    m_queue = IndexedMinHeap(m_vertexCount);
  }

  void setUpAttributes() {
    m_dims = 0;
    std::vector<double> weights;
    auto addDims = [&](int count, double weight, bool present) {
      if (!present || weight <= 0.0) return -1;
      const int first = m_dims;
      m_dims += count;
      weights.insert(weights.end(), count, weight);
      return first;
    };
    const int normalAt = addDims(3, m_options.normalWeight, m_mesh.hasNormals());
    const int colourAt = addDims(3, m_options.colourWeight, m_mesh.hasColours());
    const int uvAt = addDims(2, m_options.uvWeight, m_mesh.hasUvs());
    if (m_dims == 0) return;
    m_attribute.assign(std::size_t(m_vertexCount) * m_dims, 0.0);
    for (std::uint32_t v = 0; v < m_vertexCount; ++v) {
      double* a = &m_attribute[std::size_t(v) * m_dims];
      for (int k = 0; normalAt >= 0 && k < 3; ++k) a[normalAt + k] = m_mesh.normals[v][k];
      for (int k = 0; colourAt >= 0 && k < 3; ++k) a[colourAt + k] = m_mesh.colours[v][k];
      for (int k = 0; uvAt >= 0 && k < 2; ++k) a[uvAt + k] = m_mesh.uvs[v][k];
      for (int k = 0; k < m_dims; ++k) a[k] *= weights[k];
    }
    m_moment0.assign(m_vertexCount, 0.0);  // filled with areas by addTriangle
  }

  // Moments of each cluster's attributes, weighted by a third of the incident areas.
  void setUpAttributeMoments() {
    if (m_dims == 0) return;
    m_moment1.assign(std::size_t(m_vertexCount) * m_dims, 0.0);
    m_moment2.assign(m_vertexCount, 0.0);
    for (std::uint32_t v = 0; v < m_vertexCount; ++v) {
      const double* a = &m_attribute[std::size_t(v) * m_dims];
      double squared = 0.0;
      for (int k = 0; k < m_dims; ++k) {
        m_moment1[std::size_t(v) * m_dims + k] = m_moment0[v] * a[k];
        squared += a[k] * a[k];
      }
      m_moment2[v] = m_moment0[v] * squared;
    }
  }

  // The triangle's plane into its corners' quadrics, its area into their attribute weights.
  void addTriangle(std::uint32_t t) {
    const std::uint32_t* corner = &m_corner[3 * t];
    addTriangleQuadric(m_position, corner, m_quadric);
    if (m_dims == 0) return;
    const double thirdOfArea = glm::length(triangleCross(m_position, corner)) / 6.0;
    for (int k = 0; k < 3; ++k) m_moment0[corner[k]] += thirdOfArea;
  }

  // Gathers v's live triangles (dropping dead ones from its fan) and its neighbours with
  // the number of live triangles on each edge.
  void gatherNeighbours(std::uint32_t v, std::vector<Neighbour>& out) {
    out.clear();
    ++m_stamp;
    std::vector<std::uint32_t>& fan = m_fan[v];
    std::size_t kept = 0;
    for (std::uint32_t t : fan) {
      if (!m_triangleAlive[t]) continue;
      fan[kept++] = t;
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t x = m_corner[3 * t + k];
        if (x == v) continue;
        if (m_markA[x] == m_stamp) {
          ++out[m_slot[x]].sharedTriangles;
        } else {
          m_markA[x] = m_stamp;
          m_slot[x] = static_cast<std::uint32_t>(out.size());
          out.push_back({x, 1});
        }
      }
    }
    fan.resize(kept);
  }

  void classify(std::uint32_t v) {
    gatherNeighbours(v, m_neighbours);
    const std::size_t triangles = m_fan[v].size();
    std::size_t borderEdges = 0;
    bool nonManifold = triangles == 0;
    for (const Neighbour& n : m_neighbours) {
      if (n.sharedTriangles > 2) nonManifold = true;
      if (n.sharedTriangles == 1) ++borderEdges;
    }
    // One disk: a closed fan has as many neighbours as triangles, an open one a boundary
    // pair and one more neighbour. Anything else (bow-ties, fins) stays put.
    if (nonManifold) m_kind[v] = VertexKind::Locked;
    else if (borderEdges == 0 && m_neighbours.size() == triangles) m_kind[v] = VertexKind::Interior;
    else if (borderEdges == 2 && m_neighbours.size() == triangles + 1) m_kind[v] = VertexKind::Border;
    else m_kind[v] = VertexKind::Locked;
    if (m_kind[v] == VertexKind::Border) addBoundaryPlanes(v);
    // A vertex beside a colour discontinuity holds the colour border: it may only slide
    // along it, onto another vertex of its own colour that is also beside the border.
    if (m_options.colourWeight > 0.0 && m_mesh.hasColours())
      for (const Neighbour& n : m_neighbours)
        if (coloursDiffer(v, n.vertex)) m_colourBorder[v] = 1;
  }

  // The rules every option v -> u obeys besides the boundary's: one region, and a vertex
  // beside a colour border only onto another of its own colour beside the border.
  bool mayJoin(std::uint32_t v, std::uint32_t u) const {
    if (m_partition.regionOf(v) != m_partition.regionOf(u)) return false;
    return !m_colourBorder[v] || (m_colourBorder[u] && !coloursDiffer(v, u));
  }

  bool coloursDiffer(std::uint32_t a, std::uint32_t b) const {
    const glm::vec3 d = glm::vec3(m_mesh.colours[a]) - glm::vec3(m_mesh.colours[b]);
    return glm::dot(d, d) > kColourDiscontinuity * kColourDiscontinuity;
  }

  // Planes through v's boundary edges, perpendicular to their triangle, keep the outline.
  void addBoundaryPlanes(std::uint32_t v) {
    for (std::uint32_t t : m_fan[v]) {
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t a = m_corner[3 * t + k], b = m_corner[3 * t + (k + 1) % 3];
        if (a != v) continue;  // each boundary edge is added once, from its first vertex
        const auto shared = std::find_if(m_neighbours.begin(), m_neighbours.end(),
                                         [b](const Neighbour& n) { return n.vertex == b; });
        if (shared == m_neighbours.end() || shared->sharedTriangles != 1) continue;
        const glm::dvec3 faceNormal =
            glm::cross(m_position[b] - m_position[a], m_position[m_corner[3 * t + (k + 2) % 3]] - m_position[a]);
        addBoundaryEdgeQuadric(m_position[a], m_position[b], faceNormal, m_options.boundaryWeight, m_quadric[a],
                               m_quadric[b]);
      }
    }
  }

  double attributeCost(std::uint32_t v, std::uint32_t u) const {
    if (m_dims == 0) return 0.0;
    const double* a = &m_attribute[std::size_t(u) * m_dims];
    const double* s1 = &m_moment1[std::size_t(v) * m_dims];
    double squared = 0.0, dot = 0.0;
    for (int k = 0; k < m_dims; ++k) {
      squared += a[k] * a[k];
      dot += a[k] * s1[k];
    }
    return std::max(0.0, m_moment0[v] * squared - 2.0 * dot + m_moment2[v]);
  }

  // The mean (not the sum) of the removed cluster's squared plane distances at u's position,
  // plus its mean attribute deviation: a sum would let vertices carrying little area travel
  // far cheaply, keeping the RMS distance low while the worst one grows.
  float collapseCost(std::uint32_t v, std::uint32_t u) const {
    const Quadric& q = m_quadric[v];
    double cost = q.evaluate(m_position[u]) / std::max(q.weight, 1e-30);
    if (m_dims > 0) cost += attributeCost(v, u) / std::max(m_moment0[v], 1e-30);
    return static_cast<float>(cost);
  }

  float clusterError(std::uint32_t u) const {
    const Quadric& q = m_quadric[u];
    if (q.weight <= 0.0) return 0.0f;
    return static_cast<float>(std::sqrt(q.evaluate(m_position[u]) / q.weight) * m_diagonal);
  }

  // Queues v's cheapest collapse; with `validate`, its cheapest valid one (link condition,
  // no flips), else only the cost order is known and the check waits for the pop.
  void updateCandidate(std::uint32_t v, bool validate) {
    m_target[v] = kNone;
    m_queue.remove(v);
    if (!m_alive[v] || m_kind[v] == VertexKind::Locked) return;
    gatherNeighbours(v, m_neighbours);
    m_optionScratch.clear();
    for (const Neighbour& n : m_neighbours) {
      if (m_kind[v] == VertexKind::Border && n.sharedTriangles != 1) continue;
      if (mayJoin(v, n.vertex)) m_optionScratch.push_back({collapseCost(v, n.vertex), n.vertex});
    }
    auto cheaper = [](const Option& x, const Option& y) { return x.cost < y.cost; };
    if (validate) std::sort(m_optionScratch.begin(), m_optionScratch.end(), cheaper);
    else if (!m_optionScratch.empty())
      std::iter_swap(m_optionScratch.begin(),
                     std::min_element(m_optionScratch.begin(), m_optionScratch.end(), cheaper));
    for (const Option& option : m_optionScratch) {
      if (validate && !collapseIsValid(v, option.vertex)) continue;
      m_target[v] = option.vertex;
      m_queue.set(v, option.cost);
      return;
    }
  }

  // Link condition and normal check for moving v onto its neighbour u.
  bool collapseIsValid(std::uint32_t v, std::uint32_t u) {
    // Neighbours of v, and how many live triangles hold both v and u.
    ++m_stamp;
    std::uint32_t edgeTriangles = 0, fanV = 0, fanU = 0;
    for (std::uint32_t t : m_fan[v]) {
      if (!m_triangleAlive[t]) continue;
      ++fanV;
      bool hasU = false;
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t x = m_corner[3 * t + k];
        m_markA[x] = m_stamp;
        hasU |= x == u;
      }
      if (hasU) {
        ++edgeTriangles;
        continue;
      }
      // The triangle keeps existing with u in v's place: it must not flip or collapse.
      glm::dvec3 p[3], q[3];
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t x = m_corner[3 * t + k];
        p[k] = m_position[x];
        q[k] = x == v ? m_position[u] : p[k];
      }
      const glm::dvec3 before = glm::cross(p[1] - p[0], p[2] - p[0]);
      const glm::dvec3 after = glm::cross(q[1] - q[0], q[2] - q[0]);
      // dot > c |before| |after|, squared to spare the roots (c >= 0 is the usual case).
      const double dot = glm::dot(before, after), c = m_options.minNormalCosine;
      const double bound = c * c * glm::dot(before, before) * glm::dot(after, after);
      if (c >= 0.0 ? !(dot > 0.0 && dot * dot > bound) : !(dot > 0.0 || dot * dot < bound)) return false;
    }
    if (edgeTriangles == 0) return false;
    // Common neighbours of v and u must be exactly the apexes of the edge's triangles.
    std::uint32_t common = 0;
    for (std::uint32_t t : m_fan[u]) {
      if (!m_triangleAlive[t]) continue;
      ++fanU;
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t x = m_corner[3 * t + k];
        if (x == u || x == v || m_markB[x] == m_stamp) continue;
        m_markB[x] = m_stamp;
        if (m_markA[x] == m_stamp) ++common;
      }
    }
    // Never let a piece of surface vanish whole (its last triangles are the edge's own).
    if (fanV == edgeTriangles && fanU == edgeTriangles) return false;
    return common == edgeTriangles;
  }

  void collapse(std::uint32_t v, std::uint32_t u) {
    // v's neighbours (its ring) are gathered on the way through its fan.
    m_ring.clear();
    ++m_stamp;
    for (std::uint32_t t : m_fan[v]) {
      if (!m_triangleAlive[t]) continue;
      std::uint32_t* c = &m_corner[3 * t];
      for (int k = 0; k < 3; ++k)
        if (c[k] != v && m_markA[c[k]] != m_stamp) {
          m_markA[c[k]] = m_stamp;
          m_ring.push_back(c[k]);
        }
      if (c[0] == u || c[1] == u || c[2] == u) {
        m_triangleAlive[t] = 0;
        --m_liveTriangles;
        continue;
      }
      for (int k = 0; k < 3; ++k)
        if (c[k] == v) c[k] = u;
      m_fan[u].push_back(t);
    }
    std::vector<std::uint32_t>().swap(m_fan[v]);
    m_alive[v] = 0;
    m_queue.remove(v);
    m_quadric[u] += m_quadric[v];
    if (m_dims > 0) {
      m_moment0[u] += m_moment0[v];
      m_moment2[u] += m_moment2[v];
      for (int k = 0; k < m_dims; ++k) m_moment1[std::size_t(u) * m_dims + k] += m_moment1[std::size_t(v) * m_dims + k];
    }
    // u's quadric changed. v's old neighbours gained the option u (kept if cheaper than
    // theirs) and those aiming at v lost theirs. Everyone else keeps the costs of their
    // options (a target's position never moves); validity is checked at the pop.
    updateCandidate(u, false);
    for (const std::uint32_t x : m_ring) {
      if (x == u || !m_alive[x] || m_kind[x] == VertexKind::Locked) continue;
      if (m_target[x] == v || m_kind[x] == VertexKind::Border) {
        updateCandidate(x, false);
        continue;
      }
      if (!mayJoin(x, u)) continue;
      const float cost = collapseCost(x, u);
      if (m_target[x] != kNone && m_queue.contains(x) && !(cost < m_queue.key(x))) continue;
      m_target[x] = u;
      m_queue.set(x, cost);
    }
  }

  const TriangleMesh& m_mesh;
  const RegionPartition& m_partition;
  const CollapseOptions& m_options;
  std::uint32_t m_vertexCount = 0;
  double m_diagonal = 1.0;
  std::vector<glm::dvec3> m_position;  // translated and scaled to a unit diagonal
  std::vector<std::uint32_t> m_corner;
  std::vector<std::uint8_t> m_triangleAlive;
  std::uint32_t m_liveTriangles = 0;
  std::vector<std::vector<std::uint32_t>> m_fan;
  std::vector<Quadric> m_quadric;
  int m_dims = 0;
  std::vector<double> m_attribute;  // per vertex, m_dims weighted values
  std::vector<double> m_moment0, m_moment1, m_moment2;
  std::vector<std::uint8_t> m_alive;
  std::vector<VertexKind> m_kind;
  std::vector<std::uint8_t> m_colourBorder;
  std::vector<std::uint32_t> m_target;
  std::vector<std::uint32_t> m_markA, m_markB;
  std::vector<std::uint32_t> m_slot;  // a marked neighbour's place in the gathered list
  std::uint32_t m_stamp = 0;
  IndexedMinHeap m_queue{0};  // vertices by the cost of their queued collapse
  std::vector<Neighbour> m_neighbours;
  std::vector<std::uint32_t> m_ring;  // the removed vertex's neighbours
  std::vector<Option> m_optionScratch;
};

}  // namespace

Result<SimplificationSteps> buildCollapseSteps(const TriangleMesh& mesh, const RegionPartition& partition,
                                               const CollapseOptions& options) {
  if (Status s = validateMesh(mesh, "collapse builder input"); !s) return s.error();
  if (Status s = validatePartition(partition, mesh.vertexCount(), "collapse builder regions"); !s) return s.error();
  if (!(options.minNormalCosine >= -1.0 && options.minNormalCosine < 1.0))
    return makeError(ErrorKind::InvalidArgument, "collapse builder: minNormalCosine must lie in [-1, 1)");
  if (!(options.normalWeight >= 0.0) || !(options.colourWeight >= 0.0) || !(options.uvWeight >= 0.0) ||
      !(options.boundaryWeight >= 0.0))
    return makeError(ErrorKind::InvalidArgument, "collapse builder: weights must be finite and >= 0");
  return CollapseBuilder(mesh, partition, options).run();
}

}  // namespace polder::mesh
