// Extraction of a block's meshes from its error hierarchy (rtin.hpp): view-dependent, greedy
// to a triangle count, and to an error threshold, the view's and the threshold's refined by
// pinned side vertices where asked; and the scratch they share.
//
// Follows P. Lindstrom et al., "Real-time, continuous level of detail rendering of height
// fields" (SIGGRAPH 1996) for the vertex dependencies that keep a bintree mesh conforming;
// R. Pajarola, "Large scale terrain visualization using the restricted quadtree triangulation"
// (Visualization 1998): with monotone errors any rule "active iff error > threshold" conforms;
// M. Duchaineau et al., "ROAMing terrain" (Visualization 1997) for greedy refinement by a split
// queue; P. Lindstrom, V. Pascucci, "Visualization of large terrains made easy" (Visualization
// 2001) for the monotone view-dependent test on nested bounding spheres.
#include <polder/terrain/rtin.hpp>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <vector>

#include "rtin_grid.hpp"

namespace polder::terrain {
using namespace detail;
namespace {

constexpr std::uint32_t kNoVertex = 0xffffffffu;
constexpr std::uint8_t kSplitFlag = 0x80;

}  // namespace

// ---- scratch ----------------------------------------------------------------------------

void RtinScratch::reserve(int k) {
  assert(k >= 1 && k <= kRtinMaxK && "RtinScratch::reserve: k must be in 1..kRtinMaxK");
  prepare(blockMeshVertexBound(k));
}

void RtinScratch::prepare(std::size_t vertexCount) {
  if (m_remap.size() < vertexCount) m_remap.resize(vertexCount, kNoVertex);
  if (m_state.size() < vertexCount) m_state.resize(vertexCount, 0);
  if (m_queue.capacity() < vertexCount) m_queue.reserve(vertexCount);
}

// ---- extraction -------------------------------------------------------------------------

template <class Active>
void BlockLod::emit(Active& active, BlockMesh& out, RtinScratch& scratch) const {
  assert(!m_height.empty() && "BlockLod: extraction from a block that was never built");
  const int n = m_footprint.cells(), side = n + 1;
  out.clear();
  out.footprint = m_footprint;
  out.cellsX = m_cellsX;
  out.cellsY = m_cellsY;
  scratch.prepare(std::size_t(side) * std::size_t(side));
  std::uint32_t* remap = scratch.m_remap.data();

  auto vertex = [&](int i, int j) {
    std::uint32_t& slot = remap[std::size_t(j) * side + i];
    if (slot == kNoVertex) {
      slot = std::uint32_t(out.vertices.size());
      out.vertices.push_back(GridVertex{std::uint16_t(i), std::uint16_t(j)});
    }
    return slot;
  };
  float maxError = 0.0f;
  auto leaf = [&](int ax, int ay, int bx, int by, int cx, int cy, float err) {
    // Straddling triangles are always split, so a clipped block's leaves lie wholly inside
    // or wholly outside.
    if (m_clipped && !insideRect(Tri{ax, ay, bx, by, cx, cy}, m_cellsX, m_cellsY)) return;
    out.indices.push_back(vertex(ax, ay));
    out.indices.push_back(vertex(bx, by));
    out.indices.push_back(vertex(cx, cy));
    maxError = std::max(maxError, err);
  };
  walk(active, leaf);
  out.maxError = maxError;

  auto collect = [&](std::vector<std::uint32_t>& list, int i0, int j0, int di, int dj, int steps) {
    for (int t = 0; t <= steps; ++t) {
      const std::uint32_t slot = remap[std::size_t(j0 + t * dj) * side + (i0 + t * di)];
      if (slot != kNoVertex) list.push_back(slot);
    }
  };
  collect(out.edges[int(BlockEdge::South)], 0, 0, 1, 0, m_cellsX);
  collect(out.edges[int(BlockEdge::East)], m_cellsX, 0, 0, 1, m_cellsY);
  collect(out.edges[int(BlockEdge::North)], 0, m_cellsY, 1, 0, m_cellsX);
  collect(out.edges[int(BlockEdge::West)], 0, 0, 0, 1, m_cellsY);

  for (const GridVertex& v : out.vertices) remap[std::size_t(v.j) * side + v.i] = kNoVertex;
}

void BlockLod::extractThreshold(float maxError, BlockMesh& out, RtinScratch& scratch, const BoundaryPins* pins) const {
  assert(!std::isnan(maxError) && "BlockLod::extractThreshold: maxError is NaN");
  const int side = m_footprint.verticesPerSide();
  const bool pinned = pins && pins->any();
  if (pinned) markPinned(*pins, scratch);
  const std::uint8_t* marked = scratch.m_state.data();
  auto active = [&](int i, int j) {
    const std::size_t v = std::size_t(j) * side + i;
    const float e = m_error[v];
    return e > maxError || e == kForced || (pinned && marked[v] != 0);
  };
  emit(active, out, scratch);
}

void BlockLod::markPinned(const BoundaryPins& pins, RtinScratch& scratch) const {
  const int n = m_footprint.cells(), side = n + 1;
  const std::size_t vertexCount = std::size_t(side) * std::size_t(side);
  scratch.prepare(vertexCount);
  std::uint8_t* marked = scratch.m_state.data();
  std::fill(marked, marked + vertexCount, std::uint8_t(0));
  std::vector<std::uint32_t>& stack = scratch.m_queue;
  stack.clear();
  auto mark = [&](int i, int j) {
    const std::size_t v = std::size_t(j) * side + i;
    if (marked[v] != 0) return;
    marked[v] = 1;
    stack.push_back(std::uint32_t(v));
  };
  for (int p = 0; p <= n; ++p) {
    if (p <= m_cellsX && pins.pinned(BlockEdge::South, p)) mark(p, 0);
    if (p <= m_cellsX && pins.pinned(BlockEdge::North, p)) mark(p, m_cellsY);
    if (p <= m_cellsY && pins.pinned(BlockEdge::West, p)) mark(0, p);
    if (p <= m_cellsY && pins.pinned(BlockEdge::East, p)) mark(m_cellsX, p);
  }
  // A vertex is in a mesh only with both triangles it splits, i.e. with their parents split:
  // their parents' midpoints are these triangles' apexes.
  while (!stack.empty()) {
    const std::uint32_t v = stack.back();
    stack.pop_back();
    Tri tris[2];
    const int count = splitTriangles(int(v % side), int(v / side), n, tris);
    for (int t = 0; t < count; ++t) mark(tris[t].ax, tris[t].ay);
  }
}

void BlockLod::extractView(const LodView& view, BlockMesh& out, RtinScratch& scratch, const BoundaryPins* pins) const {
  assert(view.projectionConstant > 0.0 && "BlockLod::extractView: projectionConstant must be positive");
  assert(view.tolerancePx >= 0.0 && view.nearM >= 0.0 && "BlockLod::extractView: negative tolerance or near");
  const int side = m_footprint.verticesPerSide();
  const double k = view.projectionConstant, tau = view.tolerancePx;
  const bool pinned = pins && pins->any();
  if (pinned) markPinned(*pins, scratch);
  const std::uint8_t* marked = scratch.m_state.data();
  auto active = [&](int i, int j) {
    const std::size_t v = std::size_t(j) * side + i;
    const float e = m_error[v];
    if (e == kForced || (pinned && marked[v] != 0)) return true;
    if (!(e > 0.0f)) return false;  // a free vertex never pays for itself
    const double ex = i * m_vertexSpacingX - view.camera.x, ey = j * m_vertexSpacingY - view.camera.y;
    const double ez = double(m_height[v]) - view.camera.z;
    const double distance = std::sqrt(ex * ex + ey * ey + ez * ez);
    // error > tau * max(d - r, near) / K, without the division
    return double(e) * k > tau * std::max(distance - double(m_radius[v]), view.nearM);
  };
  emit(active, out, scratch);
}

void BlockLod::extractCount(std::size_t targetTriangles, BlockMesh& out, RtinScratch& scratch) const {
  assert(!m_height.empty() && "BlockLod::extractCount: block was never built");
  const int n = m_footprint.cells(), side = n + 1;
  const std::size_t vertexCount = std::size_t(side) * std::size_t(side);
  scratch.prepare(vertexCount);
  std::uint8_t* state = scratch.m_state.data();  // low bits: parents split so far
  std::fill(state, state + vertexCount, std::uint8_t(0));
  std::vector<std::uint32_t>& queue = scratch.m_queue;
  queue.clear();
  auto larger = [&](std::uint32_t a, std::uint32_t b) { return m_error[a] < m_error[b]; };
  auto inside = [&](int ax, int ay, int bx, int by, int cx, int cy) {
    return std::size_t(insideRect(Tri{ax, ay, bx, by, cx, cy}, m_cellsX, m_cellsY));
  };

  // Candidates are the vertices whose triangles all exist in the current mesh. Errors are
  // monotone, so the largest candidate is the largest unsplit vertex overall: ROAM's forced
  // splits of a hypotenuse neighbour have all been made by the time a vertex is taken.
  std::size_t count = inside(0, 0, n, 0, 0, n) + inside(n, n, 0, n, n, 0);
  queue.push_back(std::uint32_t((n / 2) * side + n / 2));  // its triangles are the roots
  while (!queue.empty()) {
    const std::uint32_t v = queue.front();
    const float e = m_error[v];
    if (!(e > 0.0f)) break;  // nothing left lowers the error
    const int i = int(v % side), j = int(v / side);
    Tri tris[2];
    const int trisCount = splitTriangles(i, j, n, tris);
    std::size_t added = 0, removed = 0;
    for (int t = 0; t < trisCount; ++t) {
      const Tri& r = tris[t];
      added += inside(i, j, r.ax, r.ay, r.bx, r.by) + inside(i, j, r.cx, r.cy, r.ax, r.ay);
      removed += inside(r.ax, r.ay, r.bx, r.by, r.cx, r.cy);
    }
    if (e != kForced && count + added - removed > targetTriangles) break;
    std::pop_heap(queue.begin(), queue.end(), larger);
    queue.pop_back();
    state[v] |= kSplitFlag;
    count = count + added - removed;
    for (int t = 0; t < trisCount; ++t) {
      const Tri& r = tris[t];
      const int legs[2][4] = {{r.ax, r.ay, r.bx, r.by}, {r.cx, r.cy, r.ax, r.ay}};
      for (const auto& leg : legs) {
        if (((leg[0] + leg[2]) & 1) != 0 || ((leg[1] + leg[3]) & 1) != 0) continue;
        const int ci = (leg[0] + leg[2]) / 2, cj = (leg[1] + leg[3]) / 2;
        const std::size_t c = std::size_t(cj) * side + ci;
        if (++state[c] == splitTriangleCount(ci, cj, n)) {
          queue.push_back(std::uint32_t(c));
          std::push_heap(queue.begin(), queue.end(), larger);
        }
      }
    }
  }
  auto active = [&](int ai, int aj) { return (state[std::size_t(aj) * side + ai] & kSplitFlag) != 0; };
  emit(active, out, scratch);
}

}  // namespace polder::terrain
