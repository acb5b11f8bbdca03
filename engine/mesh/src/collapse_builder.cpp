#include "polder/mesh/collapse_builder.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "builder_setup.hpp"
#include "halves.hpp"
#include "indexed_min_heap.hpp"
#include "locality_order.hpp"
#include "polder/closest_point_triangle.hpp"
#include "polder/thread_pool.hpp"
#include "quadric.hpp"
#include "step_listener.hpp"
#include "triangle_fans.hpp"
#include "triangle_planes.hpp"

namespace polder::mesh {

namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
// Colours further apart than this (RGB distance) make a border that collapses keep.
constexpr float kColourDiscontinuity = 0.25f;
// A collapse costs the removed cluster's summed squared plane distances over its area to
// this power. 1 (the mean) lets clusters carrying much area travel as cheaply as small
// ones and coarse levels lose shape (RMS 1.4x meshoptimizer's on the cow at 1%); 0 (the
// sum, Garland-Heckbert's) lets vertices carrying little area travel far, and the worst
// distance grows (Hausdorff up to 2.6x). Every value in 0.75-0.85 keeps both within
// 1.25x on bunny, cow, fandisk and spot at 50, 10 and 1% (simplify_bench).
constexpr double kAreaExponent = 0.8;
// Collapses that cost the same up to round-off (on flat ground) go shorter edge first:
// flat regions then coarsen evenly, and coarse levels hang less on how ties fell (fandisk
// at 1% swung between 1.0x and 1.6x meshoptimizer's Hausdorff distance). The term is this
// times the squared edge, the mesh's mean squared edge and the cost's area factor, so it
// keeps one proportion to a curved collapse's cost (which grows as the edge to the fourth)
// at any mesh density: it outweighs the curvature only on ground flatter than a sphere of
// about 100 bounding-box diagonals' radius, and stays above the quadrics' round-off.
constexpr double kShorterEdgeFirst = 1e-4;

enum class VertexKind : std::uint8_t {
  Interior,  // its fan is one closed disk
  Border,    // its fan is one open disk: it may only slide along its boundary edges
  Locked,    // non-manifold or isolated: never removed
};

// Everything a visit to a vertex reads, in two cache lines. The cheapest-first order jumps
// across the whole mesh, so each of a collapse's few dozen vertex visits is a likely
// cache miss: one per visit instead of one per table.
struct alignas(64) VertexState {
  glm::dvec3 position{0.0};      // translated and scaled to a unit diagonal
  std::uint32_t target = kNone;  // the neighbour of its queued collapse
  std::uint32_t mark = 0;        // stamps of the current gather or check
  float areaScale = 0.0f;        // 1 / (cluster area)^kAreaExponent
  VertexKind kind = VertexKind::Interior;
  bool alive = true;
  bool colourBorder = false;  // beside a colour discontinuity (classify)
  Quadric quadric;
};
static_assert(sizeof(VertexState) == 128);

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
  CollapseBuilder(const TriangleMesh& mesh, const RegionPartition& partition, const CollapseOptions& options,
                  StepListener* listener, core::ThreadPool& pool)
      : m_mesh(mesh), m_partition(partition), m_options(options), m_listener(listener), m_pool(pool) {}

