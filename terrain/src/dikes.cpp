// Dikes (dikes.hpp): the gap network's topology, zipper strips between facing interior sides,
// and the junction polygons walked around the interiors, which dike_ear_clipping.cpp
// triangulates. Follows Chuang 2001 part B (dikes between blocks, re-triangulated per frame
// from the blocks' kept boundary vertices), generalised to quadtree cuts. The dikes' errors and
// their a-priori bound: dike_errors.cpp.
//
// Coordinates. Everything is in global full-resolution sample coordinates (integers), so all
// geometric predicates are exact (64-bit orientation tests).
//
// Clockwise boundaries. Each interior's kept boundary vertices are numbered clockwise from its
// north-west corner: north side west to east (positions 0 .. nN-1), east side north to south,
// south side east to west, west side south to north, ending at position `perimeter`, which is
// the north-west corner again. The gap lies on the left of this walk, so a junction polygon
// walked along interiors this way and across zippers comes out counter-clockwise.
//
// A zipper between members M1 and M2 covers the range [xs, xe] of each member's clockwise
// boundary; its polygon is M1.xs .. M1.xe, M2.xs .. M2.xe (counter-clockwise), so the junction
// on the far side of its closing edges walks M1.xs -> M2.xe and M2.xs -> M1.xe: at a zipper's
// start the walk "jumps" to the other member's end. A zipper may have a single vertex on one
// side (a fan) or on both (a bare cut, no triangle): the jumps still close the junctions.
//
// The DEM border. Junctions never reach the DEM's south or west border: there the gap is a
// column's bottom or a row's west end, which is exactly the closing edge of the zipper of two
// nodes whose footprints start together (both have a corner there) or of a border zipper.
// Such closing edges lie on the border, where no junction is (the terrain's edge is open).
// At the east and north border the gap touches the border in runs ([y1, fy1] of an east-edge
// node's column, [x1, fx1] of a north-edge node's row); the walk follows those runs through
// every full-resolution sample.
#include <polder/terrain/dikes.hpp>

#include <algorithm>
#include <cassert>
#include <limits>
#include <string>

#include "dike_ear_clipping.hpp"

namespace polder::terrain {
namespace {

constexpr std::uint32_t kNone = 0xffffffffu;
constexpr std::uint32_t kSouth = std::uint32_t(BlockEdge::South);
constexpr std::uint32_t kEast = std::uint32_t(BlockEdge::East);
constexpr std::uint32_t kNorth = std::uint32_t(BlockEdge::North);
constexpr std::uint32_t kWest = std::uint32_t(BlockEdge::West);

// Clockwise rank of each side (BlockEdge order), starting at the north-west corner.
constexpr std::uint32_t kClockwiseRank[4] = {2, 1, 0, 3};

std::string nodeName(const NodeId& node) {
  return "(level " + std::to_string(int(node.level)) + ", " + std::to_string(node.bx) + ", " + std::to_string(node.by) +
         ")";
}

}  // namespace

std::size_t dikeVertexBound(const BlockLayout& layout, std::size_t maxNodes) {
  // At most 2^k kept vertices per side and node (corners shared), plus border samples.
  return maxNodes * 4 * std::size_t(layout.cells()) + std::size_t(layout.width()) + std::size_t(layout.height());
}

std::size_t dikeTriangleBound(const BlockLayout& layout, std::size_t maxNodes) {
  // A triangulation of a polygon with h holes and V boundary vertices has V + 2h - 2 triangles.
  return dikeVertexBound(layout, maxNodes) + 2 * maxNodes;
}

void DikeScratch::reserve(const BlockLayout& layout, std::size_t maxNodes) {
  const std::size_t vertices = dikeVertexBound(layout, maxNodes);
  // Zippers join footprints sharing a side: a planar graph, fewer than 3 per node, plus the
  // border zippers (2 per node at most).
  const std::size_t attachments = 12 * maxNodes + 16;
  m_nodes.reserve(maxNodes);
  const std::size_t cells = std::size_t(layout.nodesX(0)) * std::size_t(layout.nodesY(0));
  if (m_cells.size() < cells) m_cells.resize(cells);
  m_attachments.reserve(attachments);
  m_order.reserve(attachments);
  m_visited.reserve(attachments);
  m_vertexOwner.reserve(vertices);
  if (m_eastBorder.size() < std::size_t(layout.height())) m_eastBorder.resize(std::size_t(layout.height()));
  if (m_northBorder.size() < std::size_t(layout.width())) m_northBorder.resize(std::size_t(layout.width()));
  // A zipper's sides: two node sides, or a node side and up to a border's length of samples.
  m_chains.reserve(2 * std::size_t(layout.cells()) + 2 + std::size_t(std::max(layout.width(), layout.height())));
  m_polygon.reserve(vertices);
  m_ears.reserve(vertices);
}

std::size_t DikeScratch::capacityBytes() const {
  return m_nodes.capacity() * sizeof(Node) + m_cells.capacity() * sizeof(Cell) +
         m_attachments.capacity() * sizeof(Attachment) + m_order.capacity() * sizeof(std::uint32_t) +
         m_visited.capacity() + m_vertexOwner.capacity() * sizeof(std::uint32_t) +
         (m_eastBorder.capacity() + m_northBorder.capacity()) * sizeof(BorderSample) +
         m_chains.capacity() * sizeof(ChainPoint) + m_polygon.capacity() * sizeof(std::uint32_t) +
         m_ears.capacity() * sizeof(Ear);
}

// One frame's construction (friend of DikeScratch).
struct DikeBuilder {
  using Node = DikeScratch::Node;
  using Attachment = DikeScratch::Attachment;

