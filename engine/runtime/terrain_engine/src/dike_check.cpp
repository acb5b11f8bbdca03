#include "dike_check.hpp"

#include <algorithm>
#include <cmath>

namespace polder {

DikeCheck::DikeCheck(const terrain::DikeTriangleMeasure& measure, const terrain::BlockLayout& layout,
                     const CutIndex& cutIndex, double spacingX, double spacingY)
    : m_layout(layout), m_spacingX(spacingX), m_spacingY(spacingY), m_errors(measure), m_cutIndex(cutIndex) {}

void DikeCheck::reserve(std::size_t cutNodes) {
  m_nodeRepinned.reserve(cutNodes);
  m_repinned.reserve(cutNodes);
  m_splits.reserve(cutNodes);
}

DikeCheckResult DikeCheck::check(const Camera& camera, double tauPx, const terrain::DikeStage& dikes,
                                 std::span<const terrain::SelectedNode> cut,
                                 std::span<const terrain::BlockMesh* const> cutMeshes, cache::LodCache& cache) {
  DikeCheckResult result;
  m_errors.beginPass(dikes.visibleTriangleCount());
  m_nodeRepinned.assign(cut.size(), 0);
  m_repinned.clear();
  m_splits.clear();
  const terrain::DikeMesh& mesh = dikes.mesh();
  const std::span<const std::uint32_t> vertexNodes = dikes.vertexNodes();
  const std::span<const std::uint32_t> indices = dikes.visibleIndices();
  const std::span<const std::uint32_t> owners = dikes.visibleOwners();
  const double k = camera.errorProjectionConstant();
  const double near = std::max(camera.nearM, 1e-3);
  for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
    const terrain::DikeVertex& a = mesh.vertices[indices[t]];
    const terrain::DikeVertex& b = mesh.vertices[indices[t + 1]];
    const terrain::DikeVertex& c = mesh.vertices[indices[t + 2]];
    const terrain::DikeTriangleRef where{{indices[t], indices[t + 1], indices[t + 2]}, owners[t / 3]};
    const terrain::DikeErrorCache::Triangle& known = m_errors.lookUp(a, b, c, where);
    const double error = known.error;
    if (!(error > 0.0)) continue;
    // K e / max(d, near) > tau  <=>  d < K e / tau (or the near plane already fails it).
    // Pins go on a little early (pinReach): as the camera approaches, the triangle then
    // never fails, and the frame need not be stitched again.
    const double reach = k * error / tauPx, pinReach = reach * (1.0 + kPinHeadroom);
    if (pinReach <= near) continue;
    const int tx0 = std::min({a.x, b.x, c.x}), tx1 = std::max({a.x, b.x, c.x});
    const int ty0 = std::min({a.y, b.y, c.y}), ty1 = std::max({a.y, b.y, c.y});
    const glm::dvec3 lo{tx0 * m_spacingX, ty0 * m_spacingY, double(known.zMin) - error};
    const glm::dvec3 hi{tx1 * m_spacingX, ty1 * m_spacingY, double(known.zMax) + error};
    const glm::dvec3 nearest = glm::clamp(camera.position, lo, hi);
    const double distance = std::max(glm::length(nearest - camera.position), near);
    result.worstPx = std::max(result.worstPx, k * error / distance);
    if (distance >= pinReach) continue;
    const bool failing = distance < reach;
    bool pinned = false;
    for (const std::uint32_t v : {indices[t], indices[t + 1], indices[t + 2]}) {
      const std::uint32_t node = vertexNodes[v];
      if (node != terrain::DikeStage::kNoNode)
        pinned |= pinAround(node, tx0, ty0, tx1, ty1, failing, cut, cutMeshes, cache);
    }
    if (!failing) continue;
    ++result.failing;
    if (pinned) continue;
    // The coarsest node whose footprint the triangle's box touches: its dike strip holds
    // samples that no side can pin (it need not have a vertex in the triangle). Footprints
    // share their edges, so the cells on both sides of the box's corners are asked.
    std::uint32_t coarsest = CutIndex::kNone;
    const int xs[4] = {tx0 - 1, tx0, std::max(tx0, tx1 - 1), tx1}, ys[4] = {ty0 - 1, ty0, std::max(ty0, ty1 - 1), ty1};
    for (const int x : xs)
      for (const int y : ys) {
        if (x < 0 || y < 0 || x > m_layout.width() - 2 || y > m_layout.height() - 2) continue;
        const std::uint32_t i = m_cutIndex.at(x, y);
        if (i != CutIndex::kNone && cut[i].node.level > 0 &&
            (coarsest == CutIndex::kNone || cut[i].node.level > cut[coarsest].node.level))
          coarsest = i;
      }
    if (coarsest != CutIndex::kNone &&
        std::find(m_splits.begin(), m_splits.end(), cut[coarsest].node) == m_splits.end())
      m_splits.push_back(cut[coarsest].node);
  }
  return result;
}

// Pins the sides of cut node `node` that the dike triangle with bounding box [tx0, tx1] x
// [ty0, ty1] lies along, over the box's extent (rounded outwards to the node's stride). An
// urgent pin (the triangle fails now) lists the node in repinned(); the others take effect
// when the cache next hands out the node's mesh.
bool DikeCheck::pinAround(std::uint32_t node, int tx0, int ty0, int tx1, int ty1, bool urgent,
                          std::span<const terrain::SelectedNode> cut,
                          std::span<const terrain::BlockMesh* const> cutMeshes, cache::LodCache& cache) {
  const terrain::BlockMesh* mesh = cutMeshes[node];
  if (!mesh) return false;
  terrain::SideRange sides[2];
  const int count = terrain::sidesBesideDikeTriangle(*mesh, terrain::SampleRect{tx0, ty0, tx1, ty1}, sides);
  bool added = false;
  for (int i = 0; i < count; ++i) added |= cache.pin(cut[node].node, sides[i].side, sides[i].from, sides[i].to);
  if (added && urgent && !m_nodeRepinned[node]) {
    m_nodeRepinned[node] = 1;
    m_repinned.push_back(node);
  }
  return added;
}

}  // namespace polder
