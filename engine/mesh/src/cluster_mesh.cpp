#include "cluster_mesh.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <utility>

#include "builder_setup.hpp"
#include "triangle_planes.hpp"

namespace polder::mesh::cluster {

namespace {

// Planes through boundary edges hold the outline: this times the edge length squared (the
// collapse builder's boundaryWeight).
constexpr double kBoundaryWeight = 4.0;
// Sharp edges and outlines that span less than this many mean edge lengths are noise.
constexpr double kSmallestFeatureEdges = 4.0;
// Neighbours whose RGB colours differ by more than this lie on a colour border.
constexpr double kColourBorderTolerance = 0.2;

struct Edge {
  std::uint32_t a, b;
};

// One side of an edge (lo, hi), lo < hi, of the original mesh, for classification (lo is
// implied).
struct EdgeSide {
  std::uint32_t hi, triangle;
  bool forward;  // the triangle runs lo -> hi
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

class ClusterMeshSetup {
 public:
  ClusterMeshSetup(const TriangleMesh& input, const RegionPartition& partition, const ClusterOptions& options,
                   core::ThreadPool& pool, ClusterMesh& mesh)
      : m_input(input), m_partition(partition), m_options(options), m_pool(pool), m_mesh(mesh) {}

  void run() {
    m_mesh.vertexCount = static_cast<std::uint32_t>(m_input.vertexCount());
    NormalizedPositions normalized = normalizePositions(m_input.positions);
    m_mesh.diagonal = normalized.diagonal;
    m_mesh.position = std::move(normalized.positions);
    const glm::dvec3 extent = normalized.extent;
    // A cell of twice the largest extent covers the bounding box wherever it is centred.
    m_mesh.cellLimit = 2.0 * std::max(extent.x, std::max(extent.y, extent.z)) + 1e-9;

    // Live triangles (degenerate input ones are skipped), fans and planes; each vertex's
    // quadric sums its fan's planes in triangle order, as adding each triangle to its
    // corners one after the other would.
    m_mesh.corner = liveTriangleCorners(m_input);
    const auto triangleCount = static_cast<std::uint32_t>(m_mesh.corner.size() / 3);
    m_mesh.liveTriangles = triangleCount;
    m_mesh.triangleAlive.assign(triangleCount, 1);
    const std::vector<WeightedPlane> plane = fillFansAndPlanes(m_pool, m_mesh.position, m_mesh.corner, m_mesh.fan);
    m_mesh.quadric.resize(m_mesh.vertexCount);
    m_pool.runHalves([&](int half) {
      const auto [begin, end] = halfOf(m_mesh.vertexCount, half);
      for (std::uint32_t v = begin; v < end; ++v) {
        Quadric sum;
        for (std::uint32_t t : m_mesh.fan[v]) sum.addPlane(plane[t].normal, plane[t].offset, plane[t].weight);
        m_mesh.quadric[v] = sum;
      }
    });
    setUpColours(plane);
    const double meanEdge = classify(plane);

    // Vertices on no triangle take no part.
    m_mesh.alive.resize(m_mesh.vertexCount);
    for (std::uint32_t v = 0; v < m_mesh.vertexCount; ++v) m_mesh.alive[v] = !m_mesh.fan[v].empty();
    m_mesh.queuedKey.assign(m_mesh.vertexCount, 0.0f);
    m_mesh.stale.assign(m_mesh.vertexCount, 1);
    // The paper: cells start as a uniform subdivision of the bounding box with size tau0.
    const double tau0 = m_options.initialCellFraction > 0.0 ? m_options.initialCellFraction : 2.0 * meanEdge;
    m_mesh.cell.assign(m_mesh.vertexCount, std::min(std::max(tau0, 1e-12), m_mesh.cellLimit));
  }

 private:
  // Area-weighted colour moments per cluster, so a cluster's squared colour deviation from
  // any colour costs O(1) (as in the collapse builder); a triangle's plane weighs its area.
  void setUpColours(const std::vector<WeightedPlane>& plane) {
    m_mesh.useColours = m_input.hasColours() && m_options.colourWeight > 0.0;
    if (!m_mesh.useColours) return;
    m_mesh.colourTolerance = kColourBorderTolerance * m_options.colourWeight;
    m_mesh.colour.resize(m_mesh.vertexCount);
    for (std::uint32_t v = 0; v < m_mesh.vertexCount; ++v)
      m_mesh.colour[v] = glm::dvec3(m_input.colours[v]) * m_options.colourWeight;
    m_mesh.moment0.assign(m_mesh.vertexCount, 0.0);
    for (std::uint32_t t = 0; t < plane.size(); ++t)
      for (int k = 0; k < 3; ++k) m_mesh.moment0[m_mesh.corner[3 * t + k]] += plane[t].weight / 3.0;
    m_mesh.moment1.resize(m_mesh.vertexCount);
    m_mesh.moment2.resize(m_mesh.vertexCount);
    for (std::uint32_t v = 0; v < m_mesh.vertexCount; ++v) {
      m_mesh.moment1[v] = m_mesh.moment0[v] * m_mesh.colour[v];
      m_mesh.moment2[v] = m_mesh.moment0[v] * glm::dot(m_mesh.colour[v], m_mesh.colour[v]);
    }
  }