  const BlockLayout& layout;
  std::span<const DikeBlock> blocks;
  DikeMesh& out;
  DikeScratch& s;
  int width = 0, height = 0, pitch = 0, cells = 0, blocksX = 0, blocksY = 0;
  std::uint32_t stamp = 0;

  DikeBuilder(const BlockLayout& l, std::span<const DikeBlock> b, DikeMesh& o, DikeScratch& scratch)
      : layout(l), blocks(b), out(o), s(scratch) {
    width = layout.width();
    height = layout.height();
    pitch = layout.pitch();
    cells = layout.cells();
    blocksX = layout.nodesX(0);
    blocksY = layout.nodesY(0);
  }

  static Error invalid(std::string message) { return makeError(ErrorKind::InvalidArgument, "buildDikes: " + message); }
  // A broken invariant of this file (never the caller's input): asserts in debug builds and
  // still fails cleanly, without a half-built mesh, in release builds.
  static Error internal(const char* message) {
    assert(!"buildDikes: internal inconsistency" && message);
    return makeError(ErrorKind::InvalidData, std::string("buildDikes: internal inconsistency: ") + message);
  }

  // ---- nodes -------------------------------------------------------------------------------

  // Position offsets of a node's sides on its clockwise boundary.
  static std::uint32_t eastStart(const Node& n) { return n.sideCount[kNorth] - 1; }
  static std::uint32_t southStart(const Node& n) { return n.sideCount[kNorth] + n.sideCount[kEast] - 2; }
  static std::uint32_t westStart(const Node& n) {
    return n.sideCount[kNorth] + n.sideCount[kEast] + n.sideCount[kSouth] - 3;
  }

  // Clockwise position of chain index c of a side (chains sorted west to east / south to north).
  static std::uint32_t position(const Node& n, std::uint32_t side, std::uint32_t c) {
    switch (side) {
      case kNorth:
        return c;
      case kEast:
        return eastStart(n) + (n.sideCount[kEast] - 1 - c);
      case kSouth:
        return southStart(n) + (n.sideCount[kSouth] - 1 - c);
      default:
        return westStart(n) + c;
    }
  }

  // Output vertex of chain index c of a side: chains map to runs of clockwise positions.
  static std::uint32_t chainVertex(const Node& n, std::uint32_t side, std::uint32_t c) {
    switch (side) {
      case kNorth:
        return n.vertexBase + c;
      case kEast:
        return n.vertexBase + eastStart(n) + (n.sideCount[kEast] - 1 - c);
      case kSouth:
        return n.vertexBase + southStart(n) + (n.sideCount[kSouth] - 1 - c);
      default:
        return c + 1 == n.sideCount[kWest] ? n.vertexBase : n.vertexBase + westStart(n) + c;
    }
  }

  std::uint32_t vertexAt(const Node& n, std::uint32_t p) const { return n.vertexBase + (p == n.perimeter ? 0u : p); }
  const DikeVertex& point(std::uint32_t vertex) const { return out.vertices[vertex]; }

  // Coordinate along a side (x for north/south, y for east/west) of chain index c.
  int along(const Node& n, std::uint32_t side, std::uint32_t c) const {
    const DikeVertex& v = point(chainVertex(n, side, c));
    return (side == kNorth || side == kSouth) ? v.x : v.y;
  }

  bool sideDead(const Node& n, std::uint32_t side) const {
    switch (side) {
      case kNorth:
        return n.y1 == height - 1;
      case kEast:
        return n.x1 == width - 1;
      case kSouth:
        return n.y0 == 0;
      default:
        return n.x0 == 0;
    }
  }

