#include "polder/mesh/cluster_builder.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>
#include <vector>

#include "builder_setup.hpp"
#include "indexed_min_heap.hpp"
#include "locality_order.hpp"
#include "quadric.hpp"
#include "step_listener.hpp"
#include "triangle_fans.hpp"
#include "triangle_planes.hpp"

namespace polder::mesh {

namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

// Planes through boundary edges hold the outline: this times the edge length squared (the
// collapse builder's boundaryWeight).
constexpr double kBoundaryWeight = 4.0;
// Sharp edges and outlines that span less than this many mean edge lengths are noise.
constexpr double kSmallestFeatureEdges = 4.0;
// Neighbours whose RGB colours differ by more than this lie on a colour border.
constexpr double kColourBorderTolerance = 0.2;
// A member costing more than this times the cluster's mean cost stays out.
constexpr double kOutlierFactor = 2.5;
// At most this many vertices join in one step (the tree is cut breadth first): it bounds
// the work of a large cell on fine ground, where the seed gathers 2 to 10 vertices a step.
constexpr std::size_t kMaxClusterSize = 32;
// A triangle that survives a step may turn by at most about 87 degrees.
constexpr double kMinNormalCosine = 0.05;
// A tiny cost for gathering distant vertices: on flat ground, where every cluster costs
// nothing, it keeps clusters compact and cells growing evenly.
constexpr double kCompactness = 1e-6;

// The seed's five vertex categories (part A, preprocessing), found on the original mesh;
// a feature the coarser mesh no longer shows relaxes later (demoteFadedFeature).
// Independently of its class, a vertex next to a vertex of another colour lies on a
// colour border and only joins along its side of it (keepsFeature).
enum class VertexClass : std::uint8_t {
  Simple,     // interior and smooth: joins any representative
  Boundary,   // on one open boundary that runs straight on: joins along the boundary
  Seam,       // a boundary vertex split by a texture seam: joins along the seam, its twin too
  SharpEdge,  // on one feature line (one or two sharp edges): joins along that line
  Corner,     // three or more sharp edges, a sharp turn, a boundary meeting a crease: stays
  Complex,    // non-manifold, isolated, or where a seam splits it other than in two: stays
};

// Features cost more to gather, so they go last (the seed's class weights).
double classWeight(VertexClass c) {
  switch (c) {
    case VertexClass::Boundary:
    case VertexClass::Seam:
    case VertexClass::SharpEdge: return 2.0;
    default: return 1.0;
  }
}

// How much of a candidate cluster evaluate() looks at.
enum class Evaluation : std::uint8_t {
  FirstRing,    // r's neighbours only: the initial queue's estimate
  Tree,         // the whole tree, without the geometric checks: the queue's key
  CheckedTree,  // the whole tree, valid: a step about to be taken
};

// What growing a tree reads and writes of a vertex, side by side: its position (single
// precision is plenty for the cell test) and its mark.
struct TreePoint {
  glm::vec3 position;
  std::uint32_t mark;  // == m_stamp: r or in r's tree; == m_stamp + 1: seen, outside
};

struct MemberScore {
  double cost;        // of moving the member's cluster onto the representative
  double meanSquare;  // of the cluster's plane distances there
};

struct Edge {
  std::uint32_t a, b;
};

// One side of an edge (lo, hi), lo < hi, of the original mesh, for classification (lo is
// implied).
struct EdgeSide {
  std::uint32_t hi, triangle;
  bool forward;  // the triangle runs lo -> hi
};

// A neighbour of a vertex and the (first two) current triangles on their edge.
struct Link {
  std::uint32_t vertex;
  std::uint32_t triangles;
  std::uint32_t first, second;
};

// Disjoint sets of vertices (path halving).
class UnionFind {
 public:
  explicit UnionFind(std::uint32_t size) : m_parent(size) { std::iota(m_parent.begin(), m_parent.end(), 0u); }
  std::uint32_t find(std::uint32_t v) {
    while (m_parent[v] != v) v = m_parent[v] = m_parent[m_parent[v]];
    return v;
  }
  void join(std::uint32_t a, std::uint32_t b) { m_parent[find(a)] = find(b); }

 private:
  std::vector<std::uint32_t> m_parent;
};

class ClusterBuilder {
 public:
  ClusterBuilder(const TriangleMesh& mesh, const RegionPartition& partition, const ClusterOptions& options,
                 StepListener* listener)
      : m_mesh(mesh),
        m_partition(partition),
        m_options(options),
        m_listener(listener),
        m_queue(static_cast<std::uint32_t>(mesh.vertexCount())) {}

  SimplificationSteps run() {
    SimplificationSteps steps;
    setUp();
    if (m_liveTriangles == 0) return steps;
    steps.representative.reserve(m_vertexCount / 2);
    steps.removed.reserve(m_vertexCount);
    steps.onto.reserve(m_vertexCount);
    steps.removedBegin.reserve(m_vertexCount / 2 + 1);
    steps.error.reserve(m_vertexCount / 2);
    const std::size_t reportEvery = std::max<std::size_t>(1, m_vertexCount / 64);
    std::size_t removedCount = 0, nextReport = reportEvery;

    // Seed preprocessing: every vertex gets its priority (the cost of the cluster it would
    // gather); then the simplification loop, one step per cycle. The first ring of the
    // cluster estimates the priority at a fraction of the work: the queue evaluates the
    // whole cluster when the vertex comes up, and most vertices are gathered before that.
    for (std::uint32_t v = 0; v < m_vertexCount; ++v)
      if (evaluate(v, Evaluation::FirstRing)) m_queue.set(v, queueKey());
    std::uint32_t r = 0;
    while (m_liveTriangles > m_options.stopAtTriangles && nextRepresentative(r)) {
      gather(r);
      if (m_rTwin == kNone) {
        steps.add(r, m_members, m_error);
      } else {
        m_targets.resize(m_members.size());
        for (std::size_t i = 0; i < m_members.size(); ++i) m_targets[i] = targetOf(i, r);
        steps.add(r, m_members, m_targets, m_error);
      }
      if (m_listener) m_listener->stepTaken(steps);
      removedCount += m_members.size();
      const std::uint32_t rTwin = m_rTwin;  // evaluations below overwrite it
      updateNeighbourhood(r);
      if (rTwin != kNone) updateNeighbourhood(rTwin);
      if (m_options.progress && removedCount >= nextReport) {
        m_options.progress(double(removedCount) / double(m_vertexCount));
        nextReport = removedCount + reportEvery;
      }
    }
    return steps;
  }