  // What a scan of the edges (a, b), a < b, with a in one half of the vertices found: per
  // vertex counts and flags (b may lie in the other half), and the edges in scan order.
  struct EdgeScan {
    std::vector<std::uint32_t> neighbours;
    std::vector<std::uint8_t> open;  // an edge at the vertex lacks one triangle running each way
    std::vector<std::uint8_t> nonManifold, colourBorder;
    std::vector<Edge> sharpEdges, boundaryEdges;
    std::vector<std::uint32_t> boundaryTriangle;  // per boundary edge
    std::vector<double> edgeLength;               // per edge
  };

  // Each edge (a, b), a < b, with a in [begin, end) once: from a's fan, with its sides.
  void scanEdges(std::uint32_t begin, std::uint32_t end, const std::vector<WeightedPlane>& plane,
                 EdgeScan& scan) const {
    scan.neighbours.assign(m_mesh.vertexCount, 0);
    scan.open.assign(m_mesh.vertexCount, 0);
    scan.nonManifold.assign(m_mesh.vertexCount, 0);
    scan.colourBorder.assign(m_mesh.vertexCount, 0);
    std::vector<EdgeSide> sides;
    for (std::uint32_t a = begin; a < end; ++a) {
      sides.clear();
      for (std::uint32_t t : m_mesh.fan[a]) {
        const std::uint32_t* c = &m_mesh.corner[3 * t];
        if (const std::uint32_t after = cornerAfter(c, a); after > a) sides.push_back({after, t, true});
        if (const std::uint32_t before = cornerBefore(c, a); before > a) sides.push_back({before, t, false});
      }
      std::sort(sides.begin(), sides.end(), [](const EdgeSide& x, const EdgeSide& y) { return x.hi < y.hi; });
      for (std::size_t i = 0; i < sides.size();) {
        std::size_t j = i + 1;
        while (j < sides.size() && sides[j].hi == sides[i].hi) ++j;
        const std::uint32_t b = sides[i].hi;
        ++scan.neighbours[a], ++scan.neighbours[b];
        if (j - i != 2 || sides[i].forward == sides[i + 1].forward) scan.open[a] = scan.open[b] = 1;
        scan.edgeLength.push_back(glm::length(m_mesh.position[a] - m_mesh.position[b]));
        if (j - i == 1) {
          scan.boundaryEdges.push_back({a, b});
          scan.boundaryTriangle.push_back(sides[i].triangle);
        } else if (j - i == 2) {
          const glm::dvec3 n0 = plane[sides[i].triangle].normal;
          // Two consistently oriented triangles run the edge in opposite directions.
          const double flip = sides[i].forward != sides[i + 1].forward ? 1.0 : -1.0;
          const glm::dvec3 n1 = plane[sides[i + 1].triangle].normal * flip;
          if (glm::dot(n0, n0) > 0.0 && glm::dot(n1, n1) > 0.0 && glm::dot(n0, n1) < m_mesh.featureCosine)
            scan.sharpEdges.push_back({a, b});
        } else {
          scan.nonManifold[a] = scan.nonManifold[b] = 1;
        }
        if (m_mesh.useColours && m_mesh.coloursDiffer(a, b)) scan.colourBorder[a] = scan.colourBorder[b] = 1;
        i = j;
      }
    }
  }

