// The cluster builder's mesh as its steps so far left it (Chuang 2001 part A), with what the
// seed's preprocessing found: vertex classes, feature lines, seam twins, per-vertex
// quadrics and colour moments. The workers of a round (cluster_worker.hpp) share it, each
// changing it only within its own part of the mesh.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <limits>
#include <vector>

#include "halves.hpp"
#include "polder/mesh/cluster_builder.hpp"
#include "polder/mesh/region_partition.hpp"
#include "polder/mesh/triangle_mesh.hpp"
#include "polder/thread_pool.hpp"
#include "quadric.hpp"
#include "triangle_fans.hpp"

namespace polder::mesh::cluster {

inline constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

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

struct ClusterMesh {
  std::uint32_t vertexCount = 0;
  double diagonal = 1.0;   // of the input's bounding box: errors are scaled back by it
  double cellLimit = 2.0;  // a cell this large covers the bounding box wherever it is centred
  double featureCosine = 0.0;
  std::vector<glm::dvec3> position;  // translated and scaled to a unit diagonal
  std::vector<std::uint32_t> corner;
  std::vector<std::uint8_t> triangleAlive;
  std::uint32_t liveTriangles = 0;
  TriangleFans fan;              // live triangles only (gather drops the dead)
  std::vector<Quadric> quadric;  // per vertex: the planes of its cluster
  bool useColours = false;
  double colourTolerance = 0.0;    // colours further apart than this lie across a border
  std::vector<glm::dvec3> colour;  // RGB times colourWeight
  std::vector<double> moment0, moment2;
  std::vector<glm::dvec3> moment1;
  std::vector<VertexClass> vertexClass;
  std::vector<std::uint8_t> colourBorder;
  // Every edge at the vertex has two triangles, one running each way (set up, then kept by
  // updateClosedAround).
  std::vector<std::uint8_t> closedAround;
  std::vector<std::uint32_t> twin;         // a Seam vertex's twin (classifySeams), else kNoTwin
  std::vector<std::uint32_t> line;         // feature line of a sharp-edge vertex
  std::vector<std::uint64_t> cornerLines;  // sorted lineKey(corner, line) of lines ending at corners
  std::vector<std::uint8_t> alive;
  std::vector<double> cell;  // per vertex: its floating cell's size tau
  // Between rounds: whether a vertex must be evaluated afresh (it was out of every
  // worker's part, or had nothing to gather), and else its queue key.
  std::vector<float> queuedKey;
  std::vector<std::uint8_t> stale;

  // Whether neighbours a and b differ in colour by more than the tolerance.
  bool coloursDiffer(std::uint32_t a, std::uint32_t b) const {
    const glm::dvec3 d = colour[a] - colour[b];
    return glm::dot(d, d) > colourTolerance * colourTolerance;
  }

  // Whether the line a -> v -> b turns at v by more than the feature angle (its two edges
  // far from collinear), or has an edge of no length.
  bool turnsSharply(std::uint32_t a, std::uint32_t v, std::uint32_t b) const {
    const glm::dvec3 in = position[v] - position[a], out = position[b] - position[v];
    const double lengths = glm::length(in) * glm::length(out);
    return !(lengths > 0.0) || glm::dot(in, out) < featureCosine * lengths;
  }

  static std::uint64_t lineKey(std::uint32_t corner, std::uint32_t line) {
    return (std::uint64_t(corner) << 32) | line;
  }
};

// Part A's preprocessing of `input` (its vertices in locality order): every vertex
// classified and given the quadric of its planes; cells start at tau0. Halves of the work
// run as two halves on `pool`; the result does not depend on it.
ClusterMesh setUpClusterMesh(const TriangleMesh& input, const RegionPartition& partition, const ClusterOptions& options,
                             core::ThreadPool& pool);

}  // namespace polder::mesh::cluster