  SimplificationSteps run() {
    if (m_listener) m_listener->builderOnTwoCores(true);
    setUp();
    queueFirstCandidates();
    if (m_listener) m_listener->builderOnTwoCores(false);
    const std::size_t reportEvery = std::max<std::size_t>(1, m_vertexCount / 64);
    SimplificationSteps steps;
    steps.representative.reserve(m_vertexCount);
    steps.removed.reserve(m_vertexCount);
    steps.onto.reserve(m_vertexCount);
    steps.removedBegin.reserve(m_vertexCount + 1);
    steps.error.reserve(m_vertexCount);
    while (!m_queue.empty() && m_liveTriangles > m_options.stopAtTriangles) {
      const std::uint32_t v = m_queue.top();
      m_queue.remove(v);
      if (!m_queue.empty()) {  // often the next one looked at: its state and fan start loading
        const std::uint32_t next = m_queue.top();
        __builtin_prefetch(&m_vertex[next]);
        __builtin_prefetch(reinterpret_cast<const char*>(&m_vertex[next]) + 64);
        m_fan.prefetch(next);
      }
      const std::uint32_t u = m_vertex[v].target;
      m_fan.prefetch(u);
      prefetchRing(v);
      if (m_twin[v] != kNoTwin) {
        if (!collapseSeam(v, u, steps)) updateCandidate(v, /*validate=*/true);
        continue;
      }
      // Candidates are costed without the validity checks; check the cheapest now, and if it
      // fails, queue v's cheapest valid option instead.
      if (!m_vertex[u].alive || !collapseIsValid(v, u)) {
        updateCandidate(v, /*validate=*/true);
        continue;
      }
      collapse(v, u);
      const std::uint32_t removed[1] = {v};
      steps.add(u, removed, clusterError(u));
      if (m_listener) m_listener->stepTaken(steps);
      if (m_options.progress && steps.size() % reportEvery == 0)
        m_options.progress(double(steps.size()) / double(m_vertexCount));
    }
    return steps;
  }

 private:
  // The builder's state, by halves on two threads where the work splits by vertex or by
  // triangle: each vertex's quadric and attribute moments sum its fan's triangles in
  // triangle order, as adding each triangle to its corners one after the other would.
  void setUp() {
    m_vertexCount = static_cast<std::uint32_t>(m_mesh.vertexCount());
    NormalizedPositions normalized = normalizePositions(m_mesh.positions);
    m_diagonal = normalized.diagonal;
    const std::vector<glm::dvec3>& position = normalized.positions;

    // Live triangles (degenerate input ones are skipped), fans and planes.
    m_corner = liveTriangleCorners(m_mesh);
    m_liveTriangles = static_cast<std::uint32_t>(m_corner.size() / 3);
    const std::vector<WeightedPlane> plane = fillFansAndPlanes(m_pool, position, m_corner, m_fan);
    setUpAttributes();
    m_vertex.resize(m_vertexCount);
    m_deviation.assign(m_vertexCount, 0.0f);
    double squaredEdgeSum = 0.0;  // over every triangle's three edges (corner k to the next)
    m_pool.runHalves([&](int half) {
      const auto [begin, end] = halfOf(m_vertexCount, half);
      for (std::uint32_t v = begin; v < end; ++v) {
        // Each plane as a quadric of its own, then added: the roundings of adding each
        // triangle's quadric to its corners.
        Quadric quadric;
        for (std::uint32_t t : m_fan[v]) {
          if (plane[t].weight <= 0.0) continue;  // a flat triangle adds nothing
          Quadric q;
          q.addPlane(plane[t].normal, plane[t].offset, plane[t].weight);
          quadric += q;
        }
        if (m_dims > 0) {
          double area = 0.0;
          for (std::uint32_t t : m_fan[v]) area += plane[t].weight / 3.0;
          setUpAttributeMoments(v, area);
        }
        VertexState& state = m_vertex[v];
        state.position = position[v];
        state.quadric = quadric;
        state.areaScale = areaScaleOf(quadric);
      }
      if (half == 1) return;
      for (std::uint32_t k = 0; k < m_corner.size(); ++k) {  // one sum, in one order
        const glm::dvec3 edge = position[m_corner[k]] - position[m_corner[k - k % 3 + (k + 1) % 3]];
        squaredEdgeSum += glm::dot(edge, edge);
      }
    });
    m_tieBreakScale = m_corner.empty() ? 0.0 : kShorterEdgeFirst * squaredEdgeSum / double(m_corner.size());
    m_twin = positionTwins(m_mesh.positions);
    classifyAll();
    pairSeamTwins();
    m_queue = IndexedMinHeap(m_vertexCount);
  }

