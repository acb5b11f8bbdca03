// Per-block level of detail: an error hierarchy over one block's (2^k+1)^2 vertices, organised
// as a right-triangle bintree, and extraction of crack-free meshes from it.
//
// Follows:
// - W. Evans, D. Kirkpatrick, G. Townsend. Right-triangulated irregular networks.
//   Algorithmica 30(2), 2001 (the RTIN: bintree of right isosceles triangles over a grid).
// - P. Lindstrom, D. Koller, W. Ribarsky, L. Hodges, N. Faust, G. Turner. Real-time,
//   continuous level of detail rendering of height fields. SIGGRAPH 1996 (vertex
//   dependencies that keep a bintree mesh conforming).
// - M. Duchaineau, M. Wolinsky, D. Sigeti, M. Miller, C. Aldrich, M. Mineev-Weinstein.
//   ROAMing terrain: real-time optimally adapting meshes. IEEE Visualization 1997 (monotone
//   error bounds; greedy refinement by a split queue with forced splits).
// - R. Pajarola. Large scale terrain visualization using the restricted quadtree
//   triangulation. IEEE Visualization 1998 (saturated, monotone vertex errors).
// - P. Lindstrom, V. Pascucci. Visualization of large terrains made easy. IEEE
//   Visualization 2001 (nested bounding spheres for a monotone view-dependent test).
//
// The bintree. The two roots are the halves of the block square cut along its diagonal from
// the south-east corner to the north-west corner. A triangle (apex a; hypotenuse b, c) splits
// at the midpoint m of its hypotenuse into (m; a, b) and (m; c, a). Every vertex except the
// four corners is the hypotenuse midpoint of one triangle (on the block's side) or two (inside),
// so a mesh is a set of active vertices: a triangle is split iff its midpoint is active. The
// finest triangles are half cells.
//
// Errors. A triangle's error is EXACT against the full-resolution surface, which is the
// triangulation of heightfield.hpp (each cell cut from (x+1, y) to (x, y+1)), not only its
// samples: the largest vertical distance, in metres, between the triangle's plane and that
// surface anywhere over the closed triangle. The difference is piecewise linear, largest at a
// vertex of the two triangulations' overlay: a full-resolution sample in the triangle (all
// samples, not only the strided ones, edges included), or a cell centre on a triangle edge that
// runs south-west to north-east (such an edge crosses each cell diagonal there; the surface is
// the mean of the diagonal's ends), and both are scanned.
//
// Half cells at stride 1. The bintree cuts half of the cells (a checkerboard) along the other
// diagonal than the surface, south-west to north-east, off by |h00 + h11 - h10 - h01| / 2 at
// the centre. Where both halves of such a cell are in a mesh (a diamond; always so in the
// full-detail mesh) they are drawn cut like the surface instead, for the cell with corners
// p00 = (i, j) and p11 = (i+1, j+1): the half with apex p10, {p00, p10, p11}, as {p00, p10, p01},
// the half with apex p01, {p11, p01, p00}, as {p11, p01, p10}. Same cell, same sides, so the
// mesh stays conforming, and their error is 0. A half cell whose cell's other half is not in
// the mesh (its hypotenuse is then a leg of the coarser triangle beside it, whose midpoint,
// the cell's other corner, is inactive) keeps the bintree's cut and its error, the gap; that
// coarser triangle's leg crosses the same cell centre, so its error, and its midpoint's, is at
// least the gap. So a mesh's triangles are the bintree's, but for those flipped halves; at a
// stride above 1 nothing is flipped (a half cell is then a strided cell, not the surface's).
//
// A vertex's error is the largest error of the triangles it splits and of every vertex below
// it, so errors only shrink going down the tree. Therefore any rule "active iff error >
// threshold" (threshold monotone too) gives a conforming mesh (no T-junctions) in which every
// triangle's exact error is at most its midpoint's error, except half cells, whose error is at
// most floorError() (0 at stride 1) or, at stride 1 when not flipped, at most the error of
// the inactive vertex beside it (within the threshold too). A vertex's radius bounds, in 3D,
// the triangles it splits (their drawn
// planes and the true surface under them) and, nested, the spheres of every vertex below it,
// which keeps the view-dependent test monotone.
//
// Clipped blocks. A block may run past the DEM's east or north edge. It then keeps the valid
// sub-rectangle of cellsX x cellsY cells whose vertices all lie in the field, and never
// stretches anything: triangles that straddle the rectangle's border are always split (their
// vertices get infinite error), triangles outside it are dropped, so every mesh tiles exactly
// [0, cellsX] x [0, cellsY] and its east and north edges are i = cellsX and j = cellsY.
// Full-resolution samples beyond the last strided vertex (fewer than `stride` columns or rows
// at the field's edge) are not covered by this block; a finer quadtree level covers them.
//
// Threads: a built BlockLod is immutable; extractions are const and may run concurrently,
// each with its own BlockMesh and RtinScratch.
//
// Use:
//   auto lod = BlockLod::build(field, BlockFootprint{x0, y0, 5, 1});  // once, on a loader thread
//   BlockMesh mesh;                                                   // kept, e.g. in the LOD cache
//   RtinScratch scratch;                                              // one per thread
//   mesh.reserve(5);
//   scratch.reserve(5);
//   lod->extractView(LodView{camera.position - lod->origin(), camera.projectionConstant(), tau}, mesh, scratch);
//   // mesh.vertices are grid indices: global sample (x0 + i * stride, y0 + j * stride).
#pragma once

