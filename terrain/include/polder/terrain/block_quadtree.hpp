// The block quadtree: per-node height ranges and error bounds over a BlockLayout, and the
// per-frame selection of a quadtree cut (docs/design.md "One frame", step 1, and "Terrain").
//
// Follows F. Strugar, "Continuous distance-dependent level of detail for rendering
// heightmaps" (CDLOD, JGT 2009) for per-node min/max boxes and selection into a caller
// buffer, and T. Ulrich, "Rendering massive terrains using chunked level of detail control"
// (SIGGRAPH 2002 course) for the screen-space rule K * delta / distance <= tau.
//
// What a node stores. For every node of every level, three small numbers (plus the parts of
// delta, for diagnostics); NOT its BlockLod:
//   minHeight, maxHeight  exact range of the full-resolution samples of the node's whole
//                         footprint (interior and dike, every sample, not only the strided
//                         ones), for the node's bounding box;
//   delta                 a conservative bound, in metres, on the vertical error of drawing
//                         this node (its BlockLod's mesh and its dikes) instead of the full-
//                         resolution surface: max(BlockLod::maxError(), BlockLod::floorError(),
//                         dike bound). Children's deltas are not folded in: delta is about this
//                         node's own drawing. floorError is listed although the coarsest mesh's
//                         error usually exceeds it, because a finer bintree triangle can fit its
//                         samples worse than the coarse one and the bound must hold for every
//                         mesh the node may draw at its stride.
// Keeping every node's BlockLod would cost about 22 KB per 33 x 33 node, i.e. ~450 MB for a
// 4096^2 DEM, so the tree keeps 20 bytes per node and the frame pipeline builds (or finds in
// the LOD cache) the BlockLod of the nodes it selects, with BlockLod::build on its loaders.
//
// Building. Every node's error needs a BlockLod::build over all the full-resolution samples
// of its interior: a level-L node costs about 4^L level-0 blocks, so each level costs about
// one pass of BlockLod::build over the whole DEM and the tree (rootLevel + 1) passes. Nodes
// are shared out to worker threads, coarsest first so that no thread is left with one huge
// node at the end; each node's numbers depend only on the node, so the result is the same for
// any thread count.
//
// Dikes. The node's dike strip is drawn by the dikes module (dikes.hpp), whose bound
// (dike_errors.hpp, dikeErrorBound()) the caller injects through
// BlockQuadtreeOptions::dikeErrorBound; the frame pipeline passes the dikes' bound there.
// Without it the dike term is 0 and delta bounds the node's interior only. The dike bound
// must also cover the full-resolution samples a clipped interior leaves uncovered at the DEM's
// east and north edges (fewer than `stride` columns or rows, rtin.hpp "Clipped blocks"):
// block_layout.hpp counts them as dike.
//
// Nodes that cannot be drawn at their stride. A coarse node at the DEM's east or north edge
// may have less than one strided cell inside the DEM (e.g. 1 sample column left at stride 4):
// BlockLod cannot build it. Its errors are +infinity, so selection always refines it; level-0
// blocks always have a whole cell (BlockLayout's existence rule), so refinement ends.
//
// Selection (select()). Depth-first from the root. A node whose box is outside the frustum is
// output as culled (visible = false) at that level and not descended. A visible node is
// refined while K * delta > tau * distance (distance from the camera to the node's box, 0
// inside it; delta = 0 is exact and never refined; K = Camera::errorProjectionConstant(), which
// bounds a vertical error's size in pixels anywhere in the view, not only at its centre);
// level-0 nodes are taken when visible.
// The output is a CUT: culled and taken nodes together tile the DEM exactly (no overlap, no
// gap), which the dikes need to close every gap between neighbouring blocks. Callers that
// only draw skip visible == false. Order: depth first, SW, SE, NW, NE within each parent.
//
// Residency. select() takes an optional predicate isResident(NodeId). Before refining a node
// it asks about each child that is visible (culled children are never drawn, so their data
// need not be loaded); if one is not resident, the node itself is taken, flagged
// refinementBlocked: the cut falls back to the resident ancestor and never has a hole. The
// root is taken as resident (the pipeline keeps the coarsest level loaded).
//
// Threads: a built BlockQuadtree is immutable; select() is const and may run concurrently,
// each call with its own SelectionScratch and output vector. build() calls dikeErrorBound and
// progress on the calling thread only.
//
// Use:
//   auto layout = BlockLayout::create(field.width, field.height);
//   BlockQuadtreeOptions options;
//   options.dikeErrorBound = [&](NodeId n) { return dikeErrorBound(field, *layout, n); };
//   auto tree = BlockQuadtree::build(field, *layout, options);     // once, at load
//   SelectionScratch scratch;
//   std::vector<SelectedNode> cut;
//   scratch.reserve(*tree);
//   cut.reserve(layout->reservedCutNodes());                        // select() allocates no more
//   tree->select(camera, SelectionOptions{1.0}, scratch, cut, isResident);  // every frame
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <type_traits>
#include <utility>
#include <vector>

