#include <polder/terrain/dike_stage.hpp>

#include <algorithm>

#include <cassert>

namespace polder::terrain {

DikeStage::DikeStage(const BlockLayout& layout) : m_layout(layout) {
  const std::size_t maxNodes = layout.reservedCutNodes();
  m_blocks.reserve(maxNodes);
  m_mesh.reserve(layout, maxNodes);
  m_scratch.reserve(layout, maxNodes);
  m_vertexNode.reserve(dikeVertexBound(layout, maxNodes));
  m_visibleIndices.reserve(3 * dikeTriangleBound(layout, maxNodes));
  m_visibleOwners.reserve(dikeTriangleBound(layout, maxNodes));
  m_inputs.reserve(maxNodes);
}

bool DikeStage::sameInputs(std::span<const SelectedNode> cut, std::span<const BlockMesh* const> cutMeshes) const {
  if (m_failed || cut.size() != m_inputs.size()) return false;
  for (std::size_t i = 0; i < cut.size(); ++i) {
    const BlockMesh* mesh = cutMeshes[i];
    const Input input{cut[i].node, cut[i].visible, mesh, mesh ? mesh->revision : 0};
    // A mesh no cache numbered (revision 0) may have changed in place: never trust it.
    if (!(input == m_inputs[i]) || (mesh && mesh->revision == 0)) return false;
  }
  return true;
}

bool DikeStage::stitch(std::span<const SelectedNode> cut, std::span<const BlockMesh* const> cutMeshes) {
  assert(cut.size() == cutMeshes.size() && "DikeStage::stitch: one mesh per node of the cut");
  if (sameInputs(cut, cutMeshes)) return false;
  m_inputs.clear();
  for (std::size_t i = 0; i < cut.size(); ++i)
    m_inputs.push_back(Input{cut[i].node, cut[i].visible, cutMeshes[i], cutMeshes[i] ? cutMeshes[i]->revision : 0});
  m_blocks.clear();
  for (std::size_t i = 0; i < cut.size(); ++i) m_blocks.push_back(DikeBlock{cut[i].node, cutMeshes[i]});
  m_visibleIndices.clear();
  m_visibleOwners.clear();
  // The cut comes from the quadtree, so a failure here is a programming error upstream; the
  // frame then simply has no dikes rather than a crash.
  m_failed = !buildDikes(m_layout, m_blocks, m_mesh, m_scratch).ok();
  if (m_failed) {
    m_mesh.clear();
    return true;
  }

  // The output lists every node's boundary vertices, node by node in cut order (corners only
  // for a node without a mesh), then the DEM-border samples.
  m_vertexNode.assign(m_mesh.vertices.size(), kNoNode);
  std::size_t next = 0;
  for (std::size_t i = 0; i < cut.size(); ++i) {
    std::size_t count = 4;
    if (const BlockMesh* mesh = cutMeshes[i]) {
      count = 0;
      for (const auto& side : mesh->edges) count += side.size();
      count -= 4;  // each corner sits on two sides
    }
    for (std::size_t v = next; v < next + count && v < m_vertexNode.size(); ++v) m_vertexNode[v] = std::uint32_t(i);
    next += count;
  }
  auto visible = [&](std::uint32_t v) { return m_vertexNode[v] != kNoNode && cut[m_vertexNode[v]].visible; };
  for (std::size_t t = 0; t + 2 < m_mesh.indices.size(); t += 3) {
    const std::uint32_t a = m_mesh.indices[t], b = m_mesh.indices[t + 1], c = m_mesh.indices[t + 2];
    // A triangle of DEM-border samples only (at the north-east corner) goes with its owner.
    if (visible(a) || visible(b) || visible(c) || cut[m_mesh.owners[t / 3]].visible) {
      m_visibleIndices.insert(m_visibleIndices.end(), {a, b, c});
      m_visibleOwners.push_back(m_mesh.owners[t / 3]);
    }
  }
  return true;
}

WatertightReport DikeStage::checkWatertight() const {
  TriangleSoup soup;
  for (const DikeBlock& block : m_blocks) {
    if (block.mesh) {
      soup.addBlock(*block.mesh);
      continue;
    }
    // A node without a mesh stitches as its corners (DikeBlock): the two triangles between
    // them, cut from south-east to north-west, are its surface.
    const SampleRect fp = m_layout.footprint(block.node);
    const int stride = m_layout.stride(block.node);
    const int n = 1 << m_layout.k();
    const int x1 = fp.x0 + std::min(n, (m_layout.width() - 1 - fp.x0) / stride) * stride;
    const int y1 = fp.y0 + std::min(n, (m_layout.height() - 1 - fp.y0) / stride) * stride;
    const GridPoint sw{fp.x0, fp.y0}, se{x1, fp.y0}, ne{x1, y1}, nw{fp.x0, y1};
    soup.addTriangle(sw, se, nw);
    soup.addTriangle(se, ne, nw);
  }
  soup.addDikes(m_mesh);
  WatertightReport report = terrain::checkWatertight(soup, m_layout.width(), m_layout.height());
  if (m_failed) ++report.openEdges;  // no dikes at all: count the frame as broken
  return report;
}

}  // namespace polder::terrain
