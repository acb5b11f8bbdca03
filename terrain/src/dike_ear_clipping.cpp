// Exact ear clipping of the dikes' junction polygons (dikes.hpp "How", step 2): the shortest
// valid diagonal first, zero-area ears rejected. The polygons come from the junction walk in
// dikes.cpp. The dikes follow J.-H. Chuang, "Level-of-Detail Modeling Technique for Virtual
// Reality (I)", 2001, part B (dikes.hpp): the gaps between blocks re-triangulated every frame
// from the boundary vertices the blocks kept.
//
// Coordinates are full-resolution samples (integers), so every predicate is an exact 64-bit
// orientation test.
#include "dike_ear_clipping.hpp"

#include <cassert>
#include <limits>

namespace polder::terrain::detail {
namespace {

constexpr std::uint32_t kNone = 0xffffffffu;

std::int64_t orient(std::int64_t ax, std::int64_t ay, std::int64_t bx, std::int64_t by, std::int64_t cx,
                    std::int64_t cy) {
  return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
}

// Orders diagonals by length; of two equally long ones, the one running north-west to
// south-east first, the direction heightfield.hpp cuts its cells: a junction of one cell
// (where full-detail sides meet at a corner) is then cut like the surface, error 0.
std::int64_t diagonalRank(std::int64_t dx, std::int64_t dy) { return 2 * (dx * dx + dy * dy) + (dx * dy > 0 ? 1 : 0); }

void evaluateEar(std::vector<DikeScratch::Ear>& ears, std::uint32_t i) {
  DikeScratch::Ear& e = ears[i];
  const DikeScratch::Ear& a = ears[e.prev];
  const DikeScratch::Ear& c = ears[e.next];
  e.diagonal2 = -1;
  if (orient(a.x, a.y, e.x, e.y, c.x, c.y) <= 0) return;  // reflex or straight: no ear
  for (std::uint32_t t = c.next; t != e.prev; t = ears[t].next) {
    const DikeScratch::Ear& v = ears[t];
    // A second visit of a corner's point (a junction touching itself there) is not inside.
    if ((v.x == a.x && v.y == a.y) || (v.x == e.x && v.y == e.y) || (v.x == c.x && v.y == c.y)) continue;
    if (orient(a.x, a.y, e.x, e.y, v.x, v.y) >= 0 && orient(e.x, e.y, c.x, c.y, v.x, v.y) >= 0 &&
        orient(c.x, c.y, a.x, a.y, v.x, v.y) >= 0)
      return;  // a vertex in the closed triangle: cutting here would make a T-junction
  }
  e.diagonal2 = diagonalRank(c.x - a.x, c.y - a.y);
}

}  // namespace

const char* clipEars(std::span<const std::uint32_t> polygon, const DikeVertex* points,
                     std::vector<DikeScratch::Ear>& ears, std::uint32_t* triangles) {
  const std::uint32_t m = std::uint32_t(polygon.size());
  assert(m >= 3 && "clipEars: a polygon with fewer than three vertices");
  const std::uint32_t* poly = polygon.data();
  auto point = [points](std::uint32_t vertex) -> const DikeVertex& { return points[vertex]; };
  auto triangle = [&triangles](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    triangles[0] = a;
    triangles[1] = b;
    triangles[2] = c;
    triangles += 3;
  };
  auto o = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    const DikeVertex& p = point(poly[a]);
    const DikeVertex& q = point(poly[b]);
    const DikeVertex& r = point(poly[c]);
    return orient(p.x, p.y, q.x, q.y, r.x, r.y);
  };
  auto emit = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) { triangle(poly[a], poly[b], poly[c]); };
  if (m == 3) {  // most junctions are triangles or quadrilaterals: no lists needed
    if (o(0, 1, 2) <= 0) return "a degenerate junction triangle";
    emit(0, 1, 2);
    return nullptr;
  }
  if (m == 4) {
    // A diagonal is valid when both halves turn left (a straight angle would put a vertex
    // on it); the shorter of two valid ones keeps triangles local.
    const bool ac = o(0, 1, 2) > 0 && o(0, 2, 3) > 0, bd = o(1, 2, 3) > 0 && o(1, 3, 0) > 0;
    if (!ac && !bd) return "a junction quadrilateral with no diagonal";
    auto rank = [&](std::uint32_t a, std::uint32_t b) {
      return diagonalRank(std::int64_t(point(poly[a]).x) - point(poly[b]).x,
                          std::int64_t(point(poly[a]).y) - point(poly[b]).y);
    };
    if (ac && (!bd || rank(0, 2) <= rank(1, 3))) {
      emit(0, 1, 2);
      emit(0, 2, 3);
    } else {
      emit(1, 2, 3);
      emit(1, 3, 0);
    }
    return nullptr;
  }
  ears.resize(m);
  for (std::uint32_t i = 0; i < m; ++i) {
    const DikeVertex& v = point(poly[i]);
    ears[i].x = v.x;
    ears[i].y = v.y;
    ears[i].vertex = poly[i];
    ears[i].prev = i == 0 ? m - 1 : i - 1;
    ears[i].next = i + 1 == m ? 0 : i + 1;
  }
  for (std::uint32_t i = 0; i < m; ++i) evaluateEar(ears, i);
  std::uint32_t head = 0, remaining = m;
  while (remaining > 3) {
    std::uint32_t best = kNone;
    std::int64_t bestLength = std::numeric_limits<std::int64_t>::max();
    std::uint32_t i = head;
    for (std::uint32_t t = 0; t < remaining; ++t, i = ears[i].next) {
      if (ears[i].diagonal2 >= 0 && ears[i].diagonal2 < bestLength) {
        best = i;
        bestLength = ears[i].diagonal2;
      }
    }
    if (best == kNone) return "a junction polygon has no ear (not simple)";
    const std::uint32_t a = ears[best].prev, c = ears[best].next;
    triangle(ears[a].vertex, ears[best].vertex, ears[c].vertex);
    ears[a].next = c;
    ears[c].prev = a;
    if (head == best) head = c;
    --remaining;
    if (remaining > 3) {
      evaluateEar(ears, a);
      evaluateEar(ears, c);
    }
  }
  const DikeScratch::Ear& e = ears[head];
  const DikeScratch::Ear& a = ears[e.prev];
  const DikeScratch::Ear& c = ears[e.next];
  if (orient(a.x, a.y, e.x, e.y, c.x, c.y) <= 0) return "a junction's last triangle is degenerate";
  triangle(a.vertex, e.vertex, c.vertex);
  return nullptr;
}

}  // namespace polder::terrain::detail