 private:
  // Seed step 1 with a lazy queue: the neighbourhood of an entry may have changed since it
  // was made, so the popped vertex is evaluated again and only taken if its current cost
  // (after the geometric checks) still beats every other entry; otherwise it goes back
  // with that cost. On true, r and m_members hold the step to take.
  bool nextRepresentative(std::uint32_t& r) {
    while (!m_queue.empty()) {
      r = m_queue.top();
      m_queue.remove(r);
      if (!m_queue.empty()) m_fan.prefetch(m_queue.top());  // often the next one looked at
      if (!evaluate(r, Evaluation::Tree)) continue;
      if (!beatsTheQueue()) {
        m_queue.set(r, queueKey());
        continue;
      }
      // Only a cluster about to be taken gets the geometric checks; if they fail in this
      // cell, the search for a valid cluster goes on in the next larger one.
      if (validateCluster(r)) scoreCluster(r);
      else if (!growCell(r) || !evaluate(r, Evaluation::CheckedTree)) continue;
      if (beatsTheQueue()) return true;
      m_queue.set(r, queueKey());
    }
    return false;
  }

  // The queue's key for the last evaluation's priority.
  float queueKey() const { return static_cast<float>(m_priority); }

  // Whether the last evaluation costs no more than every queued vertex.
  bool beatsTheQueue() const { return m_queue.empty() || queueKey() <= m_queue.key(m_queue.top()); }

  // (Re)evaluates r and queues it if it has something to gather.
  void schedule(std::uint32_t r) {
    m_queue.remove(r);
    if (m_alive[r] && evaluate(r, Evaluation::Tree)) m_queue.set(r, queueKey());
  }

  // Seed step 6, lazily: the representative gets its new priority at once; a neighbour
  // already queued is evaluated again when it comes up (its cluster now holds the
  // representative's larger quadric, so its cost has mostly grown); one that had nothing
  // to gather may have something now. The neighbours' weights are updated too: a feature
  // the coarser mesh no longer shows may now join others.
  void updateNeighbourhood(std::uint32_t r) {
    collectRing(r);
    updateClosedAround(r);
    schedule(r);
    for (std::uint32_t x : m_ring) {
      if (!m_queue.contains(x)) schedule(x);
      if (!demoteFadedFeature(x)) continue;
      for (std::uint32_t t : m_fan[x])
        for (int k = 0; k < 3; ++k)
          if (const std::uint32_t y = m_corner[3 * t + k]; !m_queue.contains(y)) schedule(y);
    }
  }

  // --- Preprocessing -------------------------------------------------------------------

  void setUp() {
    m_vertexCount = static_cast<std::uint32_t>(m_mesh.vertexCount());
    NormalizedPositions normalized = normalizePositions(m_mesh.positions);
    m_diagonal = normalized.diagonal;
    m_position = std::move(normalized.positions);
    const glm::dvec3 extent = normalized.extent;
    // A cell of twice the largest extent covers the bounding box wherever it is centred.
    m_cellLimit = 2.0 * std::max(extent.x, std::max(extent.y, extent.z)) + 1e-9;

    // Live triangles (degenerate input ones are skipped) and fans.
    m_corner = liveTriangleCorners(m_mesh);
    m_fan.build(m_vertexCount, m_corner);
    const auto triangleCount = static_cast<std::uint32_t>(m_corner.size() / 3);
    m_liveTriangles = triangleCount;
    m_triangleAlive.assign(triangleCount, 1);

    m_quadric.assign(m_vertexCount, Quadric{});
    std::vector<glm::dvec3> faceNormal(triangleCount, glm::dvec3(0.0));
    for (std::uint32_t t = 0; t < triangleCount; ++t)
      faceNormal[t] = addTriangleQuadric(m_position, &m_corner[3 * t], m_quadric);
    setUpColours();
    const double meanEdge = classify(faceNormal);

    m_alive.assign(m_vertexCount, 1);
    m_treePoint.resize(m_vertexCount);
    for (std::uint32_t v = 0; v < m_vertexCount; ++v) m_treePoint[v] = {glm::vec3(m_position[v]), 0};
    m_ringMark.assign(m_vertexCount, 0);
    m_memberIndex.assign(m_vertexCount, 0);
    m_linkSeen.assign(m_vertexCount, 0);
    m_runsFromR.assign(m_vertexCount, 0);
    m_runsToR.assign(m_vertexCount, 0);
    m_keptOnEdge.assign(m_vertexCount, 0);
    m_vanishing.assign(m_vertexCount, 0);
    m_triangleSeen.assign(m_triangleAlive.size(), 0);
    // Seed: cells start as a uniform subdivision of the bounding box with size tau0.
    const double tau0 = m_options.initialCellFraction > 0.0 ? m_options.initialCellFraction : 2.0 * meanEdge;
    m_cell.assign(m_vertexCount, std::min(std::max(tau0, 1e-12), m_cellLimit));
  }

  // Area-weighted colour moments per cluster, so a cluster's squared colour deviation from
  // any colour costs O(1) (as in the collapse builder).
  void setUpColours() {
    m_useColours = m_mesh.hasColours() && m_options.colourWeight > 0.0;
    if (!m_useColours) return;
    m_colour.resize(m_vertexCount);
    for (std::uint32_t v = 0; v < m_vertexCount; ++v)
      m_colour[v] = glm::dvec3(m_mesh.colours[v]) * m_options.colourWeight;
    m_moment0.assign(m_vertexCount, 0.0);
    for (std::uint32_t t = 0; t < m_corner.size() / 3; ++t) {
      const double third = glm::length(triangleCross(m_position, &m_corner[3 * t])) / 6.0;  // of its area
      for (int k = 0; k < 3; ++k) m_moment0[m_corner[3 * t + k]] += third;
    }
    m_moment1.resize(m_vertexCount);
    m_moment2.resize(m_vertexCount);
    for (std::uint32_t v = 0; v < m_vertexCount; ++v) {
      m_moment1[v] = m_moment0[v] * m_colour[v];
      m_moment2[v] = m_moment0[v] * glm::dot(m_colour[v], m_colour[v]);
    }
  }