  // Per vertex, its attributes times their weights (m_dims values), for the moments.
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
    m_moment0.assign(m_vertexCount, 0.0);
    m_moment1.assign(std::size_t(m_vertexCount) * m_dims, 0.0);
    m_moment2.assign(m_vertexCount, 0.0);
  }

  // v's attribute moments, weighted by a third of its triangles' areas (`area` in all).
  void setUpAttributeMoments(std::uint32_t v, double area) {
    m_moment0[v] = area;
    const double* a = &m_attribute[std::size_t(v) * m_dims];
    double squared = 0.0;
    for (int k = 0; k < m_dims; ++k) {
      m_moment1[std::size_t(v) * m_dims + k] = area * a[k];
      squared += a[k] * a[k];
    }
    m_moment2[v] = area * squared;
  }

  // Every vertex's kind and colour border, by halves on two threads (classifying only reads
  // the mesh), then the boundary planes of the border vertices, in vertex order.
  void classifyAll() {
    m_pool.runHalves([&](int half) {
      const auto [begin, end] = halfOf(m_vertexCount, half);
      FanScratch scratch;
      for (std::uint32_t v = begin; v < end; ++v) classify(v, scratch);
    });
    for (std::uint32_t v = 0; v < m_vertexCount; ++v) {
      if (m_vertex[v].kind != VertexKind::Border) continue;
      gatherNeighbours(v, m_neighbours);
      addBoundaryPlanes(v);
    }
  }

  // Every vertex's cheapest collapse, queued in vertex order: an interior vertex's options
  // are costed by halves on two threads (reading only), the others' one by one.
  void queueFirstCandidates() {
    std::vector<Option> cheapest(m_vertexCount, Option{0.0f, kNone});
    m_pool.runHalves([&](int half) {
      const auto [begin, end] = halfOf(m_vertexCount, half);
      std::vector<Option> options;
      for (std::uint32_t v = begin; v < end; ++v) {
        if (m_vertex[v].kind != VertexKind::Interior) continue;
        options.clear();
        addInteriorOptions(v, options);
        if (!options.empty()) cheapest[v] = *std::min_element(options.begin(), options.end(), cheaper);
      }
    });
    for (std::uint32_t v = 0; v < m_vertexCount; ++v) {
      if (m_vertex[v].kind != VertexKind::Interior) {
        updateCandidate(v, /*validate=*/false);
        continue;
      }
      m_vertex[v].target = cheapest[v].vertex;
      if (cheapest[v].vertex != kNone) m_queue.set(v, cheapest[v].cost);
    }
  }

  // An interior vertex's collapses onto its neighbours, appended to `options`. A closed fan
  // meets each neighbour once as the corner after v: no marks needed.
  void addInteriorOptions(std::uint32_t v, std::vector<Option>& options) const {
    for (std::uint32_t t : m_fan[v]) {
      const std::uint32_t x = cornerAfter(&m_corner[3 * t], v);
      if (mayJoin(v, x)) options.push_back({collapseCost(v, x), x});
    }
  }

  static bool cheaper(const Option& x, const Option& y) { return x.cost < y.cost; }

  // Gathers v's neighbours, in the order its fan first meets them, with the number of
  // triangles on each edge. A fan usually holds a handful: a scan needs no marks, so threads
  // may gather at once; a large fan (a cone's apex) is sorted instead, so that a vertex of
  // valence n costs O(n log n), not O(n^2).
  void gatherNeighbours(std::uint32_t v, std::vector<Neighbour>& out) const {
    constexpr std::size_t kScannedFan = 32;
    out.clear();
    if (m_fan[v].size() > kScannedFan) return gatherNeighboursSorted(v, out);
    for (std::uint32_t t : m_fan[v])
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t x = m_corner[3 * t + k];
        if (x == v) continue;
        auto seen = std::find_if(out.begin(), out.end(), [x](const Neighbour& n) { return n.vertex == x; });
        if (seen == out.end())
          out.push_back({x, 1});
        else
          ++seen->sharedTriangles;
      }
  }

  void gatherNeighboursSorted(std::uint32_t v, std::vector<Neighbour>& out) const {
    std::vector<Neighbour> met;  // (vertex, where the fan first meets it)
    met.reserve(2 * m_fan[v].size());
    for (std::uint32_t t : m_fan[v])
      for (int k = 0; k < 3; ++k)
        if (const std::uint32_t x = m_corner[3 * t + k]; x != v) met.push_back({x, std::uint32_t(met.size())});
    std::sort(met.begin(), met.end(), [](const Neighbour& a, const Neighbour& b) {
      return a.vertex != b.vertex ? a.vertex < b.vertex : a.sharedTriangles < b.sharedTriangles;
    });
    std::vector<Neighbour> first;  // (vertex, first meeting), one per neighbour
    for (std::size_t i = 0; i < met.size();) {
      std::size_t end = i;
      while (end < met.size() && met[end].vertex == met[i].vertex) ++end;
      first.push_back(met[i]);
      out.push_back({met[i].vertex, std::uint32_t(end - i)});
      i = end;
    }
    std::vector<std::uint32_t> order(out.size());
    for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(),
              [&](std::uint32_t a, std::uint32_t b) { return first[a].sharedTriangles < first[b].sharedTriangles; });
    for (std::uint32_t i = 0; i < order.size(); ++i) met[i] = out[order[i]];
    out.assign(met.begin(), met.begin() + std::ptrdiff_t(order.size()));
  }

  // A fresh mark value; marks are cleared when the counter would wrap.
  std::uint32_t nextStamp() {
    if (m_stamp == std::numeric_limits<std::uint32_t>::max()) {
      for (VertexState& state : m_vertex) state.mark = 0;
      m_stamp = 0;
    }
    return ++m_stamp;
  }

  // What classify needs of one fan; one per thread.
  struct FanScratch {
    std::vector<Neighbour> neighbours;     // gatherNeighbours'
    std::vector<std::uint32_t> chainFrom;  // neighbour slot -> fan entry it starts
    std::vector<std::uint8_t> chainLedTo;
    // The place of neighbour x in `neighbours`.
    std::uint32_t slotOf(std::uint32_t x) const {
      std::uint32_t slot = 0;
      while (neighbours[slot].vertex != x) ++slot;
      return slot;
    }
  };

  // v's kind and colour border; reads the mesh only, so threads may classify at once.
  void classify(std::uint32_t v, FanScratch& scratch) {
    std::vector<Neighbour>& neighbours = scratch.neighbours;
    gatherNeighbours(v, neighbours);
    const std::size_t triangles = m_fan[v].size();
    std::size_t borderEdges = 0;
    bool nonManifold = triangles == 0;
    for (const Neighbour& n : neighbours) {
      if (n.sharedTriangles > 2) nonManifold = true;
      if (n.sharedTriangles == 1) ++borderEdges;
    }
    // One disk: a closed fan has as many neighbours as triangles, an open one a boundary
    // pair and one more neighbour, and either is one consistently wound chain of
    // triangles. Anything else (bow-ties, pinches, fins, flipped triangles) stays put.
    VertexKind& kind = m_vertex[v].kind;
    if (nonManifold)
      kind = VertexKind::Locked;
    else if (borderEdges == 0 && neighbours.size() == triangles && fanIsOneChain(v, /*closed=*/true, scratch))
      kind = VertexKind::Interior;
    else if (borderEdges == 2 && neighbours.size() == triangles + 1 && fanIsOneChain(v, /*closed=*/false, scratch))
      kind = VertexKind::Border;
    else
      kind = VertexKind::Locked;
    // A vertex beside a colour discontinuity holds the colour border: it may only slide
    // along it, onto another vertex of its own colour that is also beside the border.
    if (m_options.colourWeight > 0.0 && m_mesh.hasColours())
      for (const Neighbour& n : neighbours)
        if (coloursDiffer(v, n.vertex)) m_vertex[v].colourBorder = true;
  }

  // Starts loading the triangles of v's fan, then their corners' states, all at once: the
  // checks and the collapse visit each of them, one after another.
  void prefetchRing(std::uint32_t v) const {
    const std::span<const std::uint32_t> fan = m_fan[v];
    for (std::uint32_t t : fan) __builtin_prefetch(&m_corner[3 * t]);
    for (std::uint32_t t : fan)
      for (int k = 0; k < 3; ++k) __builtin_prefetch(&m_vertex[m_corner[3 * t + k]]);
  }

  // A vertex split across a texture seam has a twin at its position on the seam's other
  // side; both are border vertices of the split surface, and the two move together, each
  // along its own side (collapseSeam). Twins in any other arrangement, and positions held
  // by three or more vertices, stay put, so the surface never parts where they meet.
  // (m_twin holds positionTwins, found before classify for the seams' boundary planes.)
  void pairSeamTwins() {
    auto isBorder = [&](std::uint32_t v) { return m_vertex[v].kind == VertexKind::Border; };
    for (std::uint32_t v : keepSeamTwins(m_twin, m_partition, isBorder)) m_vertex[v].kind = VertexKind::Locked;
  }

  // Where seam vertex v's twin goes when v goes onto its boundary neighbour u: onto u's
  // twin, or onto u itself where the seam ends at u; either must lie across a boundary
  // edge from the twin, or the seam does not run on along u and the move is refused (kNone).
  std::uint32_t seamPartner(std::uint32_t v, std::uint32_t u) {
    const std::uint32_t twin = m_twin[v];
    if (u == twin) return kNone;
    const std::uint32_t wanted = m_twin[u] != kNoTwin ? m_twin[u] : u;
    gatherNeighbours(twin, m_twinNeighbours);
    for (const Neighbour& n : m_twinNeighbours)
      if (n.vertex == wanted && n.sharedTriangles == 1 && wanted != v && mayJoin(twin, wanted)) return wanted;
    return kNone;
  }

  // Whether v may go onto u now, with its twin where it has one (onto `partner`).
  bool moveIsValid(std::uint32_t v, std::uint32_t u, std::uint32_t& partner) {
    partner = kNone;
    if (!collapseIsValid(v, u)) return false;
    if (m_twin[v] == kNoTwin) return true;
    partner = seamPartner(v, u);
    return partner != kNone && collapseIsValid(m_twin[v], partner);
  }

  // Takes seam vertex v's queued move onto u together with its twin's, as one step, if both
  // are valid; false otherwise.
  bool collapseSeam(std::uint32_t v, std::uint32_t u, SimplificationSteps& steps) {
    std::uint32_t partner = kNone;
    if (!m_vertex[u].alive || !moveIsValid(v, u, partner)) return false;
    const std::uint32_t twin = m_twin[v];
    collapse(v, u);
    m_seamRing.assign(m_ring.begin(), m_ring.end());
    collapse(twin, partner);
    const std::uint32_t removed[2] = {v, twin}, onto[2] = {u, partner};
    steps.add(u, removed, onto, std::max(clusterError(u), clusterError(partner)));
    if (m_listener) m_listener->stepTaken(steps);
    // Seam vertices around either side were re-costed while the other side still had its
    // old shape: cost them again.
    m_seamRing.insert(m_seamRing.end(), m_ring.begin(), m_ring.end());
    m_seamRing.push_back(u);
    m_seamRing.push_back(partner);
    for (std::uint32_t x : m_seamRing)
      if (m_vertex[x].alive && m_twin[x] != kNoTwin) updateCandidate(x, /*validate=*/false);
    return true;
  }

  // Whether v's fan is one chain of consistently wound triangles, each leading through its
  // corner after v to the triangle whose corner before v that is: a cycle through the whole
  // fan (closed), or a path through it from the one triangle nothing leads to (open). Uses
  // the neighbours just gathered into `scratch`.
  bool fanIsOneChain(std::uint32_t v, bool closed, FanScratch& scratch) const {
    const std::span<const std::uint32_t> fan = m_fan[v];
    std::vector<std::uint32_t>& chainFrom = scratch.chainFrom;
    chainFrom.assign(scratch.neighbours.size(), kNone);  // neighbour slot -> fan entry it starts
    for (std::uint32_t i = 0; i < fan.size(); ++i) {
      std::uint32_t& from = chainFrom[scratch.slotOf(cornerBefore(&m_corner[3 * fan[i]], v))];
      if (from != kNone) return false;  // two triangles start at one neighbour
      from = i;
    }
    std::uint32_t start = 0;
    if (!closed) {  // the triangle whose corner before v no triangle ends at
      std::vector<std::uint8_t>& ledTo = scratch.chainLedTo;
      ledTo.assign(scratch.neighbours.size(), 0);
      for (std::uint32_t t : fan) ledTo[scratch.slotOf(cornerAfter(&m_corner[3 * t], v))] = 1;
      while (start < fan.size() && ledTo[scratch.slotOf(cornerBefore(&m_corner[3 * fan[start]], v))]) ++start;
      if (start == fan.size()) return false;
    }
    std::uint32_t at = start;
    for (std::size_t visited = 1; visited <= fan.size(); ++visited) {
      const std::uint32_t next = chainFrom[scratch.slotOf(cornerAfter(&m_corner[3 * fan[at]], v))];
      if (next == kNone || next == start) return visited == fan.size() && (next == start) == closed;
      at = next;
    }
    return false;
  }

  // The rules every option v -> u obeys besides the boundary's: one region, and a vertex
  // beside a colour border only onto another of its own colour beside the border.
  bool mayJoin(std::uint32_t v, std::uint32_t u) const {
    if (m_partition.regionOf(v) != m_partition.regionOf(u)) return false;
    return !m_vertex[v].colourBorder || (m_vertex[u].colourBorder && !coloursDiffer(v, u));
  }

  bool coloursDiffer(std::uint32_t a, std::uint32_t b) const {
    const glm::vec3 d = glm::vec3(m_mesh.colours[a]) - glm::vec3(m_mesh.colours[b]);
    return glm::dot(d, d) > kColourDiscontinuity * kColourDiscontinuity;
  }

  // Planes through v's boundary edges, perpendicular to their triangle, keep the outline
  // (and a texture seam's line: the surface's split there is a boundary of each side).
  void addBoundaryPlanes(std::uint32_t v) {
    for (std::uint32_t t : m_fan[v]) {
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t a = m_corner[3 * t + k], b = m_corner[3 * t + (k + 1) % 3];
        if (a != v) continue;  // each boundary edge is added once, from its first vertex
        const auto shared =
            std::find_if(m_neighbours.begin(), m_neighbours.end(), [b](const Neighbour& n) { return n.vertex == b; });
        if (shared == m_neighbours.end() || shared->sharedTriangles != 1) continue;
        const glm::dvec3 &pa = m_vertex[a].position, &pb = m_vertex[b].position;
        const glm::dvec3 faceNormal = glm::cross(pb - pa, m_vertex[m_corner[3 * t + (k + 2) % 3]].position - pa);
        // Both sides of a texture seam hold its line, and the pair costs as one outline.
        const bool seam = m_twin[a] != kNoTwin || m_twin[b] != kNoTwin;
        const double weight = seam ? 0.5 * m_options.boundaryWeight : m_options.boundaryWeight;
        addBoundaryEdgeQuadric(pa, pb, faceNormal, weight, m_vertex[a].quadric, m_vertex[b].quadric);
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

  // The removed cluster's squared plane distances at u's position, summed and divided by
  // its area to the power kAreaExponent, plus its mean attribute deviation, plus the
  // tie-break.
  float collapseCost(std::uint32_t v, std::uint32_t u) const {
    const VertexState& removed = m_vertex[v];
    double cost = removed.quadric.evaluate(m_vertex[u].position) * removed.areaScale;
    if (m_dims > 0) cost += attributeCost(v, u) / std::max(m_moment0[v], 1e-30);
    const glm::dvec3 edge = m_vertex[u].position - removed.position;
    const double areaFactor = removed.quadric.weight * removed.areaScale;  // area^(1 - kAreaExponent)
    return static_cast<float>(cost + m_tieBreakScale * glm::dot(edge, edge) * areaFactor);
  }

  static float areaScaleOf(const Quadric& q) {
    return static_cast<float>(1.0 / std::pow(std::max(q.weight, 1e-30), kAreaExponent));
  }

  // The step's object-space error: how far the surface around u may now lie from the
  // original (m_deviation), in the mesh's units.
  float clusterError(std::uint32_t u) const { return static_cast<float>(m_deviation[u] * m_diagonal); }

  // Queues v's cheapest collapse; with `validate`, its cheapest valid one (link condition,
  // no flips), else only the cost order is known and the check waits for the pop.
  void updateCandidate(std::uint32_t v, bool validate) {
    VertexState& state = m_vertex[v];
    state.target = kNone;
    m_queue.remove(v);
    if (!state.alive || state.kind == VertexKind::Locked) return;
    m_optionScratch.clear();
    if (state.kind == VertexKind::Interior) {
      addInteriorOptions(v, m_optionScratch);
    } else {
      gatherNeighbours(v, m_neighbours);
      std::uint32_t boundaryNeighbour[2], boundaryCount = 0;
      for (const Neighbour& n : m_neighbours)  // a border vertex slides along its boundary
        if (n.sharedTriangles == 1 && mayJoin(v, n.vertex) && boundaryCount < 2)
          boundaryNeighbour[boundaryCount++] = n.vertex;
      for (std::uint32_t i = 0; i < boundaryCount; ++i) {
        const std::uint32_t u = boundaryNeighbour[i];
        float cost = collapseCost(v, u);
        if (m_twin[v] != kNoTwin) {  // and its twin along the seam's other side
          const std::uint32_t partner = seamPartner(v, u);
          if (partner == kNone) continue;
          cost += collapseCost(m_twin[v], partner);
        }
        m_optionScratch.push_back({cost, u});
      }
    }
    if (validate)
      std::sort(m_optionScratch.begin(), m_optionScratch.end(), cheaper);
    else if (!m_optionScratch.empty())
      std::iter_swap(m_optionScratch.begin(),
                     std::min_element(m_optionScratch.begin(), m_optionScratch.end(), cheaper));
    std::uint32_t partner = kNone;
    for (const Option& option : m_optionScratch) {
      if (validate && !moveIsValid(v, option.vertex, partner)) continue;
      state.target = option.vertex;
      m_queue.set(v, option.cost);
      return;
    }
  }

  // Link condition and normal check for moving v onto its neighbour u.
  bool collapseIsValid(std::uint32_t v, std::uint32_t u) {
    // Neighbours of v, and how many live triangles hold both v and u.
    const std::uint32_t neighbourOfV = nextStamp(), counted = nextStamp();
    std::uint32_t edgeTriangles = 0, fanV = 0, fanU = 0;
    for (std::uint32_t t : m_fan[v]) {
      ++fanV;
      bool hasU = false;
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t x = m_corner[3 * t + k];
        m_vertex[x].mark = neighbourOfV;
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
        p[k] = m_vertex[x].position;
        q[k] = x == v ? m_vertex[u].position : p[k];
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
      ++fanU;
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t x = m_corner[3 * t + k];
        if (x == u || x == v || m_vertex[x].mark != neighbourOfV) continue;
        m_vertex[x].mark = counted;
        ++common;
      }
    }
    // Never let a piece of surface vanish whole (its last triangles are the edge's own).
    if (fanV == edgeTriangles && fanU == edgeTriangles) return false;
    return common == edgeTriangles;
  }

  // After v went onto u: v's cluster now lies on u's fan, at v's distance from it plus
  // however far v's own surface already was from the original; the fans of v's old
  // neighbours moved by that distance too, which their later collapses carry on. The sum
  // keeps the estimate at or above the measured Hausdorff distance (error_estimate_test).
  void trackDeviation(std::uint32_t v, std::uint32_t u) {
    const glm::dvec3& p = m_vertex[v].position;
    double nearest = std::numeric_limits<double>::infinity();  // u's fan keeps a triangle (collapseIsValid)
    for (std::uint32_t t : m_fan[u]) {
      const std::uint32_t* c = &m_corner[3 * t];
      const TrianglePoint q =
          closestPointOnTriangle(p, m_vertex[c[0]].position, m_vertex[c[1]].position, m_vertex[c[2]].position);
      nearest = std::min(nearest, glm::length(q.point - p));
    }
    const float moved = static_cast<float>(nearest);
    m_deviation[u] = std::max(m_deviation[u], m_deviation[v] + moved);
    for (const std::uint32_t x : m_ring) m_deviation[x] = std::max(m_deviation[x], moved);
  }

  void collapse(std::uint32_t v, std::uint32_t u) {
    // v's neighbours (its ring) are gathered on the way through its fan.
    m_ring.clear();
    const std::uint32_t inRing = nextStamp();
    for (std::uint32_t t : m_fan[v]) {
      std::uint32_t* c = &m_corner[3 * t];
      for (int k = 0; k < 3; ++k)
        if (c[k] != v && m_vertex[c[k]].mark != inRing) {
          m_vertex[c[k]].mark = inRing;
          m_ring.push_back(c[k]);
        }
      if (c[0] == u || c[1] == u || c[2] == u) {
        // The edge's triangles vanish: out of the fans of u and of their third corner.
        --m_liveTriangles;
        for (int k = 0; k < 3; ++k)
          if (c[k] != v) m_fan.swapErase(c[k], t);
        continue;
      }
      for (int k = 0; k < 3; ++k)
        if (c[k] == v) c[k] = u;
      m_fan.push(u, t);
    }
    m_fan.clear(v);
    m_vertex[v].alive = false;
    trackDeviation(v, u);
    m_queue.remove(v);
    m_vertex[u].quadric += m_vertex[v].quadric;
    m_vertex[u].areaScale = areaScaleOf(m_vertex[u].quadric);
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
      VertexState& state = m_vertex[x];
      if (x == u || !state.alive || state.kind == VertexKind::Locked) continue;
      if (state.target == v || state.kind == VertexKind::Border) {
        updateCandidate(x, false);
        continue;
      }
      if (!mayJoin(x, u)) continue;
      const float cost = collapseCost(x, u);
      if (state.target != kNone && m_queue.contains(x) && !(cost < m_queue.key(x))) continue;
      state.target = u;
      m_queue.set(x, cost);
    }
  }

  const TriangleMesh& m_mesh;
  const RegionPartition& m_partition;
  const CollapseOptions& m_options;
  StepListener* m_listener;  // may be null
  core::ThreadPool& m_pool;  // for the set-up
  std::uint32_t m_vertexCount = 0;
  double m_diagonal = 1.0;
  double m_tieBreakScale = 0.0;  // kShorterEdgeFirst x mean squared edge length
  std::vector<std::uint32_t> m_corner;
  std::uint32_t m_liveTriangles = 0;
  TriangleFans m_fan;  // each vertex's live triangles
  int m_dims = 0;
  std::vector<double> m_attribute;  // per vertex, m_dims weighted values
  std::vector<double> m_moment0, m_moment1, m_moment2;
  std::vector<VertexState> m_vertex;
  std::vector<float> m_deviation;  // per vertex, unit-diagonal space (trackDeviation)
  std::uint32_t m_stamp = 0;
  IndexedMinHeap m_queue{0};  // vertices by the cost of their queued collapse
  std::vector<Neighbour> m_neighbours;
  std::vector<std::uint32_t> m_ring;  // the removed vertex's neighbours
  std::vector<std::uint32_t> m_twin;  // per vertex: its seam twin (pairSeamTwins), or kNoTwin
  std::vector<Neighbour> m_twinNeighbours;
  std::vector<std::uint32_t> m_seamRing;
  std::vector<Option> m_optionScratch;
};

}  // namespace

