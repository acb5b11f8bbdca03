// Dikes: the triangles that close the gaps between the blocks of a frame (docs/design.md "One
// frame" step 3, "Terrain / Grid and dikes").
//
// Follows:
// - J.-H. Chuang (莊榮宏), "Level-of-Detail Modeling Technique for Virtual Reality (I)", NSC
//   89-2218-E-009-012 final report, National Chiao Tung University, 2001, part B: blocks with a dike between each pair
//   of neighbours, triangulated every frame from the boundary vertices each block's current LOD kept, so that meshes of
//   different resolution join without cracks. Here generalised to quadtree nodes of any level (dikes `stride` cells
//   wide) and to neighbours that differ by any number of levels and LOD steps.
//
// The gap network. Interiors never touch (block_layout.hpp): east and north of every interior
// lies its dike strip, `stride` cells wide (less where a footprint or a clipped interior meets
// the DEM's east or north edge). Everything that is not an interior is dike, and buildDikes
// triangulates all of it, every frame, using only vertices that some block's current mesh has
// on its sides (BlockMesh::edges), plus full-resolution samples of the DEM's east and north
// border where the gap touches it. Together with the block meshes the result is watertight:
// every edge off the DEM border is shared by exactly two triangles, no vertex lies inside an
// edge, no triangle is degenerate, all are counter-clockwise seen from +z, and the union covers
// [0, width-1] x [0, height-1] exactly once (watertight.hpp checks all of it).
//
// How. (1) Zippers: for every pair of facing interior sides (an interior's east side and the
// west side of a node whose footprint starts where its footprint ends; likewise north/south)
// the strip between them over the common range is a rectangle free of anything else. The kept
// vertices of both sides inside that range are merged by coordinate into a strip of triangles,
// each spanning two neighbouring vertices of one side and one of the other (two parallel
// lines: never degenerate). Against the DEM's east and north border the other side is the
// border samples. (2) Junctions: what the zippers leave (around interior corners, and where a
// coarse side has no vertex in a finer neighbour's range) is a set of polygons bounded by
// chain pieces, zipper ends and border samples. They are found by walking around each
// interior's boundary in order, jumping across zippers, and triangulated by ear clipping that
// takes the shortest valid diagonal first (of two equally long, the one running north-west to
// south-east, as the surface cuts its cells) and rejects zero-area ears, so vertices on straight
// sides stay vertices (no T-junctions). Every interior has a zipper with a node of its
// parent's other children on a side where their footprints start together, so all interiors
// and zippers hang together and every junction polygon is simply connected.
//
// Cost: linear in the kept boundary vertices, plus the junction polygons' ear clipping
// (quadratic in a polygon's size; junctions have a handful of vertices except along a coarse
// side with no vertex in a long range): about 0.1 to 0.3 ms for 400 blocks of 33 x 33
// samples at view-dependent LODs on one core. The output and all working memory are caller
// storage (DikeMesh, DikeScratch); after reserve() a frame allocates nothing. Where both
// sides keep every vertex (stride 1, full detail) a zipper cuts each cell along the same
// diagonal as heightfield.hpp, so such dikes are the full-resolution surface itself.
//
// Errors: dike_errors.hpp gives every dike triangle's exact vertical error against the
// full-resolution surface and an a-priori bound per quadtree node on the triangles it owns
// (DikeMesh::owners).
//
// Threads: buildDikes is a pure function of its inputs; concurrent calls need their own
// DikeMesh and DikeScratch.
//
// Use:
//   DikeMesh dikes;      // kept, reserved once
//   DikeScratch scratch;
//   dikes.reserve(layout, maxNodes);
//   scratch.reserve(layout, maxNodes);
//   std::vector<DikeBlock> blocks;  // per node of the cut: its NodeId and current BlockMesh
//   Status status = buildDikes(layout, blocks, dikes, scratch);  // every frame
//   // dikes.vertices are full-resolution samples (x, y): height field.at(x, y).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <polder/result.hpp>
#include <polder/terrain/block_layout.hpp>
#include <polder/terrain/block_mesh.hpp>

namespace polder::terrain {

// A dike vertex: a full-resolution sample in global coordinates (x east, y north).
struct DikeVertex {
  std::int32_t x = 0;
  std::int32_t y = 0;
  friend bool operator==(const DikeVertex&, const DikeVertex&) = default;
};

// One node of the frame's cut and the mesh it draws this frame.
struct DikeBlock {
  NodeId node;
  // Its current mesh: footprint layout.interior(node), cellsX/cellsY as BlockLod clips them.
  // nullptr for a node the frame does not draw (e.g. culled): its sides then count as their
  // two corners, exactly the sides of the two-triangle mesh of its (clipped) interior.
  const BlockMesh* mesh = nullptr;
};

// Upper bounds on one frame's dikes over at most `maxNodes` nodes of `layout`
// (meshoptimizer's ...Bound() idiom), for DikeMesh::reserve.
std::size_t dikeVertexBound(const BlockLayout& layout, std::size_t maxNodes);
std::size_t dikeTriangleBound(const BlockLayout& layout, std::size_t maxNodes);

struct DikeMesh {
  // Every boundary vertex of every node (each once), then the border samples used.
  std::vector<DikeVertex> vertices;
  std::vector<std::uint32_t> indices;  // three per triangle, counter-clockwise seen from +z
  // Per triangle: index (into the frame's DikeBlock list) of its owner, the node whose
  // dikeErrorBound covers it: for a zipper triangle the coarser of the two nodes it joins, for
  // a junction triangle the coarsest node around its junction polygon.
  std::vector<std::uint32_t> owners;
  // The first zipperTriangles triangles are zipper strips, the rest junction polygons.
  std::size_t zipperTriangles = 0;