  Status setupNodes() {
    s.m_nodes.clear();
    s.m_vertexOwner.clear();
    const int n = cells;
    std::size_t vertexTotal = 0;
    for (std::size_t b = 0; b < blocks.size(); ++b) {
      const NodeId id = blocks[b].node;
      if (!layout.exists(id)) return invalid("node " + nodeName(id) + " is not in the layout");
      const int stride = layout.stride(id);
      const SampleRect fp = layout.footprint(id);
      const int cellsX = std::min(n, (width - 1 - fp.x0) / stride), cellsY = std::min(n, (height - 1 - fp.y0) / stride);
      if (cellsX < 1 || cellsY < 1)
        return invalid("node " + nodeName(id) + " has no whole cell inside the DEM at its stride (refine it)");
      Node node;
      node.mesh = blocks[b].mesh;
      node.level = id.level;
      node.x0 = fp.x0;
      node.y0 = fp.y0;
      node.x1 = fp.x0 + cellsX * stride;
      node.y1 = fp.y0 + cellsY * stride;
      node.fx1 = fp.x1;
      node.fy1 = fp.y1;
      if (const BlockMesh* mesh = node.mesh) {
        const BlockFootprint expected = layout.interior(id);
        if (mesh->footprint.x0 != expected.x0 || mesh->footprint.y0 != expected.y0 || mesh->footprint.k != expected.k ||
            mesh->footprint.stride != expected.stride || mesh->cellsX != cellsX || mesh->cellsY != cellsY)
          return invalid("the mesh of node " + nodeName(id) + " is not for its interior");
        for (std::uint32_t side = 0; side < 4; ++side) {
          // The lists are checked while they are copied out (setupVertices): one pass over
          // the mesh's scattered vertices instead of two.
          if (mesh->edges[side].size() < 2)
            return invalid("the mesh of node " + nodeName(id) + " has fewer than two vertices on a side");
          node.sideCount[side] = std::uint32_t(mesh->edges[side].size());
        }
        const auto& e = mesh->edges;
        if (e[kNorth].front() != e[kWest].back() || e[kNorth].back() != e[kEast].back() ||
            e[kSouth].back() != e[kEast].front() || e[kSouth].front() != e[kWest].front())
          return invalid("the mesh of node " + nodeName(id) + " does not share its corners between sides");
      } else {
        for (std::uint32_t side = 0; side < 4; ++side) node.sideCount[side] = 2;
      }
      node.perimeter = node.sideCount[0] + node.sideCount[1] + node.sideCount[2] + node.sideCount[3] - 4;
      node.vertexBase = std::uint32_t(vertexTotal);
      node.eastBorderAttachment = kNone;
      node.northBorderAttachment = kNone;
      vertexTotal += node.perimeter;
      s.m_nodes.push_back(node);
    }
    if (vertexTotal + std::size_t(width) + std::size_t(height) >= std::size_t(kNone))
      return invalid("too many vertices");

    return setupVertices(vertexTotal);
  }

  // The clockwise boundaries become the first output vertices, then are checked in one
  // sequential pass: corners in place, each side on its line and strictly monotone.
  Status setupVertices(std::size_t vertexTotal) {
    out.vertices.resize(vertexTotal);
    s.m_vertexOwner.resize(vertexTotal);
    for (std::uint32_t b = 0; b < s.m_nodes.size(); ++b) {
      const Node& node = s.m_nodes[b];
      DikeVertex* const first = out.vertices.data() + node.vertexBase;
      std::fill(s.m_vertexOwner.begin() + node.vertexBase, s.m_vertexOwner.begin() + node.vertexBase + node.perimeter,
                b);
      const BlockMesh* mesh = node.mesh;
      if (!mesh) {
        first[0] = DikeVertex{node.x0, node.y1};
        first[1] = DikeVertex{node.x1, node.y1};
        first[2] = DikeVertex{node.x1, node.y0};
        first[3] = DikeVertex{node.x0, node.y0};
        continue;
      }
      const int stride = layout.stride(blocks[b].node);
      const GridVertex* mv = mesh->vertices.data();
      const std::size_t vertexCount = mesh->vertices.size();
      DikeVertex* v = first;
      bool inRange = true;
      auto copy = [&](const std::vector<std::uint32_t>& list, std::size_t index) {
        const std::uint32_t m = list[index];
        if (m >= vertexCount) {
          inRange = false;
          return;
        }
        *v++ = DikeVertex{node.x0 + int(mv[m].i) * stride, node.y0 + int(mv[m].j) * stride};
      };
      const auto& e = mesh->edges;
      for (std::size_t t = 0; t < e[kNorth].size() && inRange; ++t) copy(e[kNorth], t);
      for (std::size_t t = e[kEast].size() - 1; t-- > 1 && inRange;) copy(e[kEast], t);
      if (inRange) copy(e[kSouth], e[kSouth].size() - 1);  // the south-east corner
      for (std::size_t t = e[kSouth].size() - 1; t-- > 1 && inRange;) copy(e[kSouth], t);
      if (inRange) copy(e[kWest], 0);  // the south-west corner
      for (std::size_t t = 1; t + 1 < e[kWest].size() && inRange;) copy(e[kWest], t++);
      if (!inRange || !boundaryValid(node, first))
        return invalid("the mesh of node " + nodeName(blocks[b].node) + " has invalid side lists (edges)");
    }
    return {};
  }

  // The emitted clockwise boundary: corners at their places, every side on its line and
  // strictly monotone (so each side list was sorted and held only that side's vertices).
  bool boundaryValid(const Node& n, const DikeVertex* v) const {
    const std::uint32_t ne = eastStart(n), se = southStart(n), sw = westStart(n), p = n.perimeter;
    if (!(v[0] == DikeVertex{n.x0, n.y1}) || !(v[ne] == DikeVertex{n.x1, n.y1}) || !(v[se] == DikeVertex{n.x1, n.y0}) ||
        !(v[sw] == DikeVertex{n.x0, n.y0}))
      return false;
    for (std::uint32_t t = 1; t <= ne; ++t)
      if (v[t].y != n.y1 || v[t].x <= v[t - 1].x) return false;
    for (std::uint32_t t = ne + 1; t <= se; ++t)
      if (v[t].x != n.x1 || v[t].y >= v[t - 1].y) return false;
    for (std::uint32_t t = se + 1; t <= sw; ++t)
      if (v[t].y != n.y0 || v[t].x >= v[t - 1].x) return false;
    for (std::uint32_t t = sw + 1; t <= p; ++t) {
      const DikeVertex& here = t == p ? v[0] : v[t];
      if (here.x != n.x0 || here.y <= v[t - 1].y) return false;
    }
    return true;
  }