  // Classifies every vertex into the seed's categories from the edges around it, labels
  // feature lines, adds boundary planes; returns the mean edge length.
  double classify(const std::vector<glm::dvec3>& faceNormal) {
    m_featureCosine = std::cos(m_options.featureAngleDegrees * 3.14159265358979323846 / 180.0);
    std::vector<std::uint32_t> neighbours(m_vertexCount, 0);
    std::vector<std::uint8_t> nonManifold(m_vertexCount, 0);
    m_closedAround.assign(m_vertexCount, 1);
    std::vector<Edge> sharpEdges, boundaryEdges;
    m_colourBorder.assign(m_vertexCount, 0);
    double edgeLengthSum = 0.0;
    std::size_t edgeCount = 0;
    // Each edge (a, b), a < b, once: from a's fan, with its sides.
    std::vector<EdgeSide> sides;
    for (std::uint32_t a = 0; a < m_vertexCount; ++a) {
      sides.clear();
      for (std::uint32_t t : m_fan[a]) {
        const std::uint32_t* c = &m_corner[3 * t];
        if (const std::uint32_t after = cornerAfter(c, a); after > a) sides.push_back({after, t, true});
        if (const std::uint32_t before = cornerBefore(c, a); before > a) sides.push_back({before, t, false});
      }
      std::sort(sides.begin(), sides.end(), [](const EdgeSide& x, const EdgeSide& y) { return x.hi < y.hi; });
      for (std::size_t i = 0; i < sides.size();) {
        std::size_t j = i + 1;
        while (j < sides.size() && sides[j].hi == sides[i].hi) ++j;
        const std::uint32_t b = sides[i].hi;
        ++neighbours[a], ++neighbours[b];
        if (j - i != 2 || sides[i].forward == sides[i + 1].forward) m_closedAround[a] = m_closedAround[b] = 0;
        edgeLengthSum += glm::length(m_position[a] - m_position[b]);
        ++edgeCount;
        if (j - i == 1) {
          boundaryEdges.push_back({a, b});
          addBoundaryEdgeQuadric(m_position[a], m_position[b], faceNormal[sides[i].triangle], kBoundaryWeight,
                                 m_quadric[a], m_quadric[b]);
        } else if (j - i == 2) {
          const glm::dvec3 n0 = faceNormal[sides[i].triangle];
          // Two consistently oriented triangles run the edge in opposite directions.
          const double flip = sides[i].forward != sides[i + 1].forward ? 1.0 : -1.0;
          const glm::dvec3 n1 = faceNormal[sides[i + 1].triangle] * flip;
          if (glm::dot(n0, n0) > 0.0 && glm::dot(n1, n1) > 0.0 && glm::dot(n0, n1) < m_featureCosine)
            sharpEdges.push_back({a, b});
        } else {
          nonManifold[a] = nonManifold[b] = 1;
        }
        if (m_useColours && coloursDiffer(a, b)) m_colourBorder[a] = m_colourBorder[b] = 1;
        i = j;
      }
    }
    const double meanEdge = edgeCount > 0 ? edgeLengthSum / double(edgeCount) : 1.0;

    // Sharp edges that only make a small knot (a spike, a crease of scanner noise) are no
    // feature: they would lock one another for good. Nor do the turns of a small hole's
    // outline make corners.
    const double smallestFeature = kSmallestFeatureEdges * meanEdge;
    dropSmallComponents(sharpEdges, smallestFeature);
    std::vector<Edge> outlineTurns = boundaryEdges;
    dropSmallComponents(outlineTurns, smallestFeature);
    std::vector<std::uint8_t> cornersByTurn(m_vertexCount, 0);
    for (const Edge& e : outlineTurns) cornersByTurn[e.a] = cornersByTurn[e.b] = 1;

    // Per vertex: its boundary and sharp edges, and the first two neighbours along them.
    std::vector<std::uint32_t> boundaryCount(m_vertexCount, 0), sharpCount(m_vertexCount, 0);
    std::vector<std::uint32_t> boundaryNeighbour(2 * std::size_t(m_vertexCount), kNone);
    std::vector<std::uint32_t> sharpNeighbour(2 * std::size_t(m_vertexCount), kNone);
    auto count = [](const std::vector<Edge>& edges, std::vector<std::uint32_t>& counts, std::vector<std::uint32_t>& slots) {
      for (const Edge& e : edges)
        for (auto [v, x] : {std::pair{e.a, e.b}, std::pair{e.b, e.a}}) {
          if (counts[v] < 2) slots[2 * v + counts[v]] = x;
          ++counts[v];
        }
    };
    count(boundaryEdges, boundaryCount, boundaryNeighbour);
    count(sharpEdges, sharpCount, sharpNeighbour);

    // A line through v turns sharply when its two edges are far from collinear.
    auto turns = [&](std::uint32_t v, const std::vector<std::uint32_t>& slots) {
      return turnsSharply(slots[2 * v], v, slots[2 * v + 1]);
    };
    m_class.assign(m_vertexCount, VertexClass::Complex);
    for (std::uint32_t v = 0; v < m_vertexCount; ++v) {
      const auto triangles = static_cast<std::uint32_t>(m_fan[v].size());  // all alive at set-up
      if (triangles == 0 || nonManifold[v]) continue;
      const bool closedDisk =
          boundaryCount[v] == 0 && neighbours[v] == triangles && m_closedAround[v] && fanIsOneCycle(v);
      const bool openDisk = boundaryCount[v] == 2 && neighbours[v] == triangles + 1;
      if (openDisk) {
        const bool corner = sharpCount[v] > 0 || (cornersByTurn[v] && turns(v, boundaryNeighbour));
        m_class[v] = corner ? VertexClass::Corner : VertexClass::Boundary;
      } else if (closedDisk) {
        if (sharpCount[v] == 0) m_class[v] = VertexClass::Simple;
        else if (sharpCount[v] == 1) m_class[v] = VertexClass::SharpEdge;  // where a crease fades out
        else if (sharpCount[v] == 2 && !turns(v, sharpNeighbour)) m_class[v] = VertexClass::SharpEdge;
        else m_class[v] = VertexClass::Corner;
      }
    }
    classifySeams();
    labelLines(sharpEdges);
    return meanEdge;
  }

  // A vertex split across a texture seam has a twin at its position on the seam's other
  // side. Where both are boundary vertices of the split surface (the seam runs straight on
  // through them) they are Seam vertices, which move together (addTwins); twins in any
  // other arrangement, and positions held by three or more vertices, stay put, since
  // gathering one alone would part the seam's sides.
  void classifySeams() {
    m_twin = positionTwins(m_mesh.positions);
    const std::vector<std::uint32_t> held = keepSeamTwins(
        m_twin, m_partition, [&](std::uint32_t v) { return m_class[v] == VertexClass::Boundary; });
    for (std::uint32_t v = 0; v < m_vertexCount; ++v)
      if (m_twin[v] != kNoTwin) m_class[v] = VertexClass::Seam;
    for (std::uint32_t v : held) m_class[v] = VertexClass::Complex;
  }