  std::size_t triangleCount() const { return indices.size() / 3; }

  // Room for any frame of at most maxNodes nodes: building into a reserved mesh does not
  // allocate.
  void reserve(const BlockLayout& layout, std::size_t maxNodes) {
    vertices.reserve(dikeVertexBound(layout, maxNodes));
    indices.reserve(3 * dikeTriangleBound(layout, maxNodes));
    owners.reserve(dikeTriangleBound(layout, maxNodes));
  }
  void clear() {
    vertices.clear();
    indices.clear();
    owners.clear();
    zipperTriangles = 0;
  }
};

// Working memory of buildDikes, kept by the caller (one per thread) and reused every frame.
// Its members are buildDikes' business (dikes.cpp, dike_ear_clipping.cpp); they are spelled
// out here only so that the caller can own the memory.
class DikeScratch {
 public:
  // Room for frames of up to maxNodes nodes over `layout`.
  void reserve(const BlockLayout& layout, std::size_t maxNodes);
  // Bytes the scratch holds (its vectors' capacities): constant in steady state.
  std::size_t capacityBytes() const;

  struct Node {  // one node of the frame, in global sample coordinates
    const BlockMesh* mesh = nullptr;
    int level = 0;
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // interior (clipped)
    int fx1 = 0, fy1 = 0;                // footprint's north-east corner (clipped)
    std::uint32_t vertexBase = 0;        // output vertex of clockwise position 0 (north-west corner)
    std::uint32_t perimeter = 0;         // clockwise positions 0..perimeter-1; perimeter is 0 again
    std::uint32_t sideCount[4] = {};     // kept vertices per side, BlockEdge order
    std::uint32_t attachmentBegin = 0;   // its attachments, clockwise, in m_order
    std::uint32_t attachmentEnd = 0;
    std::uint32_t eastBorderAttachment = 0;   // its zipper with the DEM's east border, or none
    std::uint32_t northBorderAttachment = 0;  // its zipper with the DEM's north border, or none
  };
  struct Attachment {  // a zipper's range [xs, xe] on one member's clockwise boundary
    std::uint32_t node = 0;
    std::uint32_t xs = 0, xe = 0;
    std::uint32_t side = 0;      // BlockEdge
    std::uint32_t twin = 0;      // the other member's attachment, or none (the DEM border)
    std::uint32_t rank = 0;      // position in its node's clockwise list
    std::uint32_t borderXs = 0;  // DEM-border zipper: output vertices of the border's ends
    std::uint32_t borderXe = 0;
    std::int32_t borderCoordinate = 0;  // DEM-border zipper: y (east) or x (north) of borderXe
  };
  struct Cell {  // level-0 block -> node of the cut covering it
    std::uint32_t stamp = 0;
    std::uint32_t node = 0;
  };
  struct BorderSample {  // border samples are numbered when first used
    std::uint32_t stamp = 0;
    std::uint32_t vertex = 0;
  };
  struct ChainPoint {  // a zipper side: output vertex and coordinate along the side
    std::uint32_t vertex = 0;
    std::int32_t along = 0;
  };
  struct Ear {  // ear clipping's doubly linked polygon
    std::int64_t x = 0, y = 0;
    std::uint32_t vertex = 0;
    std::uint32_t prev = 0, next = 0;
    std::int64_t diagonal2 = -1;  // rank of the ear's diagonal (by squared length), -1 when not an ear
  };

 private:
  friend struct DikeBuilder;
  std::vector<Node> m_nodes;
  std::vector<Cell> m_cells;
  std::vector<Attachment> m_attachments;
  std::vector<std::uint32_t> m_order;        // per node, its attachments clockwise
  std::vector<std::uint8_t> m_visited;       // per attachment: the junction after it is walked
  std::vector<std::uint32_t> m_vertexOwner;  // per output vertex: node index
  std::vector<BorderSample> m_eastBorder;    // per y of the east border
  std::vector<BorderSample> m_northBorder;   // per x of the north border
  std::vector<ChainPoint> m_chains;          // the two sides of the zipper being built
  std::vector<std::uint32_t> m_polygon;      // the junction being walked
  std::vector<Ear> m_ears;
  std::uint32_t m_stamp = 0;
};

// Triangulates the whole gap network of one frame into `out` (cleared first). `blocks` must
// be a quadtree cut of `layout`: nodes that exist, can be drawn at their stride (at least one
// whole strided cell inside the DEM each way), and whose footprints tile the DEM exactly;
// each mesh must be for its node's interior. InvalidArgument otherwise (nothing is asserted
// on these inputs). Allocates only where `out` or `scratch` lack room (see reserve()).
Status buildDikes(const BlockLayout& layout, std::span<const DikeBlock> blocks, DikeMesh& out, DikeScratch& scratch);

// The side positions of a block a dike triangle lies beside, for BoundaryPins: where the
// triangle (bounding box `triangle`, full-resolution samples) lies in the gap east or west of
// `mesh`'s interior, its West or East side over the box's rows, rounded outwards to the
// stride; likewise South or North over its columns. Keeping those side vertices refines the
// dike there (the engine's dike check, uniformMesh). At most two sides; returns how many.
struct SideRange {
  BlockEdge side = BlockEdge::South;
  int from = 0;  // positions along the side (BoundaryPins), inclusive
  int to = 0;
};
int sidesBesideDikeTriangle(const BlockMesh& mesh, const SampleRect& triangle, SideRange out[2]);

}  // namespace polder::terrain