  // ---- the cut's level-0 lookup grid --------------------------------------------------------

  DikeScratch::Cell& cell(int bx, int by) {
    return s.m_cells[std::size_t(by) * std::size_t(blocksX) + std::size_t(bx)];
  }
  std::uint32_t nodeAt(int bx, int by) { return cell(bx, by).node; }

  Status fillGrid() {
    std::size_t covered = 0;
    for (std::uint32_t b = 0; b < blocks.size(); ++b) {
      const NodeId id = blocks[b].node;
      const int span = 1 << id.level;
      const int bx0 = int(id.bx) * span, by0 = int(id.by) * span;
      const int bx1 = std::min(bx0 + span, blocksX), by1 = std::min(by0 + span, blocksY);
      for (int by = by0; by < by1; ++by) {
        for (int bx = bx0; bx < bx1; ++bx) {
          DikeScratch::Cell& c = cell(bx, by);
          if (c.stamp == stamp)
            return invalid("nodes " + nodeName(blocks[c.node].node) + " and " + nodeName(id) + " overlap");
          c.stamp = stamp;
          c.node = b;
        }
      }
      covered += std::size_t(bx1 - bx0) * std::size_t(by1 - by0);
    }
    if (covered != std::size_t(blocksX) * std::size_t(blocksY))
      return invalid("the nodes do not cover the DEM (not a quadtree cut)");
    return {};
  }

  // The node whose footprint holds the east border's samples just above y (y < height - 1).
  std::uint32_t nodeAtEast(int y) { return nodeAt(blocksX - 1, y / pitch); }
  // The node whose footprint holds the north border's samples just west of x (x > 0).
  std::uint32_t nodeAtNorth(int x) { return nodeAt((x - 1) / pitch, blocksY - 1); }

  // ---- border samples ------------------------------------------------------------------------

  std::uint32_t borderVertex(int x, int y, std::uint32_t owner) {
    DikeScratch::BorderSample& slot = x == width - 1 ? s.m_eastBorder[std::size_t(y)] : s.m_northBorder[std::size_t(x)];
    if (slot.stamp != stamp) {
      slot.stamp = stamp;
      slot.vertex = std::uint32_t(out.vertices.size());
      out.vertices.push_back(DikeVertex{x, y});
      s.m_vertexOwner.push_back(owner);
    }
    return slot.vertex;
  }

  // ---- zippers -------------------------------------------------------------------------------

  // Room for `count` more triangles; triangle() then writes without checks.
  std::uint32_t* nextIndex = nullptr;
  std::uint32_t* nextOwner = nullptr;
  void openTriangles(std::size_t count) {
    const std::size_t t = out.owners.size();
    out.indices.resize(3 * (t + count));
    out.owners.resize(t + count);
    nextIndex = out.indices.data() + 3 * t;
    nextOwner = out.owners.data() + t;
  }
  void triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t owner) {
    nextIndex[0] = a;
    nextIndex[1] = b;
    nextIndex[2] = c;
    nextIndex += 3;
    *nextOwner++ = owner;
  }

  std::uint32_t coarser(std::uint32_t a, std::uint32_t b) const {
    return s.m_nodes[b].level > s.m_nodes[a].level ? b : a;
  }

  // Merges two parallel chains into a strip, always spanning the next vertex of the side
  // whose next vertex comes first along the chains (so triangles stay short). `vertical`: u is
  // the west chain and v the east one; otherwise u is the south chain and v the north one.
  // Either way both kinds of step give the triangle (u_i, v_j, next) counter-clockwise in one
  // vertex order (vertical) or the other.
  void zip(const DikeScratch::ChainPoint* u, std::uint32_t uCount, const DikeScratch::ChainPoint* v,
           std::uint32_t vCount, bool vertical, std::uint32_t owner) {
    openTriangles(uCount + vCount - 2);
    const std::uint32_t uLast = uCount - 1, vLast = vCount - 1;
    std::uint32_t i = 0, j = 0;
    while (i < uLast || j < vLast) {
      const bool advanceU = j == vLast || (i < uLast && u[i + 1].along <= v[j + 1].along);
      const std::uint32_t a = u[i].vertex, b = v[j].vertex, c = advanceU ? u[i + 1].vertex : v[j + 1].vertex;
      if (vertical)
        triangle(a, b, c, owner);
      else
        triangle(a, c, b, owner);
      i += advanceU ? 1 : 0;
      j += advanceU ? 0 : 1;
    }
  }