#include <cassert>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include <polder/result.hpp>
#include <polder/terrain/block_mesh.hpp>
#include <polder/terrain/heightfield.hpp>

namespace polder::terrain {

// The largest k a block may have (257 x 257 vertices).
inline constexpr int kRtinMaxK = 8;

// A viewpoint for view-dependent extraction: vertex v is active iff
//   error(v) > tolerancePx * max(|camera - v| - radius(v), nearM) / projectionConstant.
// Every triangle of the result then projects to at most tolerancePx pixels of vertical error,
// K * error / max(distance to the triangle, nearM) <= tolerancePx, except the finest triangles
// (half cells). At a stride above 1 their error is at most BlockLod::floorError(), which a finer
// quadtree level removes. At stride 1 a diamond's halves are drawn cut like the surface (error
// 0); a lone half cell keeps the bintree's cut (see "Half cells at stride 1" above), its error
// the gap at its cell's centre, which lies on the inactive coarser triangle beside it: bounded
// by that triangle's midpoint error, so its projected error at that centre is within the
// tolerance (the midpoint's sphere holds the centre), measured at the centre's distance rather
// than the half cell's own, possibly nearer, one.
struct LodView {
  glm::dvec3 camera{0.0};           // camera position minus BlockLod::origin(), metres
  double projectionConstant = 1.0;  // K = viewport height / (2 tan(fovy / 2)), Camera::projectionConstant()
  double tolerancePx = 1.0;         // tau, pixels
  double nearM = 1.0;               // distances below this count as this (no blow-up under the eye)
};

// Working memory of the extractions, kept by the caller (one per thread) so that steady-state
// extraction allocates nothing.
class RtinScratch {
 public:
  // Room for blocks of up to 2^k cells per side.
  void reserve(int k);

 private:
  friend class BlockLod;
  void prepare(std::size_t vertexCount);

  std::vector<std::uint32_t> m_remap;  // grid vertex -> mesh vertex; all "none" between calls
  std::vector<std::uint32_t> m_queue;  // count extraction: split candidates, a max-heap by error;
                                       // pinned extraction: the marking stack
  std::vector<std::uint8_t> m_state;   // count extraction: split parents received, and a split flag;
                                       // pinned extraction: the marked vertices
};

// The error hierarchy of one block, built from a Heightfield.
class BlockLod {
 public:
  BlockLod() = default;