#include <polder/camera.hpp>
#include <polder/frustum.hpp>
#include <polder/result.hpp>
#include <polder/terrain/block_layout.hpp>
#include <polder/terrain/heightfield.hpp>
#include <polder/thread_pool.hpp>

namespace polder::terrain {

struct BlockQuadtreeOptions {
  // Vertical error bound (metres, >= 0) of the node's dike strip; empty means 0. The frame
  // pipeline passes the dikes module's dikeErrorBound. Called once per node, on the calling
  // thread.
  std::function<float(NodeId)> dikeErrorBound;
  // Called on the calling thread with a fraction rising from 0 to 1 (weighted by samples).
  std::function<void(float)> progress;
  // The pool the node errors are built on (the calling thread takes part); null: a pool of
  // one thread per hardware thread. The tree does not depend on it.
  core::ThreadPool* pool = nullptr;
};

// What the tree keeps per node (see the top of this file).
struct NodeInfo {
  float minHeight = 0.0f;  // exact, over the node's whole footprint
  float maxHeight = 0.0f;
  float lodError = 0.0f;    // BlockLod::maxError() of the node; +inf when not drawable at its stride
  float floorError = 0.0f;  // BlockLod::floorError() of the node; +inf likewise
  float dikeError = 0.0f;   // BlockQuadtreeOptions::dikeErrorBound of the node

  // The selection's delta: the error of drawing this node, whatever mesh it extracts.
  float delta() const { return std::max(std::max(lodError, floorError), dikeError); }
  // The error no mesh of this node can avoid: what its stride and dikes leave (see
  // NodeErrorMeasure::Floor).
  float floorDelta() const { return std::max(floorError, dikeError); }
};

// Which error select() compares with tau.
enum class NodeErrorMeasure {
  // delta (NodeInfo::delta()): the node is taken only when even its coarsest mesh is within
  // tau. Conservative whatever the block LOD step then does.
  Delta,
  // NodeInfo::floorDelta(): the node is taken when its finest mesh is within tau, and the
  // per-block view-dependent extraction (LodView) keeps the rest within tau. Selects far
  // fewer, coarser nodes; valid only when every selected node is then extracted with
  // BlockLod::extractView at the same tau.
  Floor,
};

struct SelectionOptions {
  double tolerancePx = 1.0;  // tau, pixels (> 0)
  NodeErrorMeasure errorMeasure = NodeErrorMeasure::Delta;
  // Ask isResident about culled children too, and refine a culled node (a forced split, or
  // one not drawable at its stride) only into resident children: every node of the cut is
  // then resident, for a caller whose heights live only in resident data (a pyramid).
  bool culledNeedResidency = false;
  // Nodes to refine whatever their error or visibility (with their ancestors), where a check
  // after the selection found that drawing them breaks the tolerance (the engine's dike
  // check). A short list: each visited node scans it.
  std::span<const NodeId> forcedSplits;
};

struct SelectedNode {
  NodeId node;
  double distanceM = 0.0;          // camera to the node's box, metres (0 inside)
  bool visible = false;            // false: culled, in the cut only to tile the DEM
  bool refinementBlocked = false;  // wanted finer, but a visible child was not resident
};

struct SelectionStats {
  std::size_t nodesVisited = 0;  // nodes whose box was classified (or inherited "inside")
  std::size_t visibleNodes = 0;
  std::size_t culledNodes = 0;
  std::size_t blockedNodes = 0;  // refinementBlocked
};

// A non-owning reference to a callable bool(NodeId), like C++26's std::function_ref: no
// allocation, ever. Only as a function parameter: it must not outlive the callable.
class NodePredicate {
 public:
  NodePredicate() = default;
  template <class F, class = std::enable_if_t<!std::is_same_v<std::decay_t<F>, NodePredicate>>>
  NodePredicate(const F& callable)  // NOLINT: implicit, like std::function_ref
      : m_object(&callable),
        m_call([](const void* object, NodeId node) { return bool((*static_cast<const F*>(object))(node)); }) {}