  // Copies chain indices [a, b] of a side into `chain`: the output vertices of a side run
  // through consecutive clockwise positions, up or down (the west side's last vertex, the
  // north-west corner, is position 0).
  void copyChain(const Node& n, std::uint32_t side, std::uint32_t a, std::uint32_t b,
                 DikeScratch::ChainPoint* chain) const {
    const std::uint32_t first = chainVertex(n, side, a);
    const std::int32_t step = (side == kNorth || side == kWest) ? 1 : -1;
    const bool alongX = side == kNorth || side == kSouth;
    const DikeVertex* points = out.vertices.data();
    for (std::uint32_t t = 0; t <= b - a; ++t) {
      std::uint32_t vertex = std::uint32_t(std::int32_t(first) + step * std::int32_t(t));
      if (side == kWest && a + t + 1 == n.sideCount[kWest]) vertex = n.vertexBase;
      chain[t] = DikeScratch::ChainPoint{vertex, alongX ? points[vertex].x : points[vertex].y};
    }
  }

  // Chain indices [first, last] of a side whose coordinates lie in [lo, hi]; first > last when none.
  void range(const Node& n, std::uint32_t side, int lo, int hi, std::uint32_t& first, std::uint32_t& last) const {
    const std::uint32_t count = n.sideCount[side];
    if (along(n, side, 0) >= lo && along(n, side, count - 1) <= hi) {  // the whole side: footprints aligned
      first = 0;
      last = count - 1;
      return;
    }
    auto bound = [&](int value, bool strict) {  // first index with coordinate >= value (> when strict)
      std::uint32_t a = 0, b = n.sideCount[side];
      while (a < b) {
        const std::uint32_t m = (a + b) / 2;
        const int c = along(n, side, m);
        if (strict ? c <= value : c < value)
          a = m + 1;
        else
          b = m;
      }
      return a;
    };
    const std::uint32_t begin = bound(lo, false), end = bound(hi, true);
    if (end <= begin) {
      first = 1;
      last = 0;
    } else {
      first = begin;
      last = end - 1;
    }
  }

  std::uint32_t attach(std::uint32_t node, std::uint32_t side, std::uint32_t xs, std::uint32_t xe) {
    Attachment a;
    a.node = node;
    a.side = side;
    a.xs = xs;
    a.xe = xe;
    a.twin = kNone;
    s.m_attachments.push_back(a);
    return std::uint32_t(s.m_attachments.size() - 1);
  }

  // Zipper between u's east side and v's west side (vertical) or u's north side and v's
  // south side.
  void zipNodes(std::uint32_t ui, std::uint32_t vi, bool vertical) {
    const Node& u = s.m_nodes[ui];
    const Node& v = s.m_nodes[vi];
    const int lo = vertical ? std::max(u.y0, v.y0) : std::max(u.x0, v.x0);
    const int hi = vertical ? std::min(u.y1, v.y1) : std::min(u.x1, v.x1);
    if (lo >= hi) return;
    const std::uint32_t uSide = vertical ? kEast : kNorth, vSide = vertical ? kWest : kSouth;
    std::uint32_t ua, ub, va, vb;
    range(u, uSide, lo, hi, ua, ub);
    range(v, vSide, lo, hi, va, vb);
    if (ua > ub || va > vb) return;  // one side has no vertex here: the junction takes it
    const std::uint32_t uCount = ub - ua + 1, vCount = vb - va + 1;
    s.m_chains.resize(uCount + vCount);
    copyChain(u, uSide, ua, ub, s.m_chains.data());
    copyChain(v, vSide, va, vb, s.m_chains.data() + uCount);
    zip(s.m_chains.data(), uCount, s.m_chains.data() + uCount, vCount, vertical, coarser(ui, vi));
    // Clockwise, u runs north to south on its east side (west to east on its north side)
    // and v south to north on its west side (east to west on its south side).
    const std::uint32_t a = vertical ? attach(ui, uSide, position(u, uSide, ub), position(u, uSide, ua))
                                     : attach(ui, uSide, position(u, uSide, ua), position(u, uSide, ub));
    const std::uint32_t b = vertical ? attach(vi, vSide, position(v, vSide, va), position(v, vSide, vb))
                                     : attach(vi, vSide, position(v, vSide, vb), position(v, vSide, va));
    s.m_attachments[a].twin = b;
    s.m_attachments[b].twin = a;
  }

  // Zipper between u's east side and the DEM's east border (vertical) or u's north side and
  // the north border, through the border samples at u's stride (its side's own spacing: a
  // coarse node far away needs no more; where that is too coarse, the engine's dike check
  // splits the node).
  void zipBorder(std::uint32_t ui, bool vertical) {
    const Node& u = s.m_nodes[ui];
    const std::uint32_t side = vertical ? kEast : kNorth;
    const std::uint32_t count = u.sideCount[side];
    const int lo = vertical ? u.y0 : u.x0, hi = vertical ? u.y1 : u.x1;
    const int stride = 1 << u.level;  // hi - lo is a whole number of strides (the interior's side)
    const std::uint32_t samples = std::uint32_t((hi - lo) / stride + 1);
    s.m_chains.resize(count + samples);
    DikeScratch::ChainPoint* border = s.m_chains.data() + count;
    for (std::uint32_t t = 0; t < samples; ++t) {  // numbered once here, not per triangle
      const int along = lo + int(t) * stride;
      border[t] = DikeScratch::ChainPoint{
          vertical ? borderVertex(width - 1, along, ui) : borderVertex(along, height - 1, ui), along};
    }
    copyChain(u, side, 0, count - 1, s.m_chains.data());
    zip(s.m_chains.data(), count, border, samples, vertical, ui);
    // The border walks counter-clockwise around the DEM: north on the east border, west on
    // the north border.
    const std::uint32_t xsBorder = vertical ? border[0].vertex : border[samples - 1].vertex;
    const std::uint32_t xeBorder = vertical ? border[samples - 1].vertex : border[0].vertex;
    const std::uint32_t a = vertical ? attach(ui, side, position(u, side, count - 1), position(u, side, 0))
                                     : attach(ui, side, position(u, side, 0), position(u, side, count - 1));
    Attachment& at = s.m_attachments[a];
    at.borderXs = xsBorder;
    at.borderXe = xeBorder;
    at.borderCoordinate = vertical ? hi : lo;
    if (vertical)
      s.m_nodes[ui].eastBorderAttachment = a;
    else
      s.m_nodes[ui].northBorderAttachment = a;
  }

