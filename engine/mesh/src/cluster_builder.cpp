// Builder `cluster` (Chuang 2001, part A): the paper's preprocessing
// (cluster_mesh), then its simplification loop (cluster_worker), run in rounds on two
// threads while the mesh is large and on one for its coarsest levels.
#include "polder/mesh/cluster_builder.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <optional>
#include <vector>

#include "builder_setup.hpp"
#include "cluster_mesh.hpp"
#include "cluster_worker.hpp"
#include "halves.hpp"
#include "locality_order.hpp"
#include "polder/thread_pool.hpp"
#include "step_listener.hpp"

namespace polder::mesh {

namespace {

using cluster::ClusterMesh;
using cluster::ClusterWorker;

// Rounds: while the mesh is large, two workers simplify two parts of it at once, each a
// range of vertices in locality order (a piece of surface). The vertices where the parts
// meet stay out of both, so neither worker changes what the other reads; the next round
// cuts elsewhere, so they are simplified then. Each round's steps are merged by their
// queue keys, so the sequence keeps its cheapest-first order.
//
// A worker removes at most this share of its part's vertices in a round: the parts then
// coarsen evenly, as the whole queue would have them.
constexpr double kRoundShare = 0.25;
// Below this many vertices the builder goes on with one worker on the whole mesh: the
// coarse levels are taken in the exact queue order, and rounds would be short.
constexpr std::uint32_t kRoundsDownTo = 256;
// Rounds end once the cut holds more than this share of the alive vertices: they wait a
// round, and on a coarse mesh too much of the surface would stay finer than the rest.
constexpr double kLargestCut = 0.25;
// Rounds end when fewer triangles than this are left to remove (stopAtTriangles is near).
constexpr std::uint32_t kSmallestTriangleQuota = 16;
constexpr std::uint8_t kBetweenParts = 2;  // a vertex in neither part this round

class ClusterBuilder {
 public:
  ClusterBuilder(const TriangleMesh& mesh, const RegionPartition& partition, const ClusterOptions& options,
                 StepListener* listener, core::ThreadPool& pool)
      : m_input(mesh), m_partition(partition), m_options(options), m_listener(listener), m_pool(pool) {}

  SimplificationSteps run() {
    if (m_listener) m_listener->builderOnTwoCores(true);
    m_mesh = cluster::setUpClusterMesh(m_input, m_partition, m_options, m_pool);
    SimplificationSteps steps;
    if (m_mesh.liveTriangles == 0) return steps;
    const std::uint32_t vertexCount = m_mesh.vertexCount;
    steps.representative.reserve(vertexCount / 2);
    steps.removed.reserve(vertexCount);
    steps.onto.reserve(vertexCount);
    steps.removedBegin.reserve(vertexCount / 2 + 1);
    steps.error.reserve(vertexCount / 2);
    for (std::uint32_t v = 0; v < vertexCount; ++v)
      if (m_mesh.alive[v]) m_aliveVertexList.push_back(v);
    m_aliveVertices = m_startVertices = static_cast<std::uint32_t>(m_aliveVertexList.size());
    m_part.assign(vertexCount, 0);
    const bool rounds = m_aliveVertices >= 2 * kRoundsDownTo;
    std::array<std::optional<ClusterWorker>, 2> worker;
    m_pool.runHalves([&](int w) {
      if (w == 0 || rounds) worker[w].emplace(m_mesh, m_partition, m_options);
    });
    if (rounds) runRounds(*worker[0], *worker[1], steps);

    if (m_listener) m_listener->builderOnTwoCores(false);
    // The rest with one worker on the whole mesh, reporting progress every so often.
    const std::uint32_t reportEvery = std::max<std::uint32_t>(1, m_startVertices / 64);
    std::fill(m_part.begin(), m_part.end(), std::uint8_t(0));
    dropDead();
    worker[0]->beginRound(m_aliveVertexList, m_part, 0);
    for (;;) {
      const std::uint32_t removed = worker[0]->takeSteps(reportEvery, triangleSurplus(), steps, nullptr, m_listener);
      reportProgress(removed);
      if (removed < reportEvery) break;
    }
    return steps;
  }

 private:
  // The rounds' loops walk what is still alive only.
  void dropDead() {
    std::erase_if(m_aliveVertexList, [&](std::uint32_t v) { return !m_mesh.alive[v]; });
    std::erase_if(m_liveTriangleList, [&](std::uint32_t t) { return !m_mesh.triangleAlive[t]; });
  }

  // Triangles the build may still remove before reaching stopAtTriangles.
  std::uint32_t triangleSurplus() const {
    return m_mesh.liveTriangles > m_options.stopAtTriangles ? m_mesh.liveTriangles - m_options.stopAtTriangles : 0;
  }

  void reportProgress(std::uint32_t removed) {
    m_aliveVertices -= removed;
    if (m_options.progress) m_options.progress(1.0 - double(m_aliveVertices) / double(m_startVertices));
  }

