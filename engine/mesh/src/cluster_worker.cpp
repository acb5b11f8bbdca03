#include "cluster_worker.hpp"

#include <algorithm>
#include <cmath>

#include "builder_setup.hpp"
#include "triangle_planes.hpp"

namespace polder::mesh::cluster {

namespace {

// A member costing more than this times the cluster's mean cost stays out.
constexpr double kOutlierFactor = 2.5;
// A triangle that survives a step may turn by at most about 87 degrees.
constexpr double kMinNormalCosine = 0.05;
// A tiny cost for gathering distant vertices: on flat ground, where every cluster costs
// nothing, it keeps clusters compact and cells growing evenly.
constexpr double kCompactness = 1e-6;

// Features cost more to gather, so they go last (the paper's class weights).
double classWeight(VertexClass c) {
  switch (c) {
    case VertexClass::Boundary:
    case VertexClass::Seam:
    case VertexClass::SharpEdge:
      return 2.0;
    default:
      return 1.0;
  }
}

}  // namespace

ClusterWorker::ClusterWorker(ClusterMesh& mesh, const RegionPartition& partition, const ClusterOptions& options)
    : m_mesh(mesh), m_partition(partition), m_options(options), m_queue(mesh.vertexCount) {
  const std::uint32_t n = mesh.vertexCount;
  m_treePoint.resize(n);
  for (std::uint32_t v = 0; v < n; ++v) m_treePoint[v] = {glm::vec3(mesh.position[v]), 0};
  m_ringMark.assign(n, 0);
  m_memberIndex.assign(n, 0);
  m_linkSeen.assign(n, 0);
  m_runsFromR.assign(n, 0);
  m_runsToR.assign(n, 0);
  m_keptOnEdge.assign(n, 0);
  m_vanishing.assign(n, 0);
  m_triangleSeen.assign(mesh.triangleAlive.size(), 0);
}

void ClusterWorker::beginRound(std::span<const std::uint32_t> vertices, std::span<const std::uint8_t> part,
                               std::uint8_t own) {
  m_trianglesRemoved = 0;
  m_queue.clear();
  for (std::uint32_t v : vertices) {
    std::uint32_t& mark = m_treePoint[v].mark;
    if (part[v] != own)
      mark = kOutOfPart;
    else if (mark == kOutOfPart)
      mark = 0;
  }
  // The paper's preprocessing, for vertices never evaluated or changed out of sight: their
  // priority (the cost of the cluster they would gather). The first ring of the cluster
  // estimates it at a fraction of the work: the queue evaluates the whole cluster when
  // the vertex comes up, and most vertices are gathered before that.
  for (std::uint32_t v : vertices) {
    if (part[v] != own) continue;
    if (m_mesh.stale[v]) {
      m_mesh.stale[v] = 0;
      if (evaluate(v, Evaluation::FirstRing)) m_queue.set(v, queueKey());
    } else {
      m_queue.set(v, m_mesh.queuedKey[v]);
    }
  }
}

std::uint32_t ClusterWorker::takeSteps(std::uint32_t vertexQuota, std::uint32_t triangleQuota,
                                       SimplificationSteps& steps, std::vector<float>* keys, StepListener* listener) {
  std::uint32_t removed = 0, r = 0;
  while (removed < vertexQuota && m_trianglesRemoved < triangleQuota && nextRepresentative(r)) {
    gather(r);
    if (m_rTwin == kNone) {
      steps.add(r, m_members, m_error);
    } else {
      m_targets.resize(m_members.size());
      for (std::size_t i = 0; i < m_members.size(); ++i) m_targets[i] = targetOf(i, r);
      steps.add(r, m_members, m_targets, m_error);
    }
    if (keys) keys->push_back(queueKey());
    if (listener) listener->stepTaken(steps);
    removed += static_cast<std::uint32_t>(m_members.size());
    const std::uint32_t rTwin = m_rTwin;  // evaluations below overwrite it
    updateNeighbourhood(r);
    if (rTwin != kNone) updateNeighbourhood(rTwin);
  }
  return removed;
}

void ClusterWorker::endRound(std::span<const std::uint32_t> vertices, std::span<const std::uint8_t> part,
                             std::uint8_t own) {
  // A vertex with nothing to gather may have been held up by vertices out of the part.
  for (std::uint32_t v : vertices) {
    if (part[v] != own || !m_mesh.alive[v]) continue;
    if (m_queue.contains(v))
      m_mesh.queuedKey[v] = m_queue.key(v);
    else
      m_mesh.stale[v] = 1;
  }
}

// Step 1 of the paper with a lazy queue: the neighbourhood of an entry may have changed since it
// was made, so the popped vertex is evaluated again and only taken if its current cost
// (after the geometric checks) still beats every other entry; otherwise it goes back
// with that cost. On true, r and m_members hold the step to take.
bool ClusterWorker::nextRepresentative(std::uint32_t& r) {
  while (!m_queue.empty()) {
    r = m_queue.top();
    m_queue.remove(r);
    if (!m_queue.empty()) m_mesh.fan.prefetch(m_queue.top());  // often the next one looked at
    if (!evaluate(r, Evaluation::Tree)) continue;
    if (!beatsTheQueue()) {
      m_queue.set(r, queueKey());
      continue;
    }
    // Only a cluster about to be taken gets the geometric checks; if they fail in this
    // cell, the search for a valid cluster goes on in the next larger one.
    if (validateCluster(r))
      scoreCluster(r);
    else if (!growCell(r) || !evaluate(r, Evaluation::CheckedTree))
      continue;
    if (beatsTheQueue()) return true;
    m_queue.set(r, queueKey());
  }
  return false;
}

// (Re)evaluates r, when in the worker's part, and queues it if it has something to gather.
void ClusterWorker::schedule(std::uint32_t r) {
  m_queue.remove(r);
  if (m_mesh.alive[r] && inPart(r) && evaluate(r, Evaluation::Tree)) m_queue.set(r, queueKey());
}

// Step 6 of the paper, lazily: the representative gets its new priority at once; a neighbour
// already queued is evaluated again when it comes up (its cluster now holds the
// representative's larger quadric, so its cost has mostly grown); one that had nothing
// to gather may have something now. The neighbours' weights are updated too: a feature
// the coarser mesh no longer shows may now join others.
void ClusterWorker::updateNeighbourhood(std::uint32_t r) {
  collectRing(r);
  updateClosedAround(r);
  schedule(r);
  for (std::uint32_t x : m_ring) {
    if (!m_queue.contains(x)) schedule(x);
    if (!demoteFadedFeature(x)) continue;
    for (std::uint32_t t : m_mesh.fan[x])
      for (int k = 0; k < 3; ++k)
        if (const std::uint32_t y = m_mesh.corner[3 * t + k]; !m_queue.contains(y)) schedule(y);
  }
}

// --- One candidate cluster ---------------------------------------------------------------

// The cluster r would gather now (m_members), its priority and error. A cell that holds
// nothing r may gather grows until it does or covers the bounding box; false then.
bool ClusterWorker::evaluate(std::uint32_t r, Evaluation evaluation) {
  for (;;) {
    growTree(r, m_mesh.cell[r], evaluation != Evaluation::FirstRing);
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
bool ClusterWorker::growCell(std::uint32_t r) {
  if (!m_cellLeftOut || m_mesh.cell[r] >= m_mesh.cellLimit) return false;
  m_mesh.cell[r] = std::min(m_mesh.cell[r] * m_options.cellGrowth, m_mesh.cellLimit);
  return true;
}

// Drops the members whose move would flip a triangle or pinch the surface; false when
// nothing is left to gather, or when the step would remove r's piece of surface whole.
bool ClusterWorker::validateCluster(std::uint32_t r) {
  m_dropped.assign(m_members.size(), 0);
  do dropFlippingMembers(r);
  while (dropAPinchingMember(r));
  removeDroppedMembers();
  return !m_members.empty() && keepsATriangle(r);
}

// Steps 2 and 3 of the paper: the spanning tree of r over current edges, breadth first, through
// vertices inside the floating cell (a cube of side tau centred on r), in r's region,
// that may join r under the classification rules (only r's neighbours unless
// `wholeTree`). m_treePoint[x].mark == m_stamp marks r and the tree; m_parent holds each
// member's parent (an index into m_members, kNone for r).
void ClusterWorker::growTree(std::uint32_t r, double tau, bool wholeTree) {
  nextStamps();
  const std::uint32_t inTree = m_stamp, outside = m_stamp + 1;  // out of the cell or the region: seen once
  TreePoint* point = m_treePoint.data();
  const std::uint32_t* corner = m_mesh.corner.data();
  point[r].mark = inTree;
  // The tree never outgrows kMaxClusterSize: members are written in place, counted by `size`.
  std::uint32_t* members = m_treeMembers.data();
  std::uint32_t* parents = m_treeParents.data();
  std::uint32_t size = 0, cellLeftOut = 0;
  m_seamRoot = m_mesh.vertexClass[r] == VertexClass::Seam;
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
    const std::uint32_t unseen =
        std::uint32_t(mark != inTree) & std::uint32_t(mark != outside) & std::uint32_t(mark != kOutOfPart);
    const std::uint32_t inCell = std::uint32_t(std::fabs(offset.x) <= half) &
                                 std::uint32_t(std::fabs(offset.y) <= half) &
                                 std::uint32_t(std::fabs(offset.z) <= half);
    const std::uint32_t inRegion = oneRegion || m_partition.regionOf(x) == region;
    std::uint32_t joins = unseen & inCell & inRegion;
    // Joining along a feature depends on the edge x is reached by, so it leaves no mark.
    if (m_mesh.vertexClass[x] != VertexClass::Simple || (m_mesh.useColours && m_mesh.colourBorder[x])) [[unlikely]]
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
    const bool closed = m_mesh.closedAround[p];
    for (std::uint32_t t : m_mesh.fan[p]) {
      const std::uint32_t* c = corner + 3 * t;
      if (!consider(p, cornerAfter(c, p), parentIndex)) return false;
      if (!closed && !consider(p, cornerBefore(c, p), parentIndex)) return false;
    }
    return true;
  };
  // Breadth first: the fans of the members queued so far are loaded while the first of
  // them is walked. visit has one call site, so it is inlined and the tree's counters
  // stay in registers (4% of a build's cycles).
  std::uint32_t p = r, parentIndex = kNone, fansLoading = 0;
  for (std::uint32_t next = 0; visit(p, parentIndex) && wholeTree && next < size; ++next) {
    for (; fansLoading < size; ++fansLoading) m_mesh.fan.prefetch(members[fansLoading]);
    p = members[next];
    parentIndex = next;
  }
  m_members.assign(members, members + size);
  m_parent.assign(parents, parents + size);
  for (std::uint32_t i = 0; i < size; ++i) m_memberIndex[members[i]] = i;
  m_cellLeftOut = cellLeftOut != 0;
}

// Two fresh mark values (the tree's and the outside's); marks are cleared before the
// counter would reach kOutOfPart.
void ClusterWorker::nextStamps() {
  if (m_stamp >= kOutOfPart - 4) {
    for (TreePoint& p : m_treePoint)
      if (p.mark != kOutOfPart) p.mark = 0;
    m_stamp = 0;
  }
  m_stamp += 2;
}

// Whether x, reached over the edge from p (r or a tree member), may join p's cluster
// without losing its feature.
bool ClusterWorker::keepsFeature(std::uint32_t p, std::uint32_t x) const {
  switch (m_mesh.vertexClass[x]) {
    case VertexClass::Simple:
      break;
    case VertexClass::Boundary:
      if (!isBoundaryEdge(p, x)) return false;
      break;
    case VertexClass::Seam:
      // Only onto a seam representative, which takes the twin too: so neither r's twin
      // nor a member's may be in the tree itself (around the seam's end, where its two
      // sides meet, the tree could reach them).
      if (!m_seamRoot || m_treePoint[m_mesh.twin[x]].mark == m_stamp || !isBoundaryEdge(p, x)) return false;
      break;
    case VertexClass::SharpEdge:
      if (!onSameLine(p, x)) return false;
      break;
    default:
      return false;  // corners and complex vertices never join
  }
  // A colour-border vertex joins along its own side of the border.
  return !m_mesh.useColours || !m_mesh.colourBorder[x] || (m_mesh.colourBorder[p] && !m_mesh.coloursDiffer(p, x));
}

bool ClusterWorker::isBoundaryEdge(std::uint32_t p, std::uint32_t x) const {
  int shared = 0;
  for (std::uint32_t t : m_mesh.fan[p]) {
    const std::uint32_t* c = &m_mesh.corner[3 * t];
    shared += c[0] == x || c[1] == x || c[2] == x;
  }
  return shared == 1;
}

bool ClusterWorker::onSameLine(std::uint32_t p, std::uint32_t x) const {
  if (m_mesh.vertexClass[p] == VertexClass::SharpEdge) return m_mesh.line[p] == m_mesh.line[x];
  if (m_mesh.vertexClass[p] == VertexClass::Corner)
    return std::binary_search(m_mesh.cornerLines.begin(), m_mesh.cornerLines.end(),
                              ClusterMesh::lineKey(p, m_mesh.line[x]));
  return false;
}

// Step 3 of the paper, "vertices that can be clustered": a member whose cost is far above the
// cluster's mean (across a ridge, up a flank) stays out, with its subtree, so clusters
// follow the directions that cost little (along a cylinder rather than around it).
void ClusterWorker::dropCostlyMembers() {
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
void ClusterWorker::dropFlippingMembers(std::uint32_t r) {
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
void ClusterWorker::dropSubtrees() {
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
bool ClusterWorker::isTwinEntry(std::size_t i) const {
  return m_rTwin != kNone && m_parent[i] != kNone && m_mesh.twin[m_members[i]] == m_members[m_parent[i]];
}

// Step 4 of the paper across a texture seam: every seam member's twin joins r's twin, each as its
// partner's child in the tree (it goes where its partner goes). r's twin is marked like
// r, so the other side's triangles that lose their edge vanish just as r's side's do;
// twins share their partners' positions, so costs and checks at r hold for them.
void ClusterWorker::addTwins(std::uint32_t r) {
  m_rTwin = kNone;
  if (m_mesh.vertexClass[r] != VertexClass::Seam) return;
  const std::size_t treeSize = m_members.size();
  for (std::size_t i = 0; i < treeSize; ++i) {
    const std::uint32_t x = m_members[i];
    if (m_mesh.vertexClass[x] != VertexClass::Seam) continue;
    const std::uint32_t twin = m_mesh.twin[x];
    m_treePoint[twin].mark = m_stamp;
    m_members.push_back(twin);
    m_parent.push_back(static_cast<std::uint32_t>(i));
    m_memberIndex[twin] = static_cast<std::uint32_t>(m_members.size() - 1);
    m_rTwin = m_mesh.twin[r];
  }
  if (m_rTwin != kNone) m_treePoint[m_rTwin].mark = m_stamp;
}

// The step must not pinch the surface: a vertex x next to the cluster keeps one fan.
// Its triangles that keep a marked corner all end up on the edge (r, x), so more than
// two of them would make that edge non-manifold (the cluster reaches round x from two
// sides), and none left at all would leave x isolated. Drops the last member next to
// the first such x (with its subtree); returns whether it dropped one.
bool ClusterWorker::dropAPinchingMember(std::uint32_t r) {
  ++m_linkStamp;
  m_touched.clear();
  auto countTriangles = [&](std::uint32_t v) {
    for (std::uint32_t t : m_mesh.fan[v]) {
      if (m_triangleSeen[t] == m_linkStamp) continue;
      m_triangleSeen[t] = m_linkStamp;
      const bool vanishing = vanishes(t);
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t x = m_mesh.corner[3 * t + k];
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
    if (m_mesh.vertexClass[x] == VertexClass::Complex) continue;  // not one fan to begin with
    const bool pinched = m_keptOnEdge[x] > 2;
    const bool isolated = m_keptOnEdge[x] == 0 && m_vanishing[x] == m_mesh.fan[x].size();
    if (!pinched && !isolated) continue;
    std::size_t last = kNone;
    for (std::uint32_t t : m_mesh.fan[x]) {
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t y = m_mesh.corner[3 * t + k];
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

// Compacts m_members and their scores, renumbering parents (a kept member's parent is kept too).
void ClusterWorker::removeDroppedMembers() {
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
bool ClusterWorker::moveFlipsATriangle(std::uint32_t v, std::uint32_t r) const {
  for (std::uint32_t t : m_mesh.fan[v]) {
    if (vanishes(t)) continue;
    const std::uint32_t* c = &m_mesh.corner[3 * t];
    glm::dvec3 p[3], q[3];
    for (int k = 0; k < 3; ++k) {
      p[k] = m_mesh.position[c[k]];
      q[k] = c[k] == v ? m_mesh.position[r] : p[k];
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
bool ClusterWorker::vanishes(std::uint32_t t) const {
  const std::uint32_t* c = &m_mesh.corner[3 * t];
  auto marked = [&](std::uint32_t v) { return m_treePoint[v].mark == m_stamp; };
  return marked(c[0]) + marked(c[1]) + marked(c[2]) >= 2;
}

// Whether some triangle at the cluster survives the step. If none does, the piece of
// surface holding r would vanish whole: the coarsest level keeps at least a triangle.
bool ClusterWorker::keepsATriangle(std::uint32_t r) const {
  auto survives = [&](std::uint32_t t) { return !vanishes(t); };
  if (std::any_of(m_mesh.fan[r].begin(), m_mesh.fan[r].end(), survives)) return true;
  for (std::uint32_t v : m_members)
    if (std::any_of(m_mesh.fan[v].begin(), m_mesh.fan[v].end(), survives)) return true;
  return false;
}

// Per member v of the tree just grown (m_memberScore, kept in step with m_members): the
// cost of moving v's cluster onto r, which is its planes' quadric error and its colours'
// squared deviation from r's colour (both area-weighted) times v's class weight, plus the
// compactness tie-breaker; and the mean squared plane distance of v's cluster at r.
void ClusterWorker::scoreMembers(std::uint32_t r) {
  const glm::dvec3& at = m_mesh.position[r];
  m_memberScore.resize(m_members.size());
  for (std::uint32_t v : m_members) {  // all the members' misses at once, not one after another
    __builtin_prefetch(&m_mesh.quadric[v]);
    __builtin_prefetch(reinterpret_cast<const char*>(&m_mesh.quadric[v]) + sizeof(Quadric) - 1);
    __builtin_prefetch(&m_mesh.position[v]);
  }
  for (std::size_t i = 0; i < m_members.size(); ++i) {
    const std::uint32_t v = m_members[i];
    const Quadric& q = m_mesh.quadric[v];
    const double planes = q.evaluate(at);
    double colour = 0.0;
    if (m_mesh.useColours) {
      const glm::dvec3& c = m_mesh.colour[r];
      colour =
          std::max(0.0, m_mesh.moment0[v] * glm::dot(c, c) - 2.0 * glm::dot(c, m_mesh.moment1[v]) + m_mesh.moment2[v]);
    }
    const glm::dvec3 d = m_mesh.position[v] - at;
    m_memberScore[i].cost =
        classWeight(m_mesh.vertexClass[v]) * (planes + colour) + kCompactness * q.weight * glm::dot(d, d);
    m_memberScore[i].meanSquare = q.weight > 0.0 ? planes / q.weight : 0.0;
  }
}

// Priority (the paper's step 1, lowest first): the members' mean cost, so that steps remove
// vertices where it is cheapest per vertex. Error: the largest RMS plane distance at r
// of a cluster r holds after the step.
void ClusterWorker::scoreCluster(std::uint32_t r) {
  const glm::dvec3& at = m_mesh.position[r];
  double sum = 0.0, worstMeanSquare = 0.0;
  if (m_mesh.quadric[r].weight > 0.0) worstMeanSquare = m_mesh.quadric[r].evaluate(at) / m_mesh.quadric[r].weight;
  for (const MemberScore& score : m_memberScore) {
    sum += score.cost;
    worstMeanSquare = std::max(worstMeanSquare, score.meanSquare);
  }
  m_priority = sum / double(m_members.size());
  m_error = static_cast<float>(std::sqrt(worstMeanSquare) * m_mesh.diagonal);
}

// --- Taking a step -----------------------------------------------------------------------

// Step 4 of the paper: the members (marked, from the last evaluate(r)) join r; triangles with
// two or three marked corners vanish, the others are re-pointed at r.
void ClusterWorker::gather(std::uint32_t r) {
  for (std::size_t i = 0; i < m_members.size(); ++i) {
    const std::uint32_t v = m_members[i], target = targetOf(i, r);
    for (std::uint32_t t : m_mesh.fan[v]) {
      if (!m_mesh.triangleAlive[t]) continue;
      if (vanishes(t)) {
        m_mesh.triangleAlive[t] = 0;
        ++m_trianglesRemoved;
        // Out of its unmarked corner's fan too (the members' fans go, r's is compacted),
        // so every fan holds live triangles only.
        for (int k = 0; k < 3; ++k)
          if (const std::uint32_t x = m_mesh.corner[3 * t + k]; m_treePoint[x].mark != m_stamp) {
            m_mesh.fan.erase(x, t);
          }
        continue;
      }
      for (int k = 0; k < 3; ++k)
        if (m_mesh.corner[3 * t + k] == v) m_mesh.corner[3 * t + k] = target;
      m_mesh.fan.push(target, t);
    }
    m_mesh.fan.clear(v);
    m_mesh.alive[v] = 0;
    m_queue.remove(v);
    m_mesh.quadric[target] += m_mesh.quadric[v];
    if (m_mesh.useColours) {
      m_mesh.moment0[target] += m_mesh.moment0[v];
      m_mesh.moment1[target] += m_mesh.moment1[v];
      m_mesh.moment2[target] += m_mesh.moment2[v];
    }
  }
  compactFan(r);  // the only fans that grow: keep them free of dead triangles
  if (m_rTwin != kNone) compactFan(m_rTwin);
}

void ClusterWorker::compactFan(std::uint32_t v) {
  m_mesh.fan.eraseIf(v, [&](std::uint32_t t) { return !m_mesh.triangleAlive[t]; });
}

// Step 6 of the paper updates the weights of the representative's neighbours: a corner or
// feature-line vertex around which the current mesh has no sharp edge left (a crease of
// noise that the coarser mesh smoothed over) becomes simple, a boundary corner whose
// current outline runs straight on becomes a boundary vertex. Classes only ever relax,
// so a smooth surface never grows features, and a real crease keeps its sharp edges.
bool ClusterWorker::demoteFadedFeature(std::uint32_t x) {
  if (m_mesh.vertexClass[x] != VertexClass::Corner && m_mesh.vertexClass[x] != VertexClass::SharpEdge) return false;
  m_links.clear();
  for (std::uint32_t t : m_mesh.fan[x])
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t y = m_mesh.corner[3 * t + k];
      if (y == x) continue;
      auto link = std::find_if(m_links.begin(), m_links.end(), [y](const Link& l) { return l.vertex == y; });
      if (link == m_links.end())
        m_links.push_back({y, 1, t, kNone});
      else if (++link->triangles == 2)
        link->second = t;
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
    m_mesh.vertexClass[x] = VertexClass::Simple;
    return true;
  }
  if (boundaryEdges != 2 || m_mesh.vertexClass[x] != VertexClass::Corner ||
      m_mesh.turnsSharply(boundary[0], x, boundary[1]))
    return false;
  m_mesh.vertexClass[x] = VertexClass::Boundary;
  return true;
}

// Whether the current triangles s and t on edge (x, y) meet at more than the feature angle.
bool ClusterWorker::isSharp(std::uint32_t x, std::uint32_t y, std::uint32_t s, std::uint32_t t) const {
  auto runsForward = [&](std::uint32_t u) { return cornerAfter(&m_mesh.corner[3 * u], x) == y; };  // x -> y
  const glm::dvec3 ns = triangleCross(m_mesh.position, &m_mesh.corner[3 * s]);
  const glm::dvec3 nt =
      triangleCross(m_mesh.position, &m_mesh.corner[3 * t]) * (runsForward(s) != runsForward(t) ? 1.0 : -1.0);
  const double lengths = glm::length(ns) * glm::length(nt);
  return lengths > 0.0 && glm::dot(ns, nt) < m_mesh.featureCosine * lengths;
}

// A step changes only the edges at r: r is closed around if each of its edges now has one
// triangle running each way, and a neighbour x that was stays so if edge (r, x) does.
void ClusterWorker::updateClosedAround(std::uint32_t r) {
  ++m_linkStamp;
  for (std::uint32_t t : m_mesh.fan[r]) {
    const std::uint32_t* c = &m_mesh.corner[3 * t];
    const std::uint32_t after = cornerAfter(c, r), before = cornerBefore(c, r);
    for (std::uint32_t x : {after, before})
      if (m_linkSeen[x] != m_linkStamp) m_linkSeen[x] = m_linkStamp, m_runsFromR[x] = m_runsToR[x] = 0;
    ++m_runsFromR[after];
    ++m_runsToR[before];
  }
  bool closed = true;
  for (std::uint32_t x : m_ring) {
    if (m_runsFromR[x] == 1 && m_runsToR[x] == 1) continue;
    m_mesh.closedAround[x] = 0;
    closed = false;
  }
  m_mesh.closedAround[r] = closed;
}

// r's current neighbours, each once (gather left r's fan free of dead triangles).
void ClusterWorker::collectRing(std::uint32_t r) {
  m_ring.clear();
  ++m_ringStamp;
  m_ringMark[r] = m_ringStamp;
  for (std::uint32_t t : m_mesh.fan[r])
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t x = m_mesh.corner[3 * t + k];
      if (m_ringMark[x] == m_ringStamp) continue;
      m_ringMark[x] = m_ringStamp;
      m_ring.push_back(x);
    }
}

}  // namespace polder::mesh::cluster