  // Builds the hierarchy of `footprint` over `field`. O(full-resolution samples * 2k) time:
  // every bintree level scans all the samples under it once (and the cell centres on its
  // triangles' south-west to north-east edges, O(side) per triangle). Errors (never asserts)
  // when the block has no whole cell inside the field or a sample in it is not finite.
  // Programmer errors (k outside 1..kRtinMaxK, stride not a power of two, negative origin)
  // assert.
  static Result<BlockLod> build(const Heightfield& field, const BlockFootprint& footprint);
  // Same, reusing this object's memory.
  Status rebuild(const Heightfield& field, const BlockFootprint& footprint);
  // The hierarchy of `footprint` from its own strided vertices only, as a pyramid tile holds
  // them (docs/streaming.md): `samples` has vertex (i, j) of the block at (i, j), spacing
  // stride times the full-resolution spacing (fewer than 2^k + 1 columns or rows for a block
  // clipped by the DEM's edge). Its errors are exact against the level surface (the samples
  // triangulated as heightfield.hpp cuts cells) plus a bound on how far the full-resolution
  // surface lies from the level surface: `cellResidualM`, one bound per cell of `samples`
  // ((width - 1) x (height - 1), row-major, south row first). A triangle adds the largest bound
  // of the cells it covers, a vertex the largest of every triangle below it, so errors stay
  // monotone and bound the errors build() would find against the full resolution. At stride 1
  // with no residual `samples` is the full resolution and the result is build()'s. At a stride
  // above 1 half cells are not flipped, as in build(): each keeps its error, at least its
  // cell's residual, and so does floorError().
  static Result<BlockLod> buildFromLevel(const Heightfield& samples, const BlockFootprint& footprint,
                                         std::span<const float> cellResidualM);
  // Same with one residual for every cell.
  static Result<BlockLod> buildFromLevel(const Heightfield& samples, const BlockFootprint& footprint, float residualM);

  // (a) View-dependent: the conforming mesh of the vertices active for `view` (see LodView).
  // `pins`, when given, adds its side vertices and, to keep the mesh conforming, every vertex
  // they depend on (the apexes of the triangles they split, recursively): the result is then
  // the view's mesh refined, so the view's bound still holds. Pins outside a clipped block's
  // valid rectangle are ignored.
  void extractView(const LodView& view, BlockMesh& out, RtinScratch& scratch, const BoundaryPins* pins = nullptr) const;
  // (b) Greedy to a triangle count, as ROAM's split queue: repeatedly splits the triangle of
  // largest error together with its hypotenuse neighbour (with monotone errors the forced
  // splits are already done), and stops before the split that would exceed `targetTriangles`
  // or when no split lowers the error (all remaining errors 0). The result never exceeds the
  // target, except that the coarsest mesh (2 triangles; more for a clipped block) is the
  // least it returns.
  void extractCount(std::size_t targetTriangles, BlockMesh& out, RtinScratch& scratch) const;
  // (c) Uniform: vertex v is active iff error(v) > maxError (metres). 0 drops every vertex
  // that costs nothing; a negative value keeps every vertex (full detail, 2 * 4^k triangles).
  // `pins` as for extractView: the threshold's mesh refined, so its bound still holds.
  void extractThreshold(float maxError, BlockMesh& out, RtinScratch& scratch, const BoundaryPins* pins = nullptr) const;

  const BlockFootprint& footprint() const { return m_footprint; }
  int cellsX() const { return m_cellsX; }  // the valid sub-rectangle (= 2^k unless clipped)
  int cellsY() const { return m_cellsY; }
  bool clipped() const { return m_clipped; }

  // The block's node error for the quadtree's delta: the exact error of its coarsest mesh,
  // the two root triangles (for a clipped block, the mesh of its forced splits).
  float maxError() const { return m_maxError; }
  // The exact error of the full-detail mesh (its half cells): what the stride leaves. 0 at
  // stride 1, where the full-detail mesh is the surface's own triangulation (every cell a
  // diamond, drawn cut like the surface).
  float floorError() const { return m_floorError; }
  // Height range of the full-resolution samples the mesh covers (for node bounding boxes).
  float minHeight() const { return m_minHeight; }
  float maxHeight() const { return m_maxHeight; }

