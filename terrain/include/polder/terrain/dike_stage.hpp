// The dike step of a frame: stitches the gap network of the whole cut (terrain/dikes.hpp)
// and keeps, for drawing, the dike triangles that touch a visible block.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <polder/terrain/block_quadtree.hpp>
#include <polder/terrain/dikes.hpp>
#include <polder/terrain/watertight.hpp>

namespace polder::terrain {

class DikeStage {
 public:
  explicit DikeStage(const BlockLayout& layout);

  // Triangulates the gaps between the meshes of the cut (cutMeshes[i] for cut[i]; null for
  // a node without a mesh, which then counts as its corners). When the cut, its visibility
  // and every mesh (by BlockMesh::revision) are those of the last stitch, the dikes are the
  // same and are kept as they are: returns false then, true when it stitched.
  bool stitch(std::span<const SelectedNode> cut, std::span<const BlockMesh* const> cutMeshes);

  // False when the last cut could not be stitched (it was not a cut of the layout): no dikes.
  bool stitched() const { return !m_failed; }
  const DikeMesh& mesh() const { return m_mesh; }
  // Triangles (indices into mesh().vertices) with a vertex on a visible block's side, or
  // owned by a visible block.
  std::span<const std::uint32_t> visibleIndices() const { return m_visibleIndices; }
  std::size_t visibleTriangleCount() const { return m_visibleIndices.size() / 3; }
  // Per visible triangle: the index in the cut of its owner (DikeMesh::owners).
  std::span<const std::uint32_t> visibleOwners() const { return m_visibleOwners; }
  // Per vertex of mesh(): the index in the cut of the node whose side it is on, or kNoNode for
  // a DEM-border sample.
  static constexpr std::uint32_t kNoNode = 0xffffffffu;
  std::span<const std::uint32_t> vertexNodes() const { return m_vertexNode; }

  // Checks the last stitched frame, blocks and dikes together (allocates: not for the frame path).
  WatertightReport checkWatertight() const;

 private:
  BlockLayout m_layout;
  std::vector<DikeBlock> m_blocks;
  DikeMesh m_mesh;
  DikeScratch m_scratch;
  std::vector<std::uint32_t> m_vertexNode;
  std::vector<std::uint32_t> m_visibleIndices;
  std::vector<std::uint32_t> m_visibleOwners;
  // What the last stitch was made from: per node of the cut, its node, visibility and mesh.
  struct Input {
    NodeId node;
    bool visible = false;
    const BlockMesh* mesh = nullptr;
    std::uint64_t revision = 0;
    friend bool operator==(const Input&, const Input&) = default;
  };
  std::vector<Input> m_inputs;
  bool sameInputs(std::span<const SelectedNode> cut, std::span<const BlockMesh* const> cutMeshes) const;
  bool m_failed = false;
};

}  // namespace polder::terrain