  void buildZippers() {
    s.m_attachments.clear();
    for (std::uint32_t ui = 0; ui < s.m_nodes.size(); ++ui) {
      const NodeId id = blocks[ui].node;
      const int span = 1 << id.level;
      const Node& u = s.m_nodes[ui];
      // East: the nodes whose footprints start where u's ends, south to north.
      if (u.fx1 < width - 1) {
        const int column = (int(id.bx) + 1) * span;
        const int rowEnd = std::min((int(id.by) + 1) * span, blocksY);
        for (int row = int(id.by) * span; row < rowEnd;) {
          const std::uint32_t vi = nodeAt(column, row);
          zipNodes(ui, vi, true);
          const NodeId v = blocks[vi].node;
          row = std::max(row + 1, (int(v.by) + 1) << v.level);
        }
      } else if (u.x1 < width - 1) {
        zipBorder(ui, true);
      }
      if (s.m_nodes[ui].fy1 < height - 1) {
        const int row = (int(id.by) + 1) * span;
        const int columnEnd = std::min((int(id.bx) + 1) * span, blocksX);
        for (int column = int(id.bx) * span; column < columnEnd;) {
          const std::uint32_t vi = nodeAt(column, row);
          zipNodes(ui, vi, false);
          const NodeId v = blocks[vi].node;
          column = std::max(column + 1, (int(v.bx) + 1) << v.level);
        }
      } else if (s.m_nodes[ui].y1 < height - 1) {
        zipBorder(ui, false);
      }
    }
  }

  // Each node's attachments in clockwise order (by start position, then side).
  void orderAttachments() {
    for (Node& n : s.m_nodes) n.attachmentBegin = n.attachmentEnd = 0;
    for (const Attachment& a : s.m_attachments) ++s.m_nodes[a.node].attachmentEnd;
    std::uint32_t offset = 0;
    for (Node& n : s.m_nodes) {
      const std::uint32_t count = n.attachmentEnd;
      n.attachmentBegin = n.attachmentEnd = offset;
      offset += count;
    }
    s.m_order.resize(s.m_attachments.size());
    for (std::uint32_t a = 0; a < s.m_attachments.size(); ++a) {
      Node& n = s.m_nodes[s.m_attachments[a].node];
      s.m_order[n.attachmentEnd++] = a;
    }
    auto key = [&](std::uint32_t a) {
      const Attachment& at = s.m_attachments[a];
      return std::uint64_t(at.xs) * 4 + kClockwiseRank[at.side];
    };
    for (Node& n : s.m_nodes) {
      std::uint32_t* list = s.m_order.data() + n.attachmentBegin;
      const std::uint32_t count = n.attachmentEnd - n.attachmentBegin;
      for (std::uint32_t i = 1; i < count; ++i) {  // a handful per node: insertion sort
        const std::uint32_t a = list[i];
        const std::uint64_t ka = key(a);
        std::uint32_t j = i;
        while (j > 0 && key(list[j - 1]) > ka) {
          list[j] = list[j - 1];
          --j;
        }
        list[j] = a;
      }
      for (std::uint32_t i = 0; i < count; ++i) s.m_attachments[list[i]].rank = i;
    }
    s.m_visited.assign(s.m_attachments.size(), 0);
  }

  // ---- junctions -----------------------------------------------------------------------------

  bool onBorder(std::uint32_t a, std::uint32_t b) const {
    const DikeVertex& p = point(a);
    const DikeVertex& q = point(b);
    return (p.x == q.x && (p.x == 0 || p.x == width - 1)) || (p.y == q.y && (p.y == 0 || p.y == height - 1));
  }

  // Where a closing edge into an attachment starts: the other member's xs.
  std::uint32_t jumpSource(const Attachment& a) const {
    if (a.twin == kNone) return a.borderXs;
    const Attachment& t = s.m_attachments[a.twin];
    return vertexAt(s.m_nodes[t.node], t.xs);
  }

  std::uint32_t firstRankFrom(const Node& n, std::uint32_t p) const {
    for (std::uint32_t r = n.attachmentBegin; r < n.attachmentEnd; ++r)
      if (s.m_attachments[s.m_order[r]].xs >= p) return r - n.attachmentBegin;
    return n.attachmentEnd - n.attachmentBegin;
  }