  // Whether v's triangles (every edge at v run both ways) make one cycle around it, each
  // triangle's corner after v being the next one's corner before v: a consistently wound
  // disk, where two fans pinched together at v make two cycles.
  bool fanIsOneCycle(std::uint32_t v) const {
    const std::span<const std::uint32_t> fan = m_fan[v];
    std::size_t length = 0;
    std::uint32_t t = fan.front();
    do {
      const std::uint32_t after = cornerAfter(&m_corner[3 * t], v);
      auto startsAtAfter = [&](std::uint32_t u) { return cornerBefore(&m_corner[3 * u], v) == after; };
      const auto next = std::find_if(fan.begin(), fan.end(), startsAtAfter);
      if (next == fan.end()) return false;
      t = *next;
      ++length;
    } while (t != fan.front() && length < fan.size());
    return t == fan.front() && length == fan.size();
  }

  // Removes the edges of connected components (through shared vertices) whose bounding
  // box is smaller than `smallest` across.
  void dropSmallComponents(std::vector<Edge>& edges, double smallest) {
    UnionFind components(m_vertexCount);
    for (const Edge& e : edges) components.join(e.a, e.b);
    std::vector<glm::dvec3> lo(m_vertexCount, glm::dvec3(std::numeric_limits<double>::max()));
    std::vector<glm::dvec3> hi(m_vertexCount, glm::dvec3(std::numeric_limits<double>::lowest()));
    for (const Edge& e : edges)
      for (std::uint32_t v : {e.a, e.b}) {
        const std::uint32_t c = components.find(v);
        lo[c] = glm::min(lo[c], m_position[v]);
        hi[c] = glm::max(hi[c], m_position[v]);
      }
    std::erase_if(edges, [&](const Edge& e) {
      const std::uint32_t c = components.find(e.a);
      return glm::length(hi[c] - lo[c]) < smallest;
    });
  }

  // Feature lines: sharp edges joined through sharp-edge vertices (corners split them);
  // corners remember the lines that end at them, so they may gather along those.
  void labelLines(const std::vector<Edge>& sharpEdges) {
    UnionFind lines(m_vertexCount);
    for (const Edge& e : sharpEdges)
      if (m_class[e.a] == VertexClass::SharpEdge && m_class[e.b] == VertexClass::SharpEdge) lines.join(e.a, e.b);
    m_line.resize(m_vertexCount);
    for (std::uint32_t v = 0; v < m_vertexCount; ++v) m_line[v] = lines.find(v);
    for (const Edge& e : sharpEdges) {
      if (m_class[e.a] == VertexClass::Corner && m_class[e.b] == VertexClass::SharpEdge)
        m_cornerLines.push_back(lineKey(e.a, m_line[e.b]));
      if (m_class[e.b] == VertexClass::Corner && m_class[e.a] == VertexClass::SharpEdge)
        m_cornerLines.push_back(lineKey(e.b, m_line[e.a]));
    }
    std::sort(m_cornerLines.begin(), m_cornerLines.end());
  }

  static std::uint64_t lineKey(std::uint32_t corner, std::uint32_t line) {
    return (std::uint64_t(corner) << 32) | line;
  }

  // --- One candidate cluster -----------------------------------------------------------

  // The cluster r would gather now (m_members), its priority and error. A cell that holds
  // nothing r may gather grows until it does or covers the bounding box; false then.
  bool evaluate(std::uint32_t r, Evaluation evaluation) {
    for (;;) {
      growTree(r, m_cell[r], evaluation != Evaluation::FirstRing);
      addTwins(r);
      scoreMembers(r);
      dropCostlyMembers();
      if (!m_members.empty() && (evaluation != Evaluation::CheckedTree || validateCluster(r))) break;
      if (!growCell(r)) return false;
    }
    scoreCluster(r);
    return true;
  }

  // Grows r's cell by `cellGrowth`; false when that cannot change r's last tree: the cell
  // left no vertex out, or it already covers the bounding box.
  bool growCell(std::uint32_t r) {
    if (!m_cellLeftOut || m_cell[r] >= m_cellLimit) return false;
    m_cell[r] = std::min(m_cell[r] * m_options.cellGrowth, m_cellLimit);
    return true;
  }

  // Drops the members whose move would flip a triangle or pinch the surface; false when
  // nothing is left to gather, or when the step would remove r's piece of surface whole.
  bool validateCluster(std::uint32_t r) {
    m_dropped.assign(m_members.size(), 0);
    do dropFlippingMembers(r);
    while (dropAPinchingMember(r));
    removeDroppedMembers();
    return !m_members.empty() && keepsATriangle(r);
  }

  // Seed steps 2 and 3: the spanning tree of r over current edges, breadth first, through
  // vertices inside the floating cell (a cube of side tau centred on r), in r's region,
  // that may join r under the classification rules (only r's neighbours unless
  // `wholeTree`). m_treePoint[x].mark == m_stamp marks r and the tree; m_parent holds each
  // member's parent (an index into m_members, kNone for r).
  void growTree(std::uint32_t r, double tau, bool wholeTree) {
    nextStamps();
    const std::uint32_t inTree = m_stamp, outside = m_stamp + 1;  // out of the cell or the region: seen once
    TreePoint* point = m_treePoint.data();
    const std::uint32_t* corner = m_corner.data();
    point[r].mark = inTree;
    // The tree never outgrows kMaxClusterSize: members are written in place, counted by `size`.
    std::uint32_t* members = m_treeMembers.data();
    std::uint32_t* parents = m_treeParents.data();
    std::uint32_t size = 0, cellLeftOut = 0;
    m_seamRoot = m_class[r] == VertexClass::Seam;
    const glm::vec3 centre = point[r].position;
    const auto half = static_cast<float>(0.5 * tau);
    const std::uint32_t region = m_partition.regionOf(r);
    const bool oneRegion = m_partition.regionCount <= 1;
    // Whether the tree has room for more after x, reached from p, was looked at. Whether x
    // was seen, lies in the cell and joins is as good as random, so it is worked out
    // without branches: mispredicted branches here were the builder's largest cost.
    auto consider = [&](std::uint32_t p, std::uint32_t x, std::uint32_t parentIndex) {
      TreePoint& at = point[x];
      const std::uint32_t mark = at.mark;
      const glm::vec3 offset = at.position - centre;  // std::fabs below: glm::abs branches on the sign
      const std::uint32_t unseen = std::uint32_t(mark != inTree) & std::uint32_t(mark != outside);
      const std::uint32_t inCell = std::uint32_t(std::fabs(offset.x) <= half) &
                                   std::uint32_t(std::fabs(offset.y) <= half) &
                                   std::uint32_t(std::fabs(offset.z) <= half);
      const std::uint32_t inRegion = oneRegion || m_partition.regionOf(x) == region;
      std::uint32_t joins = unseen & inCell & inRegion;
      // Joining along a feature depends on the edge x is reached by, so it leaves no mark.
      if (m_class[x] != VertexClass::Simple || (m_useColours && m_colourBorder[x])) [[unlikely]]
        joins = joins && keepsFeature(p, x);
      cellLeftOut |= unseen & (inCell ^ 1u);
      const std::uint32_t seenOutside = unseen & ((inCell & inRegion) ^ 1u);
      const std::uint32_t markOutside = mark + (outside - mark) * seenOutside;
      at.mark = markOutside + (inTree - markOutside) * joins;
      members[size] = x;  // kept only if x joins
      parents[size] = parentIndex;
      size += joins;
      return size < kMaxClusterSize;
    };
    // p's neighbours through its live triangles; around a vertex with every edge run both
    // ways, each neighbour is the corner after p in exactly one triangle.
    auto visit = [&](std::uint32_t p, std::uint32_t parentIndex) {
      const bool closed = m_closedAround[p];
      for (std::uint32_t t : m_fan[p]) {
        const std::uint32_t* c = corner + 3 * t;
        if (!consider(p, cornerAfter(c, p), parentIndex)) return false;
        if (!closed && !consider(p, cornerBefore(c, p), parentIndex)) return false;
      }
      return true;
    };
    // Breadth first: the fans of the members queued so far are loaded while the first of
    // them is walked.
    std::uint32_t fansLoading = 0;
    if (visit(r, kNone) && wholeTree)
      for (std::uint32_t i = 0; i < size; ++i) {
        for (; fansLoading < size; ++fansLoading) m_fan.prefetch(members[fansLoading]);
        if (!visit(members[i], i)) break;
      }
    m_members.assign(members, members + size);
    m_parent.assign(parents, parents + size);
    for (std::uint32_t i = 0; i < size; ++i) m_memberIndex[members[i]] = i;
    m_cellLeftOut = cellLeftOut != 0;
  }