  explicit operator bool() const { return m_call != nullptr; }
  bool operator()(NodeId node) const { return m_call(m_object, node); }

 private:
  const void* m_object = nullptr;
  bool (*m_call)(const void*, NodeId) = nullptr;
};

class BlockQuadtree;

// select()'s working memory, kept by the caller (one per thread).
class SelectionScratch {
 public:
  // Room for any selection over `tree`.
  void reserve(const BlockQuadtree& tree);

 private:
  friend class BlockQuadtree;
  struct Entry {
    NodeId node;
    FrustumTest test = FrustumTest::Intersecting;
    bool tested = false;  // test is known (from the parent)
  };
  std::vector<Entry> m_stack;
};

class BlockQuadtree {
 public:
  BlockQuadtree() = default;

  // Builds the node data of `layout` over `field`. InvalidArgument when the field's size
  // differs from the layout's, or dikeErrorBound returns a negative or NaN bound;
  // InvalidData when a sample is not finite (no-data left unfilled); OutOfMemory when the
  // node table cannot be allocated.
  static Result<BlockQuadtree> build(const Heightfield& field, const BlockLayout& layout,
                                     const BlockQuadtreeOptions& options = {});
  // A tree whose node data was computed before, e.g. read from a pyramid (pyramid.hpp): one
  // NodeInfo per node of `layout` in the tree's order (levels finest first, rows south first).
  // InvalidArgument when the count differs from the layout's or a spacing is not positive;
  // InvalidData when a node's range is not finite or inverted, or an error is negative or NaN.
  static Result<BlockQuadtree> fromNodes(const BlockLayout& layout, double spacingX, double spacingY,
                                         std::vector<NodeInfo> nodes);

  const BlockLayout& layout() const { return m_layout; }
  std::size_t nodeCount() const { return m_nodes.size(); }
  // The most nodes a selection can output (the number of level-0 blocks: a cut's nodes are
  // disjoint and each holds at least one).
  std::size_t selectionBound() const { return std::size_t(m_layout.nodesX(0)) * std::size_t(m_layout.nodesY(0)); }

  // Asserts that the node exists (BlockLayout::exists).
  const NodeInfo& info(const NodeId& node) const { return m_nodes[nodeIndex(node)]; }
  // World-frame bounding box of the node's footprint: x, y from its samples times the
  // spacing, z from its height range.
  Aabb box(const NodeId& node) const;

  // The cut for `camera` (see the top of this file) into `out`, cleared first. Allocates only
  // when `scratch` has less room than reserve() gives or the cut is larger than `out`'s room.
  SelectionStats select(const Camera& camera, const SelectionOptions& options, SelectionScratch& scratch,
                        std::vector<SelectedNode>& out, NodePredicate isResident = {}) const;

  std::size_t memoryBytes() const;

 private:
  std::size_t nodeIndex(const NodeId& node) const;
  Aabb relativeBox(const NodeId& node, const glm::dvec3& camera) const;

  BlockLayout m_layout;
  double m_spacingX = 1.0;
  double m_spacingY = 1.0;
  std::vector<std::size_t> m_levelOffset;  // first node index of each level
  std::vector<NodeInfo> m_nodes;           // level by level, row by row (south first)
};

}  // namespace polder::terrain