  // Classifies every vertex into the paper's categories from the edges around it, labels
  // feature lines, adds boundary planes; returns the mean edge length.
  double classify(const std::vector<WeightedPlane>& plane) {
    m_mesh.featureCosine = std::cos(m_options.featureAngleDegrees * 3.14159265358979323846 / 180.0);
    std::array<EdgeScan, 2> scan;
    m_pool.runHalves([&](int half) {
      const auto [begin, end] = halfOf(m_mesh.vertexCount, half);
      scanEdges(begin, end, plane, scan[half]);
    });
    // The per-vertex findings of both halves, in the first's arrays.
    std::vector<std::uint32_t>& neighbours = scan[0].neighbours;
    std::vector<std::uint8_t>& nonManifold = scan[0].nonManifold;
    m_mesh.closedAround.resize(m_mesh.vertexCount);
    for (std::uint32_t v = 0; v < m_mesh.vertexCount; ++v) {
      neighbours[v] += scan[1].neighbours[v];
      m_mesh.closedAround[v] = !(scan[0].open[v] | scan[1].open[v]);
      nonManifold[v] |= scan[1].nonManifold[v];
      scan[0].colourBorder[v] |= scan[1].colourBorder[v];
    }
    m_mesh.colourBorder = std::move(scan[0].colourBorder);
    // In the order of one scan over all vertices.
    std::vector<Edge> sharpEdges, boundaryEdges;
    double edgeLengthSum = 0.0;
    std::size_t edgeCount = 0;
    for (const EdgeScan& half : scan) {
      sharpEdges.insert(sharpEdges.end(), half.sharpEdges.begin(), half.sharpEdges.end());
      boundaryEdges.insert(boundaryEdges.end(), half.boundaryEdges.begin(), half.boundaryEdges.end());
      for (std::size_t e = 0; e < half.boundaryEdges.size(); ++e) {
        const auto [a, b] = half.boundaryEdges[e];
        addBoundaryEdgeQuadric(m_mesh.position[a], m_mesh.position[b], plane[half.boundaryTriangle[e]].normal,
                               kBoundaryWeight, m_mesh.quadric[a], m_mesh.quadric[b]);
      }
      for (double length : half.edgeLength) edgeLengthSum += length;
      edgeCount += half.edgeLength.size();
    }
    const double meanEdge = edgeCount > 0 ? edgeLengthSum / double(edgeCount) : 1.0;

    // Sharp edges that only make a small knot (a spike, a crease of scanner noise) are no
    // feature: they would lock one another for good. Nor do the turns of a small hole's
    // outline make corners.
    const double smallestFeature = kSmallestFeatureEdges * meanEdge;
    dropSmallComponents(sharpEdges, smallestFeature);
    std::vector<Edge> outlineTurns = boundaryEdges;
    dropSmallComponents(outlineTurns, smallestFeature);
    std::vector<std::uint8_t> cornersByTurn(m_mesh.vertexCount, 0);
    for (const Edge& e : outlineTurns) cornersByTurn[e.a] = cornersByTurn[e.b] = 1;

    // Per vertex: its boundary and sharp edges, and the first two neighbours along them.
    std::vector<std::uint32_t> boundaryCount(m_mesh.vertexCount, 0), sharpCount(m_mesh.vertexCount, 0);
    std::vector<std::uint32_t> boundaryNeighbour(2 * std::size_t(m_mesh.vertexCount), kNone);
    std::vector<std::uint32_t> sharpNeighbour(2 * std::size_t(m_mesh.vertexCount), kNone);
    auto count = [](const std::vector<Edge>& edges, std::vector<std::uint32_t>& counts,
                    std::vector<std::uint32_t>& slots) {
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
      return m_mesh.turnsSharply(slots[2 * v], v, slots[2 * v + 1]);
    };
    // Each vertex by itself: half of them on each thread.
    auto classifyVertex = [&](std::uint32_t v) {
      const auto triangles = static_cast<std::uint32_t>(m_mesh.fan[v].size());  // all alive at set-up
      if (triangles == 0 || nonManifold[v]) return;
      const bool closedDisk =
          boundaryCount[v] == 0 && neighbours[v] == triangles && m_mesh.closedAround[v] && fanIsOneCycle(v);
      const bool openDisk = boundaryCount[v] == 2 && neighbours[v] == triangles + 1;
      if (openDisk) {
        const bool corner = sharpCount[v] > 0 || (cornersByTurn[v] && turns(v, boundaryNeighbour));
        m_mesh.vertexClass[v] = corner ? VertexClass::Corner : VertexClass::Boundary;
      } else if (closedDisk) {
        if (sharpCount[v] == 0)
          m_mesh.vertexClass[v] = VertexClass::Simple;
        else if (sharpCount[v] == 1)
          m_mesh.vertexClass[v] = VertexClass::SharpEdge;  // where a crease fades out
        else if (sharpCount[v] == 2 && !turns(v, sharpNeighbour))
          m_mesh.vertexClass[v] = VertexClass::SharpEdge;
        else
          m_mesh.vertexClass[v] = VertexClass::Corner;
      }
    };
    m_mesh.vertexClass.assign(m_mesh.vertexCount, VertexClass::Complex);
    m_pool.runHalves([&](int half) {
      const auto [begin, end] = halfOf(m_mesh.vertexCount, half);
      for (std::uint32_t v = begin; v < end; ++v) classifyVertex(v);
    });
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
    m_mesh.twin = positionTwins(m_input.positions);
    const std::vector<std::uint32_t> held = keepSeamTwins(
        m_mesh.twin, m_partition, [&](std::uint32_t v) { return m_mesh.vertexClass[v] == VertexClass::Boundary; });
    for (std::uint32_t v = 0; v < m_mesh.vertexCount; ++v)
      if (m_mesh.twin[v] != kNoTwin) m_mesh.vertexClass[v] = VertexClass::Seam;
    for (std::uint32_t v : held) m_mesh.vertexClass[v] = VertexClass::Complex;
  }