  // Two fresh mark values (the tree's and the outside's); marks are cleared before the
  // counter would wrap.
  void nextStamps() {
    if (m_stamp >= std::numeric_limits<std::uint32_t>::max() - 2) {
      for (TreePoint& p : m_treePoint) p.mark = 0;
      m_stamp = 0;
    }
    m_stamp += 2;
  }

  // Whether x, reached over the edge from p (r or a tree member), may join p's cluster
  // without losing its feature.
  bool keepsFeature(std::uint32_t p, std::uint32_t x) const {
    switch (m_class[x]) {
      case VertexClass::Simple: break;
      case VertexClass::Boundary:
        if (!isBoundaryEdge(p, x)) return false;
        break;
      case VertexClass::Seam:
        // Only onto a seam representative, which takes the twin too: so neither r's twin
        // nor a member's may be in the tree itself (around the seam's end, where its two
        // sides meet, the tree could reach them).
        if (!m_seamRoot || m_treePoint[m_twin[x]].mark == m_stamp || !isBoundaryEdge(p, x)) return false;
        break;
      case VertexClass::SharpEdge:
        if (!onSameLine(p, x)) return false;
        break;
      default: return false;  // corners and complex vertices never join
    }
    // A colour-border vertex joins along its own side of the border.
    return !m_useColours || !m_colourBorder[x] || (m_colourBorder[p] && !coloursDiffer(p, x));
  }

  // Whether neighbours a and b differ in colour by more than kColourBorderTolerance.
  bool coloursDiffer(std::uint32_t a, std::uint32_t b) const {
    const glm::dvec3 d = m_colour[a] - m_colour[b];
    const double tolerance = kColourBorderTolerance * m_options.colourWeight;
    return glm::dot(d, d) > tolerance * tolerance;
  }

  bool isBoundaryEdge(std::uint32_t p, std::uint32_t x) const {
    int shared = 0;
    for (std::uint32_t t : m_fan[p]) {
      if (!m_triangleAlive[t]) continue;
      const std::uint32_t* c = &m_corner[3 * t];
      shared += c[0] == x || c[1] == x || c[2] == x;
    }
    return shared == 1;
  }

  bool onSameLine(std::uint32_t p, std::uint32_t x) const {
    if (m_class[p] == VertexClass::SharpEdge) return m_line[p] == m_line[x];
    if (m_class[p] == VertexClass::Corner)
      return std::binary_search(m_cornerLines.begin(), m_cornerLines.end(), lineKey(p, m_line[x]));
    return false;
  }

  // Seed step 3, "vertices that can be clustered": a member whose cost is far above the
  // cluster's mean (across a ridge, up a flank) stays out, with its subtree, so clusters
  // follow the directions that cost little (along a cylinder rather than around it).
  void dropCostlyMembers() {
    if (m_members.size() < 2) return;
    m_dropped.assign(m_members.size(), 0);
    double sum = 0.0;
    for (const MemberScore& score : m_memberScore) sum += score.cost;
    const double limit = kOutlierFactor * sum / double(m_members.size());
    bool anyDropped = false;
    for (std::size_t i = 0; i < m_members.size(); ++i) anyDropped |= m_dropped[i] = m_memberScore[i].cost > limit;
    if (!anyDropped) return;
    dropSubtrees();
    removeDroppedMembers();
  }

  // Drops members whose move onto r would flip a surviving triangle, until none does.
  void dropFlippingMembers(std::uint32_t r) {
    for (bool changed = true; changed;) {
      changed = false;
      for (std::size_t i = 0; i < m_members.size(); ++i) {
        if (m_dropped[i]) continue;
        if (moveFlipsATriangle(m_members[i], r)) m_dropped[i] = 1, changed = true;
      }
      if (changed) dropSubtrees();
    }
  }

  // A dropped member takes its subtree along, so the cluster stays one tree (parents come
  // before their children in m_members); dropped members lose their mark.
  // A dropped twin takes its partner (its parent) along too, so seams never part.
  void dropSubtrees() {
    for (bool partnerDropped = true; partnerDropped;) {
      partnerDropped = false;
      for (std::size_t i = 0; i < m_members.size(); ++i)
        if (!m_dropped[i] && m_parent[i] != kNone && m_dropped[m_parent[i]]) m_dropped[i] = 1;
      for (std::size_t i = 0; m_rTwin != kNone && i < m_members.size(); ++i)
        if (m_dropped[i] && isTwinEntry(i) && !m_dropped[m_parent[i]]) m_dropped[m_parent[i]] = 1, partnerDropped = true;
    }
    for (std::size_t i = 0; i < m_members.size(); ++i)
      if (m_dropped[i]) m_treePoint[m_members[i]].mark = 0;
  }

  // Whether member i is a seam member's twin (added by addTwins, the partner its parent).
  bool isTwinEntry(std::size_t i) const {
    return m_rTwin != kNone && m_parent[i] != kNone && m_twin[m_members[i]] == m_members[m_parent[i]];
  }