  // World position of block-local vertex (0, 0) at height 0: subtract it from a world camera
  // position to get LodView::camera.
  glm::dvec3 origin() const { return m_origin; }
  // Vertex (i, j) relative to origin(), metres. Outside a clipped block's valid rectangle the
  // height repeats the nearest valid vertex (never drawn).
  glm::dvec3 position(int i, int j) const {
    return {i * m_vertexSpacingX, j * m_vertexSpacingY, double(m_height[vertexIndex(i, j)])};
  }
  float height(int i, int j) const { return m_height[vertexIndex(i, j)]; }
  // Monotone error (metres; +infinity for a forced split of a clipped block) and nested radius
  // (metres) of vertex (i, j). Both 0 at the corners.
  float vertexError(int i, int j) const { return m_error[vertexIndex(i, j)]; }
  float vertexRadius(int i, int j) const { return m_radius[vertexIndex(i, j)]; }
  // Exact error of the bintree triangle (apex; b, c), in either winding. Asserts that it is one.
  // At stride 1 a half cell cut like the surface (a flipped half, see above) counts as one too,
  // with error 0; the bintree's own south-west to north-east halves keep theirs (the gap).
  float triangleError(GridVertex apex, GridVertex b, GridVertex c) const;

  std::size_t memoryBytes() const;

 private:
  std::size_t vertexIndex(int i, int j) const {
    assert(i >= 0 && i <= m_footprint.cells() && j >= 0 && j <= m_footprint.cells() &&
           "BlockLod: vertex outside the block");
    return std::size_t(j) * std::size_t(m_footprint.verticesPerSide()) + std::size_t(i);
  }
  template <class Active, class Leaf>
  void walk(Active& active, Leaf& leaf) const;
  template <class Active, class Leaf>
  void walkTriangle(int ax, int ay, int bx, int by, int cx, int cy, Active& active, Leaf& leaf) const;
  template <class Active>
  void emit(Active& active, BlockMesh& out, RtinScratch& scratch) const;
  float storedTriangleError(int ax, int ay, int bx, int by, int cx, int cy) const;
  // Marks (RtinScratch::m_state) the pinned side vertices and every vertex they depend on.
  void markPinned(const BoundaryPins& pins, RtinScratch& scratch) const;
  // Error of a half cell: cell (ci, cj), side as triangleSide in rtin_grid.hpp.
  float leafError(int ci, int cj, int sideIndex) const;
  // buildFromLevel's second half: adds the cells' residuals (cell (ci, cj) at
  // residual[cj * pitch + ci]) to the errors and radii built against the level surface.
  void addCellResiduals(std::span<const float> residual, int pitch);
  // The largest residual of the cells under bintree triangle (a; b, c), stored for the
  // triangle in `triangleResidual` (per vertex, as m_triangleError).
  float coverResidual(int ax, int ay, int bx, int by, int cx, int cy, std::span<const float> residual, int pitch,
                      std::vector<float>& triangleResidual) const;

  BlockFootprint m_footprint;
  int m_cellsX = 0;
  int m_cellsY = 0;
  bool m_clipped = false;
  glm::dvec3 m_origin{0.0};
  double m_vertexSpacingX = 1.0;  // metres between neighbouring vertices
  double m_vertexSpacingY = 1.0;
  float m_maxError = 0.0f;
  float m_floorError = 0.0f;
  float m_minHeight = 0.0f;
  float m_maxHeight = 0.0f;
  std::vector<float> m_height;         // per vertex
  std::vector<float> m_error;          // per vertex, monotone
  std::vector<float> m_radius;         // per vertex, nested
  std::vector<float> m_triangleError;  // per vertex, its two triangles (see triangleSide in rtin_grid.hpp)
  std::vector<float> m_leafError;      // per cell, its two half-cell triangles; empty at stride 1 (leafError)
};

}  // namespace polder::terrain