  // Walk state: on node `node` at clockwise position p (its vertex already in the polygon),
  // q = rank of the next attachment to meet.
  struct Walk {
    std::uint32_t start = 0;  // the attachment the junction was entered through
    std::uint32_t node = 0, p = 0, q = 0;
    bool closed = false;
  };

  // Enters node a.node at a.xe across a's closing edge (from the polygon's last vertex).
  Status land(Walk& w, std::uint32_t a) {
    const Attachment& at = s.m_attachments[a];
    const std::uint32_t target = vertexAt(s.m_nodes[at.node], at.xe);
    if (onBorder(s.m_polygon.back(), target)) return internal("a junction crossed the DEM border");
    if (a == w.start) {
      w.closed = true;
      return {};
    }
    if (s.m_visited[a]) return internal("a junction walk met another junction");
    s.m_visited[a] = 1;
    s.m_polygon.push_back(target);
    w.node = at.node;
    w.p = at.xe;
    w.q = at.rank + 1;
    return {};
  }

  void enterAtCorner(Walk& w, std::uint32_t node, std::uint32_t p) {
    w.node = node;
    w.p = p;
    w.q = firstRankFrom(s.m_nodes[node], p);
  }

  // Follows the north border westward from (x, height-1), already in the polygon.
  Status walkNorth(Walk& w, int x) {
    if (x <= 0) return internal("a junction reached the DEM's north-west corner");
    const std::uint32_t ai = nodeAtNorth(x);
    const Node& a = s.m_nodes[ai];
    if (x != a.fx1) return internal("a junction left the north border off a footprint edge");
    for (int xx = x - 1; xx > a.x1; --xx) s.m_polygon.push_back(borderVertex(xx, height - 1, ai));
    const std::uint32_t northEast = eastStart(a);
    if (a.y1 < height - 1) {
      if (a.x1 < x) s.m_polygon.push_back(borderVertex(a.x1, height - 1, ai));
      if (a.northBorderAttachment == kNone) return internal("missing north border zipper");
      return land(w, a.northBorderAttachment);
    }
    if (a.x1 == x) return internal("a junction reached a block corner on the north border twice");
    s.m_polygon.push_back(vertexAt(a, northEast));
    enterAtCorner(w, ai, northEast);
    return {};
  }

  // Follows the east border northward from (width-1, y), already in the polygon.
  Status walkEast(Walk& w, int y) {
    for (int guard = 0; guard <= blocksY + 1; ++guard) {
      if (y == height - 1) return walkNorth(w, width - 1);
      const std::uint32_t ai = nodeAtEast(y);
      const Node& a = s.m_nodes[ai];
      if (y == a.y0) {  // the start of a's footprint
        if (a.x1 < width - 1) {
          if (a.eastBorderAttachment == kNone) return internal("missing east border zipper");
          return land(w, a.eastBorderAttachment);
        }
        enterAtCorner(w, ai, southStart(a));  // (width-1, y) is a's south-east corner
        return {};
      }
      if (y != a.y1 || a.fy1 == y) return internal("a junction left the east border off a run");
      for (int yy = y + 1; yy < a.fy1; ++yy) s.m_polygon.push_back(borderVertex(width - 1, yy, ai));
      const int next = a.fy1;
      if (next == height - 1) {
        s.m_polygon.push_back(borderVertex(width - 1, next, ai));
      } else {
        const std::uint32_t ti = nodeAtEast(next);
        const Node& t = s.m_nodes[ti];
        s.m_polygon.push_back(t.x1 == width - 1 ? vertexAt(t, southStart(t)) : borderVertex(width - 1, next, ti));
      }
      y = next;
    }
    return internal("the east border walk did not end");
  }

  std::uint32_t sideOfEdge(const Node& n, std::uint32_t p) const {  // edge p -> p+1
    if (p < eastStart(n)) return kNorth;
    if (p < southStart(n)) return kEast;
    if (p < westStart(n)) return kSouth;
    return kWest;
  }

  Status walkJunction(std::uint32_t start) {
    s.m_polygon.clear();
    const Attachment& first = s.m_attachments[start];
    Walk w;
    w.start = start;
    w.node = first.node;
    w.p = first.xe;
    w.q = first.rank + 1;
    s.m_visited[start] = 1;
    s.m_polygon.push_back(vertexAt(s.m_nodes[w.node], w.p));
    const std::size_t limit = out.vertices.size() + std::size_t(width) + std::size_t(height) + 16;
    for (std::size_t steps = 0; !w.closed; ++steps) {
      if (steps > 4 * limit) return internal("a junction walk did not close");
      const Node& n = s.m_nodes[w.node];
      const std::uint32_t count = n.attachmentEnd - n.attachmentBegin;
      if (w.q < count) {
        const std::uint32_t ai = s.m_order[n.attachmentBegin + w.q];
        const Attachment& a = s.m_attachments[ai];
        if (a.xs == w.p) {  // a zipper starts here: cross its closing edge
          if (a.twin != kNone) {
            if (Status st = land(w, a.twin); !st) return st;
            continue;
          }
          if (onBorder(s.m_polygon.back(), a.borderXe)) return internal("a junction crossed the DEM border");
          s.m_polygon.push_back(a.borderXe);
          const Status st = a.side == kEast ? walkEast(w, a.borderCoordinate) : walkNorth(w, a.borderCoordinate);
          if (!st) return st;
          continue;
        }
      }
      if (w.p == n.perimeter) {  // the north-west corner again
        w.p = 0;
        w.q = 0;
        continue;
      }
      const std::uint32_t side = sideOfEdge(n, w.p);
      if (sideDead(n, side)) {
        Status st;
        if (side == kNorth && w.p == 0)
          st = walkNorth(w, n.x0);
        else if (side == kEast && w.p == eastStart(n))
          st = walkEast(w, n.y1);
        else
          st = internal("a junction reached the DEM's south or west border");
        if (!st) return st;
        continue;
      }
      ++w.p;
      s.m_polygon.push_back(vertexAt(n, w.p));
    }
    return triangulateJunction();
  }