  // Seed step 4 across a texture seam: every seam member's twin joins r's twin, each as its
  // partner's child in the tree (it goes where its partner goes). r's twin is marked like
  // r, so the other side's triangles that lose their edge vanish just as r's side's do;
  // twins share their partners' positions, so costs and checks at r hold for them.
  void addTwins(std::uint32_t r) {
    m_rTwin = kNone;
    if (m_class[r] != VertexClass::Seam) return;
    const std::size_t treeSize = m_members.size();
    for (std::size_t i = 0; i < treeSize; ++i) {
      const std::uint32_t x = m_members[i];
      if (m_class[x] != VertexClass::Seam) continue;
      const std::uint32_t twin = m_twin[x];
      m_treePoint[twin].mark = m_stamp;
      m_members.push_back(twin);
      m_parent.push_back(static_cast<std::uint32_t>(i));
      m_memberIndex[twin] = static_cast<std::uint32_t>(m_members.size() - 1);
      m_rTwin = m_twin[r];
    }
    if (m_rTwin != kNone) m_treePoint[m_rTwin].mark = m_stamp;
  }

  // Where member i goes: r, or r's twin for a seam member's twin.
  std::uint32_t targetOf(std::size_t i, std::uint32_t r) const { return isTwinEntry(i) ? m_rTwin : r; }

  // The step must not pinch the surface: a vertex x next to the cluster keeps one fan.
  // Its triangles that keep a marked corner all end up on the edge (r, x), so more than
  // two of them would make that edge non-manifold (the cluster reaches round x from two
  // sides), and none left at all would leave x isolated. Drops the last member next to
  // the first such x (with its subtree); returns whether it dropped one.
  bool dropAPinchingMember(std::uint32_t r) {
    ++m_linkStamp;
    m_touched.clear();
    auto countTriangles = [&](std::uint32_t v) {
      for (std::uint32_t t : m_fan[v]) {
        if (!m_triangleAlive[t] || m_triangleSeen[t] == m_linkStamp) continue;
        m_triangleSeen[t] = m_linkStamp;
        const bool vanishing = vanishes(t);
        for (int k = 0; k < 3; ++k) {
          const std::uint32_t x = m_corner[3 * t + k];
          if (m_treePoint[x].mark == m_stamp) continue;
          if (m_linkSeen[x] != m_linkStamp) {
            m_linkSeen[x] = m_linkStamp;
            m_keptOnEdge[x] = m_vanishing[x] = 0;
            m_touched.push_back(x);
          }
          ++(vanishing ? m_vanishing[x] : m_keptOnEdge[x]);
        }
      }
    };
    countTriangles(r);
    if (m_rTwin != kNone) countTriangles(m_rTwin);
    for (std::size_t i = 0; i < m_members.size(); ++i)
      if (!m_dropped[i]) countTriangles(m_members[i]);
    for (std::uint32_t x : m_touched) {
      if (m_class[x] == VertexClass::Complex) continue;  // not one fan to begin with
      const bool pinched = m_keptOnEdge[x] > 2;
      const bool isolated = m_keptOnEdge[x] == 0 && m_vanishing[x] == liveTriangleCount(x);
      if (!pinched && !isolated) continue;
      std::size_t last = kNone;
      for (std::uint32_t t : m_fan[x]) {
        if (!m_triangleAlive[t]) continue;
        for (int k = 0; k < 3; ++k) {
          const std::uint32_t y = m_corner[3 * t + k];
          if (y == r || y == m_rTwin || m_treePoint[y].mark != m_stamp) continue;
          if (last == kNone || m_memberIndex[y] > last) last = m_memberIndex[y];
        }
      }
      if (last == kNone) continue;  // only r is next to x: r's own fan, unchanged by the step
      m_dropped[last] = 1;
      dropSubtrees();
      return true;
    }
    return false;
  }

  std::uint32_t liveTriangleCount(std::uint32_t x) const {
    std::uint32_t count = 0;
    for (std::uint32_t t : m_fan[x]) count += m_triangleAlive[t];
    return count;
  }

  // Compacts m_members and their scores, renumbering parents (a kept member's parent is kept too).
  void removeDroppedMembers() {
    m_newIndex.resize(m_members.size());
    std::uint32_t kept = 0;
    for (std::size_t i = 0; i < m_members.size(); ++i) {
      if (m_dropped[i]) continue;
      m_newIndex[i] = kept;
      m_members[kept] = m_members[i];
      m_parent[kept] = m_parent[i] == kNone ? kNone : m_newIndex[m_parent[i]];
      m_memberScore[kept] = m_memberScore[i];
      m_memberIndex[m_members[kept]] = kept;
      ++kept;
    }
    m_members.resize(kept);
    m_parent.resize(kept);
    m_memberScore.resize(kept);
  }

  // Whether moving member v onto r turns a triangle that keeps existing (one with no other
  // marked corner) by more than the limit, or flattens it.
  bool moveFlipsATriangle(std::uint32_t v, std::uint32_t r) const {
    for (std::uint32_t t : m_fan[v]) {
      if (!m_triangleAlive[t] || vanishes(t)) continue;
      const std::uint32_t* c = &m_corner[3 * t];
      glm::dvec3 p[3], q[3];
      for (int k = 0; k < 3; ++k) {
        p[k] = m_position[c[k]];
        q[k] = c[k] == v ? m_position[r] : p[k];
      }
      const glm::dvec3 before = glm::cross(p[1] - p[0], p[2] - p[0]);
      const glm::dvec3 after = glm::cross(q[1] - q[0], q[2] - q[0]);
      const double beforeLength = glm::length(before);
      if (beforeLength <= 0.0) continue;  // already flat: nothing to flip
      if (!(glm::dot(before, after) > kMinNormalCosine * beforeLength * glm::length(after))) return true;
    }
    return false;
  }

  // Whether triangle t has two or three marked corners (r and the cluster): the step
  // removes it; a triangle with one marked corner is re-pointed at r.
  bool vanishes(std::uint32_t t) const {
    const std::uint32_t* c = &m_corner[3 * t];
    auto marked = [&](std::uint32_t v) { return m_treePoint[v].mark == m_stamp; };
    return marked(c[0]) + marked(c[1]) + marked(c[2]) >= 2;
  }

  // Whether some triangle at the cluster survives the step. If none does, the piece of
  // surface holding r would vanish whole: the coarsest level keeps at least a triangle.
  bool keepsATriangle(std::uint32_t r) const {
    auto survives = [&](std::uint32_t t) { return m_triangleAlive[t] && !vanishes(t); };
    if (std::any_of(m_fan[r].begin(), m_fan[r].end(), survives)) return true;
    for (std::uint32_t v : m_members)
      if (std::any_of(m_fan[v].begin(), m_fan[v].end(), survives)) return true;
    return false;
  }