  // Whether v's triangles (every edge at v run both ways) make one cycle around it, each
  // triangle's corner after v being the next one's corner before v: a consistently wound
  // disk, where two fans pinched together at v make two cycles.
  bool fanIsOneCycle(std::uint32_t v) const {
    const std::span<const std::uint32_t> fan = m_mesh.fan[v];
    std::size_t length = 0;
    std::uint32_t t = fan.front();
    do {
      const std::uint32_t after = cornerAfter(&m_mesh.corner[3 * t], v);
      auto startsAtAfter = [&](std::uint32_t u) { return cornerBefore(&m_mesh.corner[3 * u], v) == after; };
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
    UnionFind components(m_mesh.vertexCount);
    for (const Edge& e : edges) components.join(e.a, e.b);
    std::vector<glm::dvec3> lo(m_mesh.vertexCount, glm::dvec3(std::numeric_limits<double>::max()));
    std::vector<glm::dvec3> hi(m_mesh.vertexCount, glm::dvec3(std::numeric_limits<double>::lowest()));
    for (const Edge& e : edges)
      for (std::uint32_t v : {e.a, e.b}) {
        const std::uint32_t c = components.find(v);
        lo[c] = glm::min(lo[c], m_mesh.position[v]);
        hi[c] = glm::max(hi[c], m_mesh.position[v]);
      }
    std::erase_if(edges, [&](const Edge& e) {
      const std::uint32_t c = components.find(e.a);
      return glm::length(hi[c] - lo[c]) < smallest;
    });
  }

  // Feature lines: sharp edges joined through sharp-edge vertices (corners split them);
  // corners remember the lines that end at them, so they may gather along those.
  void labelLines(const std::vector<Edge>& sharpEdges) {
    UnionFind lines(m_mesh.vertexCount);
    for (const Edge& e : sharpEdges)
      if (m_mesh.vertexClass[e.a] == VertexClass::SharpEdge && m_mesh.vertexClass[e.b] == VertexClass::SharpEdge)
        lines.join(e.a, e.b);
    m_mesh.line.resize(m_mesh.vertexCount);
    for (std::uint32_t v = 0; v < m_mesh.vertexCount; ++v) m_mesh.line[v] = lines.find(v);
    for (const Edge& e : sharpEdges) {
      if (m_mesh.vertexClass[e.a] == VertexClass::Corner && m_mesh.vertexClass[e.b] == VertexClass::SharpEdge)
        m_mesh.cornerLines.push_back(ClusterMesh::lineKey(e.a, m_mesh.line[e.b]));
      if (m_mesh.vertexClass[e.b] == VertexClass::Corner && m_mesh.vertexClass[e.a] == VertexClass::SharpEdge)
        m_mesh.cornerLines.push_back(ClusterMesh::lineKey(e.b, m_mesh.line[e.a]));
    }
    std::sort(m_mesh.cornerLines.begin(), m_mesh.cornerLines.end());
  }

  const TriangleMesh& m_input;
  const RegionPartition& m_partition;
  const ClusterOptions& m_options;
  core::ThreadPool& m_pool;
  ClusterMesh& m_mesh;
};

}  // namespace

ClusterMesh setUpClusterMesh(const TriangleMesh& input, const RegionPartition& partition, const ClusterOptions& options,
                             core::ThreadPool& pool) {
  ClusterMesh mesh;
  ClusterMeshSetup(input, partition, options, pool, mesh).run();
  return mesh;
}

}  // namespace polder::mesh::cluster