  void runRounds(ClusterWorker& first, ClusterWorker& second, SimplificationSteps& steps) {
    const std::array<ClusterWorker*, 2> workers{&first, &second};
    m_liveTriangleList.resize(m_mesh.triangleAlive.size());
    std::iota(m_liveTriangleList.begin(), m_liveTriangleList.end(), 0u);
    for (std::uint32_t round = 0; m_aliveVertices >= kRoundsDownTo; ++round) {
      // Each worker may remove a quarter of the triangles left to remove: together they
      // never pass stopAtTriangles.
      const std::uint32_t triangleQuota = triangleSurplus() / 4;
      if (triangleQuota < kSmallestTriangleQuota) break;
      const std::array<std::uint32_t, 2> partSize = splitIntoParts(round);
      if (partSize[0] + partSize[1] < (1.0 - kLargestCut) * m_aliveVertices) break;
      std::array<std::uint32_t, 2> removed{};
      auto work = [&](int w) {
        ClusterWorker& worker = *workers[w];
        m_roundSteps[w].clear();
        m_roundKeys[w].clear();
        worker.beginRound(m_aliveVertexList, m_part, static_cast<std::uint8_t>(w));
        const auto quota = static_cast<std::uint32_t>(std::ceil(kRoundShare * partSize[w]));
        removed[w] = worker.takeSteps(quota, triangleQuota, m_roundSteps[w], &m_roundKeys[w], nullptr);
        worker.endRound(m_aliveVertexList, m_part, static_cast<std::uint8_t>(w));
      };
      m_pool.runHalves(work);
      mergeRoundSteps(steps);
      for (const ClusterWorker* worker : workers) m_mesh.liveTriangles -= worker->trianglesRemoved();
      for (std::uint32_t v : m_aliveVertexList)  // no step reaches them, so they are still alive
        if (m_part[v] == kBetweenParts) m_mesh.stale[v] = 1;
      const std::uint32_t removedInRound = removed[0] + removed[1];
      reportProgress(removedInRound);
      if (removedInRound == 0 || removedInRound < (partSize[0] + partSize[1]) / 32) break;  // little left to gather
    }
  }

  // Cuts the alive vertices (in locality order) into two parts of equal size: at the
  // median in even rounds, at the quartiles (the middle half against the rest) in odd
  // ones, so each cut runs through the middle of a part of the round before. Vertices
  // on a triangle across the cut, and seam twins parted by it, belong to neither.
  // Returns the parts' sizes.
  std::array<std::uint32_t, 2> splitIntoParts(std::uint32_t round) {
    dropDead();
    const auto alive = static_cast<std::uint32_t>(m_aliveVertexList.size());
    const std::uint32_t begin = round % 2 == 0 ? 0 : alive / 4, end = round % 2 == 0 ? alive / 2 : alive - alive / 4;
    for (std::uint32_t rank = 0; rank < alive; ++rank)
      m_part[m_aliveVertexList[rank]] = rank >= begin && rank < end ? 0 : 1;
    // Bit 0 holds the side of the cut, bit 1 (kBetweenParts) marks vertices at the cut.
    const std::uint32_t* corner = m_mesh.corner.data();
    for (std::uint32_t t : m_liveTriangleList) {
      const std::uint32_t a = corner[3 * t], b = corner[3 * t + 1], c = corner[3 * t + 2];
      if (((m_part[a] ^ m_part[b]) | (m_part[a] ^ m_part[c])) & 1)
        m_part[a] |= kBetweenParts, m_part[b] |= kBetweenParts, m_part[c] |= kBetweenParts;
    }
    for (std::uint32_t v : m_aliveVertexList) {
      const std::uint32_t twin = m_mesh.twin[v];
      if (twin == kNoTwin) continue;
      if (!m_mesh.alive[twin] || ((m_part[v] | m_part[twin]) & kBetweenParts) || ((m_part[v] ^ m_part[twin]) & 1))
        m_part[v] |= kBetweenParts, m_part[twin] |= kBetweenParts;
    }
    std::array<std::uint32_t, 2> size{};
    for (std::uint32_t v : m_aliveVertexList) {
      if (m_part[v] & kBetweenParts)
        m_part[v] = kBetweenParts;
      else
        ++size[m_part[v]];
    }
    return size;
  }

  // Appends the round's steps of both workers, cheapest first (each worker's in its own
  // order: the parts are apart, so their steps commute).
  void mergeRoundSteps(SimplificationSteps& steps) {
    const SimplificationSteps& a = m_roundSteps[0];
    const SimplificationSteps& b = m_roundSteps[1];
    const std::vector<float>& keyA = m_roundKeys[0];
    const std::vector<float>& keyB = m_roundKeys[1];
    std::size_t i = 0, j = 0;
    while (i < a.size() || j < b.size()) {
      const bool fromA = j == b.size() || (i < a.size() && keyA[i] <= keyB[j]);
      steps.addCopyOf(fromA ? a : b, fromA ? i++ : j++);
      if (m_listener) m_listener->stepTaken(steps);
    }
  }

  const TriangleMesh& m_input;
  const RegionPartition& m_partition;
  const ClusterOptions& m_options;
  StepListener* m_listener;  // may be null
  core::ThreadPool& m_pool;  // for the set-up and the rounds
  ClusterMesh m_mesh;
  std::uint32_t m_startVertices = 0;  // on a triangle at the start
  std::uint32_t m_aliveVertices = 0;
  std::vector<std::uint8_t> m_part;  // per alive vertex this round: 0, 1 or kBetweenParts
  std::vector<std::uint32_t> m_aliveVertexList, m_liveTriangleList;  // as of the round's start
  std::array<SimplificationSteps, 2> m_roundSteps;
  std::array<std::vector<float>, 2> m_roundKeys;
};

}  // namespace

Result<SimplificationSteps> buildClusterSteps(const TriangleMesh& mesh, const RegionPartition& partition,
                                              const ClusterOptions& options) {
  core::ThreadPool pool(options.threads);
  return buildClusterSteps(mesh, partition, options, nullptr, pool);
}

Result<SimplificationSteps> buildClusterSteps(const TriangleMesh& mesh, const RegionPartition& partition,
                                              const ClusterOptions& options, StepListener* listener,
                                              core::ThreadPool& pool) {
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
  return buildInLocalityOrder(mesh, partition, listener,
                              [&](const TriangleMesh& ordered, const RegionPartition& regions) {
                                return ClusterBuilder(ordered, regions, options, listener, pool).run();
                              });
}

}  // namespace polder::mesh