  // Per member v of the tree just grown (m_memberScore, kept in step with m_members): the
  // cost of moving v's cluster onto r, which is its planes' quadric error and its colours'
  // squared deviation from r's colour (both area-weighted) times v's class weight, plus the
  // compactness tie-breaker; and the mean squared plane distance of v's cluster at r.
  void scoreMembers(std::uint32_t r) {
    const glm::dvec3& at = m_position[r];
    m_memberScore.resize(m_members.size());
    for (std::uint32_t v : m_members) {  // all the members' misses at once, not one after another
      __builtin_prefetch(&m_quadric[v]);
      __builtin_prefetch(reinterpret_cast<const char*>(&m_quadric[v]) + sizeof(Quadric) - 1);
      __builtin_prefetch(&m_position[v]);
    }
    for (std::size_t i = 0; i < m_members.size(); ++i) {
      const std::uint32_t v = m_members[i];
      const Quadric& q = m_quadric[v];
      const double planes = q.evaluate(at);
      double colour = 0.0;
      if (m_useColours) {
        const glm::dvec3& c = m_colour[r];
        colour = std::max(0.0, m_moment0[v] * glm::dot(c, c) - 2.0 * glm::dot(c, m_moment1[v]) + m_moment2[v]);
      }
      const glm::dvec3 d = m_position[v] - at;
      m_memberScore[i].cost = classWeight(m_class[v]) * (planes + colour) + kCompactness * q.weight * glm::dot(d, d);
      m_memberScore[i].meanSquare = q.weight > 0.0 ? planes / q.weight : 0.0;
    }
  }

  // Priority (seed step 1, lowest first): the members' mean cost, so that steps remove
  // vertices where it is cheapest per vertex. Error: the largest RMS plane distance at r
  // of a cluster r holds after the step.
  void scoreCluster(std::uint32_t r) {
    const glm::dvec3& at = m_position[r];
    double sum = 0.0, worstMeanSquare = 0.0;
    if (m_quadric[r].weight > 0.0) worstMeanSquare = m_quadric[r].evaluate(at) / m_quadric[r].weight;
    for (const MemberScore& score : m_memberScore) {
      sum += score.cost;
      worstMeanSquare = std::max(worstMeanSquare, score.meanSquare);
    }
    m_priority = sum / double(m_members.size());
    m_error = static_cast<float>(std::sqrt(worstMeanSquare) * m_diagonal);
  }

  // --- Taking a step -------------------------------------------------------------------

  // Seed step 4: the members (marked, from the last evaluate(r)) join r; triangles with
  // two or three marked corners vanish, the others are re-pointed at r.
  void gather(std::uint32_t r) {
    for (std::size_t i = 0; i < m_members.size(); ++i) {
      const std::uint32_t v = m_members[i], target = targetOf(i, r);
      for (std::uint32_t t : m_fan[v]) {
        if (!m_triangleAlive[t]) continue;
        if (vanishes(t)) {
          m_triangleAlive[t] = 0;
          --m_liveTriangles;
          // Out of its unmarked corner's fan too (the members' fans go, r's is compacted),
          // so every fan holds live triangles only.
          for (int k = 0; k < 3; ++k)
            if (const std::uint32_t x = m_corner[3 * t + k]; m_treePoint[x].mark != m_stamp) {
              m_fan.erase(x, t);
            }
          continue;
        }
        for (int k = 0; k < 3; ++k)
          if (m_corner[3 * t + k] == v) m_corner[3 * t + k] = target;
        m_fan.push(target, t);
      }
      m_fan.clear(v);
      m_alive[v] = 0;
      m_queue.remove(v);
      m_quadric[target] += m_quadric[v];
      if (m_useColours) {
        m_moment0[target] += m_moment0[v];
        m_moment1[target] += m_moment1[v];
        m_moment2[target] += m_moment2[v];
      }
    }
    compactFan(r);  // the only fans that grow: keep them free of dead triangles
    if (m_rTwin != kNone) compactFan(m_rTwin);
  }

  void compactFan(std::uint32_t v) {
    m_fan.eraseIf(v, [&](std::uint32_t t) { return !m_triangleAlive[t]; });
  }

  // Seed step 6 updates the weights of the representative's neighbours: a corner or
  // feature-line vertex around which the current mesh has no sharp edge left (a crease of
  // noise that the coarser mesh smoothed over) becomes simple, a boundary corner whose
  // current outline runs straight on becomes a boundary vertex. Classes only ever relax,
  // so a smooth surface never grows features, and a real crease keeps its sharp edges.
  bool demoteFadedFeature(std::uint32_t x) {
    if (m_class[x] != VertexClass::Corner && m_class[x] != VertexClass::SharpEdge) return false;
    compactFan(x);
    m_links.clear();
    for (std::uint32_t t : m_fan[x])
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t y = m_corner[3 * t + k];
        if (y == x) continue;
        auto link = std::find_if(m_links.begin(), m_links.end(), [y](const Link& l) { return l.vertex == y; });
        if (link == m_links.end()) m_links.push_back({y, 1, t, kNone});
        else if (++link->triangles == 2) link->second = t;
      }
    std::uint32_t boundary[2] = {kNone, kNone};
    int boundaryEdges = 0;
    for (const Link& l : m_links) {
      if (l.triangles > 2) return false;
      if (l.triangles == 1) {
        if (boundaryEdges < 2) boundary[boundaryEdges] = l.vertex;
        ++boundaryEdges;
      } else if (isSharp(x, l.vertex, l.first, l.second)) {
        return false;
      }
    }
    if (boundaryEdges == 0) {
      m_class[x] = VertexClass::Simple;
      return true;
    }
    if (boundaryEdges != 2 || m_class[x] != VertexClass::Corner || turnsSharply(boundary[0], x, boundary[1]))
      return false;
    m_class[x] = VertexClass::Boundary;
    return true;
  }

  // Whether the line a -> v -> b turns at v by more than the feature angle (its two edges
  // far from collinear), or has an edge of no length.
  bool turnsSharply(std::uint32_t a, std::uint32_t v, std::uint32_t b) const {
    const glm::dvec3 in = m_position[v] - m_position[a], out = m_position[b] - m_position[v];
    const double lengths = glm::length(in) * glm::length(out);
    return !(lengths > 0.0) || glm::dot(in, out) < m_featureCosine * lengths;
  }

  // Whether the current triangles s and t on edge (x, y) meet at more than the feature angle.
  bool isSharp(std::uint32_t x, std::uint32_t y, std::uint32_t s, std::uint32_t t) const {
    auto runsForward = [&](std::uint32_t u) { return cornerAfter(&m_corner[3 * u], x) == y; };  // x -> y
    const glm::dvec3 ns = triangleCross(m_position, &m_corner[3 * s]);
    const glm::dvec3 nt = triangleCross(m_position, &m_corner[3 * t]) * (runsForward(s) != runsForward(t) ? 1.0 : -1.0);
    const double lengths = glm::length(ns) * glm::length(nt);
    return lengths > 0.0 && glm::dot(ns, nt) < m_featureCosine * lengths;
  }