Result<SimplificationSteps> buildCollapseSteps(const TriangleMesh& mesh, const RegionPartition& partition,
                                               const CollapseOptions& options) {
  core::ThreadPool pool(options.threads);
  return buildCollapseSteps(mesh, partition, options, nullptr, pool);
}

Result<SimplificationSteps> buildCollapseSteps(const TriangleMesh& mesh, const RegionPartition& partition,
                                               const CollapseOptions& options, StepListener* listener,
                                               core::ThreadPool& pool) {
  if (Status s = validateMesh(mesh, "collapse builder input"); !s) return s.error();
  if (Status s = validatePartition(partition, mesh.vertexCount(), "collapse builder regions"); !s) return s.error();
  if (!(options.minNormalCosine >= -1.0 && options.minNormalCosine < 1.0))
    return makeError(ErrorKind::InvalidArgument, "collapse builder: minNormalCosine must lie in [-1, 1)");
  if (!(options.normalWeight >= 0.0) || !(options.colourWeight >= 0.0) || !(options.uvWeight >= 0.0) ||
      !(options.boundaryWeight >= 0.0))
    return makeError(ErrorKind::InvalidArgument, "collapse builder: weights must be finite and >= 0");
  return buildInLocalityOrder(mesh, partition, listener,
                              [&](const TriangleMesh& ordered, const RegionPartition& regions) {
                                return CollapseBuilder(ordered, regions, options, listener, pool).run();
                              });
}

}  // namespace polder::mesh
