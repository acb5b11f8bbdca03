// One worker of the cluster builder (Chuang 2001 part A): it evaluates candidate clusters and
// takes steps, over the part of a ClusterMesh that a round gives it. Vertices outside
// that part never join a cluster, are never evaluated, and keep their queue keys for the
// next round; a worker only changes triangles, fans and vertices within reach of its own
// part, so two workers on parts that are not neighbours (cluster_builder.cpp) run at once.
#pragma once

#include <array>
#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <vector>

#include "cluster_mesh.hpp"
#include "indexed_min_heap.hpp"
#include "polder/mesh/cluster_builder.hpp"
#include "polder/mesh/region_partition.hpp"
#include "polder/mesh/simplification_steps.hpp"
#include "step_listener.hpp"

namespace polder::mesh::cluster {

// At most this many vertices join in one step (the tree is cut breadth first): it bounds
// the work of a large cell on fine ground, where the paper gathers 2 to 10 vertices a step.
inline constexpr std::size_t kMaxClusterSize = 32;

class ClusterWorker {
 public:
  ClusterWorker(ClusterMesh& mesh, const RegionPartition& partition, const ClusterOptions& options);

  // Starts a round on the vertices v (all alive ones, in index order) with part[v] == own:
  // their queue is rebuilt from the mesh's keys, and stale ones are evaluated afresh.
  void beginRound(std::span<const std::uint32_t> vertices, std::span<const std::uint8_t> part, std::uint8_t own);

  // Takes steps, appending them to `steps` (with their queue keys to `keys`, when given,
  // and telling `listener`, when given), until `vertexQuota` vertices or `triangleQuota`
  // triangles are gone, or nothing is left to gather. Returns the vertices removed.
  std::uint32_t takeSteps(std::uint32_t vertexQuota, std::uint32_t triangleQuota, SimplificationSteps& steps,
                          std::vector<float>* keys, StepListener* listener);

  // Triangles removed since the round began.
  std::uint32_t trianglesRemoved() const { return m_trianglesRemoved; }

  // Ends the round: the queue keys of the worker's part go back to the mesh; vertices with
  // nothing to gather are evaluated again next round.
  void endRound(std::span<const std::uint32_t> vertices, std::span<const std::uint8_t> part, std::uint8_t own);

 private:
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
    std::uint32_t mark;  // == m_stamp: r or in r's tree; == m_stamp + 1: seen, outside; kOutOfPart
  };
  // The mark of a vertex outside the worker's part this round: seen, and never joins.
  static constexpr std::uint32_t kOutOfPart = kNone;

  struct MemberScore {
    double cost;        // of moving the member's cluster onto the representative
    double meanSquare;  // of the cluster's plane distances there
  };

  // A neighbour of a vertex and the (first two) current triangles on their edge.
  struct Link {
    std::uint32_t vertex;
    std::uint32_t triangles;
    std::uint32_t first, second;
  };

  bool nextRepresentative(std::uint32_t& r);
  void schedule(std::uint32_t r);
  void updateNeighbourhood(std::uint32_t r);
  bool inPart(std::uint32_t v) const { return m_treePoint[v].mark != kOutOfPart; }
  // The queue's key for the last evaluation's priority.
  float queueKey() const { return static_cast<float>(m_priority); }
  // Whether the last evaluation costs no more than every queued vertex.
  bool beatsTheQueue() const { return m_queue.empty() || queueKey() <= m_queue.key(m_queue.top()); }

  // One candidate cluster.
  bool evaluate(std::uint32_t r, Evaluation evaluation);
  bool growCell(std::uint32_t r);
  bool validateCluster(std::uint32_t r);
  void growTree(std::uint32_t r, double tau, bool wholeTree);
  void nextStamps();
  bool keepsFeature(std::uint32_t p, std::uint32_t x) const;
  bool isBoundaryEdge(std::uint32_t p, std::uint32_t x) const;
  bool onSameLine(std::uint32_t p, std::uint32_t x) const;
  void dropCostlyMembers();
  void dropFlippingMembers(std::uint32_t r);
  void dropSubtrees();
  bool isTwinEntry(std::size_t i) const;
  void addTwins(std::uint32_t r);
  // Where member i goes: r, or r's twin for a seam member's twin.
  std::uint32_t targetOf(std::size_t i, std::uint32_t r) const { return isTwinEntry(i) ? m_rTwin : r; }
  bool dropAPinchingMember(std::uint32_t r);
  void removeDroppedMembers();
  bool moveFlipsATriangle(std::uint32_t v, std::uint32_t r) const;
  bool vanishes(std::uint32_t t) const;
  bool keepsATriangle(std::uint32_t r) const;
  void scoreMembers(std::uint32_t r);
  void scoreCluster(std::uint32_t r);

  // Taking a step.
  void gather(std::uint32_t r);
  void compactFan(std::uint32_t v);
  bool demoteFadedFeature(std::uint32_t x);
  bool isSharp(std::uint32_t x, std::uint32_t y, std::uint32_t s, std::uint32_t t) const;
  void updateClosedAround(std::uint32_t r);
  void collectRing(std::uint32_t r);

  ClusterMesh& m_mesh;
  const RegionPartition& m_partition;
  const ClusterOptions& m_options;
  IndexedMinHeap m_queue;  // vertices of the part with something to gather, by priority
  std::uint32_t m_trianglesRemoved = 0;
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

}  // namespace polder::mesh::cluster