  // A step changes only the edges at r: r is closed around if each of its edges now has one
  // triangle running each way, and a neighbour x that was stays so if edge (r, x) does.
  void updateClosedAround(std::uint32_t r) {
    ++m_linkStamp;
    for (std::uint32_t t : m_fan[r]) {
      const std::uint32_t* c = &m_corner[3 * t];
      const std::uint32_t after = cornerAfter(c, r), before = cornerBefore(c, r);
      for (std::uint32_t x : {after, before})
        if (m_linkSeen[x] != m_linkStamp) m_linkSeen[x] = m_linkStamp, m_runsFromR[x] = m_runsToR[x] = 0;
      ++m_runsFromR[after];
      ++m_runsToR[before];
    }
    bool closed = true;
    for (std::uint32_t x : m_ring) {
      if (m_runsFromR[x] == 1 && m_runsToR[x] == 1) continue;
      m_closedAround[x] = 0;
      closed = false;
    }
    m_closedAround[r] = closed;
  }

  // r's current neighbours, each once (gather left r's fan free of dead triangles).
  void collectRing(std::uint32_t r) {
    m_ring.clear();
    ++m_ringStamp;
    m_ringMark[r] = m_ringStamp;
    for (std::uint32_t t : m_fan[r])
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t x = m_corner[3 * t + k];
        if (m_ringMark[x] == m_ringStamp) continue;
        m_ringMark[x] = m_ringStamp;
        m_ring.push_back(x);
      }
  }

  const TriangleMesh& m_mesh;
  const RegionPartition& m_partition;
  const ClusterOptions& m_options;
  StepListener* m_listener;  // may be null
  std::uint32_t m_vertexCount = 0;
  double m_diagonal = 1.0;
  double m_cellLimit = 2.0;
  double m_featureCosine = 0.0;
  std::vector<glm::dvec3> m_position;  // translated and scaled to a unit diagonal
  std::vector<std::uint32_t> m_corner;
  std::vector<std::uint8_t> m_triangleAlive;
  std::uint32_t m_liveTriangles = 0;
  TriangleFans m_fan;  // live triangles only (gather drops the dead)
  std::vector<Quadric> m_quadric;                 // per vertex: the planes of its cluster
  bool m_useColours = false;
  std::vector<glm::dvec3> m_colour;  // RGB times colourWeight
  std::vector<double> m_moment0, m_moment2;
  std::vector<glm::dvec3> m_moment1;
  std::vector<VertexClass> m_class;
  std::vector<std::uint8_t> m_colourBorder;
  // Every edge at the vertex has two triangles, one running each way (set up, then kept by
  // updateClosedAround).
  std::vector<std::uint8_t> m_closedAround;
  std::vector<std::uint32_t> m_twin;  // a Seam vertex's twin (classifySeams), else kNoTwin
  std::vector<std::uint32_t> m_line;         // feature line of a sharp-edge vertex
  std::vector<std::uint64_t> m_cornerLines;  // sorted lineKey(corner, line) of lines ending at corners
  std::vector<std::uint8_t> m_alive;
  std::vector<double> m_cell;  // per vertex: its floating cell's size tau
  IndexedMinHeap m_queue;  // vertices with something to gather, by priority
  // Scratch of the last evaluation.
  std::vector<TreePoint> m_treePoint;
  std::vector<std::uint32_t> m_ringMark;
  std::uint32_t m_stamp = 0, m_ringStamp = 0;
  std::vector<std::uint32_t> m_members, m_parent, m_ring;
  std::array<std::uint32_t, kMaxClusterSize> m_treeMembers, m_treeParents;  // growTree's room
  std::vector<std::uint8_t> m_dropped;
  std::vector<Link> m_links;
  std::vector<std::uint32_t> m_memberIndex;  // per vertex: its index in m_members when marked
  // Pinch check scratch: per vertex and per triangle stamps, per vertex counts.
  std::uint32_t m_linkStamp = 0;
  std::vector<std::uint32_t> m_linkSeen, m_triangleSeen, m_keptOnEdge, m_vanishing, m_touched;
  std::vector<std::uint32_t> m_runsFromR, m_runsToR;  // updateClosedAround: edge (r, x)'s triangles each way
  std::vector<MemberScore> m_memberScore;
  std::vector<std::uint32_t> m_newIndex;
  double m_priority = 0.0;
  float m_error = 0.0f;
  bool m_cellLeftOut = false;            // the last tree's cell left out a vertex it could have reached
  bool m_seamRoot = false;               // the tree being grown is a Seam vertex's
  std::uint32_t m_rTwin = kNone;         // the last evaluation's twin target (addTwins), or kNone
  std::vector<std::uint32_t> m_targets;  // per member of a step across a seam: targetOf
};

}  // namespace

Result<SimplificationSteps> buildClusterSteps(const TriangleMesh& mesh, const RegionPartition& partition,
                                              const ClusterOptions& options) {
  return buildClusterSteps(mesh, partition, options, nullptr);
}

Result<SimplificationSteps> buildClusterSteps(const TriangleMesh& mesh, const RegionPartition& partition,
                                              const ClusterOptions& options, StepListener* listener) {
  if (Status s = validateMesh(mesh, "cluster builder input"); !s) return s.error();
  if (Status s = validatePartition(partition, mesh.vertexCount(), "cluster builder regions"); !s) return s.error();
  if (!(options.initialCellFraction >= 0.0) || !std::isfinite(options.initialCellFraction))
    return makeError(ErrorKind::InvalidArgument, "cluster builder: initialCellFraction must be finite and >= 0");
  if (!(options.cellGrowth > 1.0) || !std::isfinite(options.cellGrowth))
    return makeError(ErrorKind::InvalidArgument, "cluster builder: cellGrowth must be finite and > 1");
  if (!(options.colourWeight >= 0.0) || !std::isfinite(options.colourWeight))
    return makeError(ErrorKind::InvalidArgument, "cluster builder: colourWeight must be finite and >= 0");
  if (!(options.featureAngleDegrees >= 0.0 && options.featureAngleDegrees <= 180.0))
    return makeError(ErrorKind::InvalidArgument, "cluster builder: featureAngleDegrees must lie in [0, 180]");
  return buildInLocalityOrder(mesh, partition, listener, [&](const TriangleMesh& ordered, const RegionPartition& regions) {
    return ClusterBuilder(ordered, regions, options, listener).run();
  });
}

}  // namespace polder::mesh