  Status walkJunctions() {
    for (std::uint32_t a = 0; a < s.m_attachments.size(); ++a) {
      if (s.m_visited[a]) continue;
      const Attachment& at = s.m_attachments[a];
      // A closing edge on the DEM border has the outside beyond it, not a junction.
      if (onBorder(jumpSource(at), vertexAt(s.m_nodes[at.node], at.xe))) continue;
      if (Status st = walkJunction(a); !st) return st;
    }
    return {};
  }

  // ---- junction triangles --------------------------------------------------------------------

  // Triangulates the walked polygon (counter-clockwise), shortest valid diagonal first
  // (dike_ear_clipping.hpp).
  Status triangulateJunction() {
    const std::uint32_t m = std::uint32_t(s.m_polygon.size());
    if (m < 3) return internal("a junction with fewer than three vertices");
    // Its triangles belong to the coarsest node around it: a junction along a coarse side with
    // no vertex in a finer neighbour's range exists because of that side's long edge, though
    // ear clipping may cut slivers from it that use only the finer nodes' vertices.
    std::uint32_t junctionOwner = s.m_vertexOwner[s.m_polygon[0]];
    for (std::uint32_t i = 1; i < m; ++i) junctionOwner = coarser(junctionOwner, s.m_vertexOwner[s.m_polygon[i]]);
    openTriangles(m - 2);
    if (const char* broken = detail::clipEars(s.m_polygon, out.vertices.data(), s.m_ears, nextIndex))
      return internal(broken);
    std::fill(nextOwner, nextOwner + (m - 2), junctionOwner);
    nextIndex += 3 * std::size_t(m - 2);
    nextOwner += m - 2;
    return {};
  }

  Status run() {
    out.clear();
    stamp = ++s.m_stamp;
    if (stamp == 0) {  // the stamps wrapped: forget every old one
      for (auto& c : s.m_cells) c.stamp = 0;
      for (auto& b : s.m_eastBorder) b.stamp = 0;
      for (auto& b : s.m_northBorder) b.stamp = 0;
      stamp = s.m_stamp = 1;
    }
    if (blocks.empty()) return invalid("no nodes");
    const std::size_t cellCount = std::size_t(blocksX) * std::size_t(blocksY);
    if (s.m_cells.size() < cellCount) s.m_cells.resize(cellCount);
    if (s.m_eastBorder.size() < std::size_t(height)) s.m_eastBorder.resize(std::size_t(height));
    if (s.m_northBorder.size() < std::size_t(width)) s.m_northBorder.resize(std::size_t(width));
    if (Status st = setupNodes(); !st) return st;
    if (Status st = fillGrid(); !st) return st;
    buildZippers();
    out.zipperTriangles = out.triangleCount();
    orderAttachments();
    return walkJunctions();
  }
};

Status buildDikes(const BlockLayout& layout, std::span<const DikeBlock> blocks, DikeMesh& out, DikeScratch& scratch) {
  DikeBuilder builder(layout, blocks, out, scratch);
  Status status = builder.run();
  if (!status) out.clear();
  return status;
}

int sidesBesideDikeTriangle(const BlockMesh& mesh, const SampleRect& triangle, SideRange out[2]) {
  const int s = mesh.footprint.stride;
  const int x0 = mesh.footprint.x0, y0 = mesh.footprint.y0;
  const int x1 = x0 + mesh.cellsX * s, y1 = y0 + mesh.cellsY * s;
  auto range = [s](BlockEdge side, int lo, int hi, int origin, int cells) {
    return SideRange{side, std::clamp((lo - origin) / s, 0, cells), std::clamp((hi - origin + s - 1) / s, 0, cells)};
  };
  int count = 0;
  // The triangle lies in the gap network, outside every interior: beside a side it touches.
  if (triangle.x1 <= x0 || triangle.x0 >= x1)
    out[count++] = range(triangle.x1 <= x0 ? BlockEdge::West : BlockEdge::East, std::max(triangle.y0, y0),
                         std::min(triangle.y1, y1), y0, mesh.cellsY);
  if (triangle.y1 <= y0 || triangle.y0 >= y1)
    out[count++] = range(triangle.y1 <= y0 ? BlockEdge::South : BlockEdge::North, std::max(triangle.x0, x0),
                         std::min(triangle.x1, x1), x0, mesh.cellsX);
  return count;
}

}  // namespace polder::terrain
