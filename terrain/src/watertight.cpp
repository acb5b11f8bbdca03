// The watertightness checker (watertight.hpp): vertices merged in an open-addressing hash map
// on 64-bit keys, edges counted through per-vertex half-edge lists, coverage by the
// winding-number argument.
#include <polder/terrain/watertight.hpp>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numeric>
#include <random>
#include <utility>

#include <polder/mix_bits.hpp>

namespace polder::terrain {
namespace {

constexpr std::uint64_t kEmpty = ~std::uint64_t(0);

// Linear probing over a power-of-two table; keys never equal kEmpty.
template <class Value>
class HashMap {
 public:
  explicit HashMap(std::size_t expected) {
    std::size_t capacity = 16;
    while (capacity < 2 * expected) capacity *= 2;
    m_keys.assign(capacity, kEmpty);
    m_values.resize(capacity);
    m_mask = capacity - 1;
  }
  // The value slot of `key`, inserted with `initial` when absent.
  Value& at(std::uint64_t key, const Value& initial, bool* inserted = nullptr) {
    std::size_t i = mixBits(key) & m_mask;
    while (m_keys[i] != kEmpty && m_keys[i] != key) i = (i + 1) & m_mask;
    if (m_keys[i] == kEmpty) {
      m_keys[i] = key;
      m_values[i] = initial;
      if (inserted) *inserted = true;
    } else if (inserted) {
      *inserted = false;
    }
    return m_values[i];
  }
  const Value* find(std::uint64_t key) const {
    std::size_t i = mixBits(key) & m_mask;
    while (m_keys[i] != kEmpty) {
      if (m_keys[i] == key) return &m_values[i];
      i = (i + 1) & m_mask;
    }
    return nullptr;
  }

 private:
  std::vector<std::uint64_t> m_keys;
  std::vector<Value> m_values;
  std::size_t m_mask = 0;
};

std::uint64_t pointKey(std::int64_t x, std::int64_t y) {
  return (std::uint64_t(std::uint32_t(std::int32_t(x))) << 32) | std::uint64_t(std::uint32_t(std::int32_t(y)));
}

std::int64_t orient(const GridPoint& a, const GridPoint& b, const GridPoint& c) {
  return (std::int64_t(b.x) - a.x) * (std::int64_t(c.y) - a.y) - (std::int64_t(b.y) - a.y) * (std::int64_t(c.x) - a.x);
}

}  // namespace

void TriangleSoup::addTriangle(GridPoint a, GridPoint b, GridPoint c) {
  const auto base = std::uint32_t(points.size());
  points.push_back(a);
  points.push_back(b);
  points.push_back(c);
  indices.push_back(base);
  indices.push_back(base + 1);
  indices.push_back(base + 2);
}

void TriangleSoup::addBlock(const BlockMesh& mesh) {
  const auto base = std::uint32_t(points.size());
  const int s = mesh.footprint.stride;
  for (const GridVertex& v : mesh.vertices)
    points.push_back(GridPoint{mesh.footprint.x0 + int(v.i) * s, mesh.footprint.y0 + int(v.j) * s});
  for (std::uint32_t index : mesh.indices) indices.push_back(base + index);
}

void TriangleSoup::addDikes(const DikeMesh& dikes) {
  const auto base = std::uint32_t(points.size());
  for (const DikeVertex& v : dikes.vertices) points.push_back(GridPoint{v.x, v.y});
  for (std::uint32_t index : dikes.indices) indices.push_back(base + index);
}

WatertightReport checkWatertight(const TriangleSoup& soup, int width, int height, const WatertightOptions& options) {
  WatertightReport report;
  report.triangles = soup.triangleCount();
  report.expectedDoubledArea = 2 * std::int64_t(width - 1) * std::int64_t(height - 1);

  // Distinct vertices by coordinates: points inside the DEM are sorted into tiles of 64 x 64
  // samples (a counting sort), then merged per tile in a small dense table, which stays in
  // cache; points outside the DEM (an error anyway) go through a hash map.
  constexpr int kTile = 64;
  std::vector<GridPoint> unique;
  std::vector<std::uint32_t> idOf(soup.points.size());
  {
    auto inside = [&](const GridPoint& p) { return p.x >= 0 && p.y >= 0 && p.x <= width - 1 && p.y <= height - 1; };
    const int tilesX = std::max(width, 1) / kTile + 1, tilesY = std::max(height, 1) / kTile + 1;
    std::vector<std::uint32_t> tileStart(std::size_t(tilesX) * tilesY + 1, 0);
    for (const GridPoint& p : soup.points)
      if (inside(p)) ++tileStart[std::size_t(p.y / kTile) * tilesX + std::size_t(p.x / kTile) + 1];
    std::partial_sum(tileStart.begin(), tileStart.end(), tileStart.begin());
    std::vector<std::uint32_t> order(tileStart.back());
    {
      std::vector<std::uint32_t> fill(tileStart.begin(), tileStart.end() - 1);
      for (std::uint32_t i = 0; i < soup.points.size(); ++i) {
        const GridPoint& p = soup.points[i];
        if (inside(p)) order[fill[std::size_t(p.y / kTile) * tilesX + std::size_t(p.x / kTile)]++] = i;
      }
    }
    std::vector<std::uint32_t> slotStamp(kTile * kTile, 0), slotId(kTile * kTile);
    std::uint32_t stamp = 0;
    for (std::size_t tile = 0; tile + 1 < tileStart.size(); ++tile) {
      if (tileStart[tile] == tileStart[tile + 1]) continue;
      ++stamp;
      for (std::uint32_t k = tileStart[tile]; k < tileStart[tile + 1]; ++k) {
        const GridPoint& p = soup.points[order[k]];
        const std::size_t slot = std::size_t(p.y % kTile) * kTile + std::size_t(p.x % kTile);
        if (slotStamp[slot] != stamp) {
          slotStamp[slot] = stamp;
          slotId[slot] = std::uint32_t(unique.size());
          unique.push_back(p);
        }
        idOf[order[k]] = slotId[slot];
      }
    }
    HashMap<std::uint32_t> outside(16);
    for (std::uint32_t i = 0; i < soup.points.size(); ++i) {
      const GridPoint& p = soup.points[i];
      if (inside(p)) continue;
      bool inserted = false;
      idOf[i] = outside.at(pointKey(p.x, p.y), std::uint32_t(unique.size()), &inserted);
      if (inserted) {
        unique.push_back(p);
        ++report.outsidePoints;
      }
    }
  }
  report.vertices = unique.size();
  // Point -> vertex lookups, for T-junction searches only: built when first needed (a clean
  // mesh never needs it).
  std::unique_ptr<HashMap<std::uint32_t>> lookup;
  auto isVertex = [&](std::int64_t x, std::int64_t y) {
    if (!lookup) {
      lookup = std::make_unique<HashMap<std::uint32_t>>(unique.size());
      for (std::uint32_t i = 0; i < unique.size(); ++i) lookup->at(pointKey(unique[i].x, unique[i].y), i);
    }
    return lookup->find(pointKey(x, y)) != nullptr;
  };

  // Triangles: area, winding; half-edges by their start vertex (compressed rows), so that an
  // edge's uses in either direction are found in two short lists. Vertex ids of one block
  // are consecutive, which keeps this mostly cache-local, unlike one big edge hash.
  std::vector<std::uint32_t> first(unique.size() + 1, 0), target(3 * report.triangles);
  for (std::size_t t = 0; t < report.triangles; ++t) {
    const std::uint32_t v[3] = {idOf[soup.indices[3 * t]], idOf[soup.indices[3 * t + 1]],
                                idOf[soup.indices[3 * t + 2]]};
    const std::int64_t area = orient(unique[v[0]], unique[v[1]], unique[v[2]]);
    report.doubledArea += area;
    if (area == 0)
      ++report.degenerate;
    else if (area < 0)
      ++report.wrongWinding;
    for (int e = 0; e < 3; ++e) ++first[v[e] + 1];
  }
  std::partial_sum(first.begin(), first.end(), first.begin());
  {
    std::vector<std::uint32_t> fill(first.begin(), first.end() - 1);
    for (std::size_t t = 0; t < report.triangles; ++t) {
      const std::uint32_t v[3] = {idOf[soup.indices[3 * t]], idOf[soup.indices[3 * t + 1]],
                                  idOf[soup.indices[3 * t + 2]]};
      for (int e = 0; e < 3; ++e) target[fill[v[e]]++] = v[(e + 1) % 3];
    }
  }
  auto uses = [&](std::uint32_t a, std::uint32_t b) {  // half-edges a -> b
    std::uint32_t n = 0;
    for (std::uint32_t i = first[a]; i < first[a + 1]; ++i) n += target[i] == b;
    return n;
  };

  // Border stretches per side (south, east, north, west), as [start, end] along the side in
  // the counter-clockwise direction of travel.
  std::vector<std::pair<std::int64_t, std::int64_t>> border[4];
  auto vertexOnEdge = [&](const GridPoint& a, const GridPoint& b) {  // lattice points strictly inside
    const std::int64_t dx = std::int64_t(b.x) - a.x, dy = std::int64_t(b.y) - a.y;
    const std::int64_t g = std::gcd(dx < 0 ? -dx : dx, dy < 0 ? -dy : dy);
    std::size_t found = 0;
    for (std::int64_t k = 1; k < g; ++k)
      if (isVertex(a.x + dx / g * k, a.y + dy / g * k)) ++found;
    return found;
  };
  // Each undirected edge once: from its smaller vertex if that one starts a half-edge of it,
  // else from the larger one. A vertex's list is sorted first, so repeated half-edges form
  // runs (lists are short: about six entries inside a mesh).
  for (std::uint32_t a = 0; a < unique.size(); ++a) {
    std::uint32_t* list = target.data() + first[a];
    const std::uint32_t count = first[a + 1] - first[a];
    for (std::uint32_t i = 1; i < count; ++i) {
      const std::uint32_t value = list[i];
      std::uint32_t j = i;
      for (; j > 0 && list[j - 1] > value; --j) list[j] = list[j - 1];
      list[j] = value;
    }
    for (std::uint32_t i = 0; i < count;) {
      const std::uint32_t b = list[i];
      std::uint32_t forward = 0;
      while (i < count && list[i] == b) {
        ++forward;
        ++i;
      }
      if (b == a) continue;  // a repeated vertex: counted as degenerate already
      const std::uint32_t backward = uses(b, a);
      if (b < a && backward > 0) continue;  // handled from b
      const std::uint32_t total = forward + backward;
      const bool clean = forward == 1 && backward == 1;
      if (total == 1) {
        const GridPoint& p = unique[forward ? a : b];  // the single use runs p -> q
        const GridPoint& q = unique[forward ? b : a];
        int side = -1;
        if (p.y == 0 && q.y == 0)
          side = q.x > p.x ? 0 : 4;
        else if (p.x == width - 1 && q.x == width - 1)
          side = q.y > p.y ? 1 : 4;
        else if (p.y == height - 1 && q.y == height - 1)
          side = q.x < p.x ? 2 : 4;
        else if (p.x == 0 && q.x == 0)
          side = q.y < p.y ? 3 : 4;
        if (side < 0) {
          ++report.openEdges;
        } else if (side == 4) {
          ++report.borderErrors;  // on the border but clockwise
        } else {
          const std::int64_t s0 = (side == 0 || side == 2) ? p.x : p.y, s1 = (side == 0 || side == 2) ? q.x : q.y;
          border[side].emplace_back(std::min(s0, s1), std::max(s0, s1));
        }
      } else if (total > 2) {
        ++report.overSharedEdges;
      } else if (!clean) {
        ++report.flippedEdges;
      }
      if (!clean) report.tJunctions += vertexOnEdge(unique[a], unique[b]);
    }
  }
  // Each border side must be covered exactly once, end to end.
  for (int side = 0; side < 4; ++side) {
    auto& list = border[side];
    std::sort(list.begin(), list.end());
    const std::int64_t length = (side == 0 || side == 2) ? width - 1 : height - 1;
    std::int64_t reached = 0;
    for (const auto& [a, b] : list) {
      if (a != reached) ++report.borderErrors;  // a hole or an overlap along the border
      reached = std::max(reached, b);
    }
    if (reached != length) ++report.borderErrors;
  }

  report.coversExactly = report.outsidePoints == 0 && report.degenerate == 0 && report.wrongWinding == 0 &&
                         report.openEdges == 0 && report.overSharedEdges == 0 && report.flippedEdges == 0 &&
                         report.borderErrors == 0 && report.doubledArea == report.expectedDoubledArea;

  if (options.samplePoints > 0 && report.triangles > 0 && width > 1 && height > 1) {
    // Square buckets hold the triangles whose boxes reach them, sized for about one triangle
    // per bucket's area: the boxes of a covering mesh add up to a few times the DEM's area, so
    // the lists hold a few entries per triangle and per bucket.
    const double perTriangle = double(width - 1) * double(height - 1) / double(report.triangles);
    const int bucket = std::clamp(int(std::ceil(std::sqrt(perTriangle))), 1, std::max(width, height));
    const int bx = (width - 2) / bucket + 1, by = (height - 2) / bucket + 1;
    std::vector<std::uint32_t> start(std::size_t(bx) * by + 1, 0);
    auto forBuckets = [&](std::size_t t, auto&& f) {
      const GridPoint& a = unique[idOf[soup.indices[3 * t]]];
      const GridPoint& b = unique[idOf[soup.indices[3 * t + 1]]];
      const GridPoint& c = unique[idOf[soup.indices[3 * t + 2]]];
      const int x0 = std::clamp(std::min({a.x, b.x, c.x}) / bucket, 0, bx - 1);
      const int x1 = std::clamp(std::max({a.x, b.x, c.x}) / bucket, 0, bx - 1);
      const int y0 = std::clamp(std::min({a.y, b.y, c.y}) / bucket, 0, by - 1);
      const int y1 = std::clamp(std::max({a.y, b.y, c.y}) / bucket, 0, by - 1);
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) f(std::size_t(y) * bx + x);
    };
    for (std::size_t t = 0; t < report.triangles; ++t) forBuckets(t, [&](std::size_t b) { ++start[b + 1]; });
    std::partial_sum(start.begin(), start.end(), start.begin());
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1), list(start.back());
    for (std::size_t t = 0; t < report.triangles; ++t)
      forBuckets(t, [&](std::size_t b) { list[fill[b]++] = std::uint32_t(t); });

    // Points (X / D, Y / D) with D odd and larger than any coordinate difference; a point on
    // an edge (orientation 0) is skipped rather than guessed.
    constexpr std::int64_t kD = 1000003;
    std::mt19937_64 rng(options.seed);
    std::uniform_int_distribution<std::int64_t> px(1, std::int64_t(width - 1) * kD - 1),
        py(1, std::int64_t(height - 1) * kD - 1);
    for (std::size_t sample = 0; sample < options.samplePoints; ++sample) {
      const std::int64_t X = px(rng), Y = py(rng);
      const int cellX = std::clamp(int(X / kD / bucket), 0, bx - 1),
                cellY = std::clamp(int(Y / kD / bucket), 0, by - 1);
      const std::size_t b = std::size_t(cellY) * bx + cellX;
      int inside = 0;
      bool onEdge = false;
      for (std::uint32_t e = start[b]; e < start[b + 1] && !onEdge; ++e) {
        const std::size_t t = list[e];
        const GridPoint* v[3] = {&unique[idOf[soup.indices[3 * t]]], &unique[idOf[soup.indices[3 * t + 1]]],
                                 &unique[idOf[soup.indices[3 * t + 2]]]};
        std::int64_t o[3];
        for (int k = 0; k < 3; ++k) {
          const GridPoint& p = *v[k];
          const GridPoint& q = *v[(k + 1) % 3];
          o[k] = (std::int64_t(q.x) - p.x) * (Y - std::int64_t(p.y) * kD) -
                 (std::int64_t(q.y) - p.y) * (X - std::int64_t(p.x) * kD);
        }
        if (o[0] == 0 || o[1] == 0 || o[2] == 0) {
          const bool allSame = (o[0] >= 0 && o[1] >= 0 && o[2] >= 0) || (o[0] <= 0 && o[1] <= 0 && o[2] <= 0);
          onEdge = allSame;
          continue;
        }
        if ((o[0] > 0 && o[1] > 0 && o[2] > 0) || (o[0] < 0 && o[1] < 0 && o[2] < 0)) ++inside;
      }
      if (onEdge) continue;
      ++report.samplesTested;
      if (inside == 0)
        ++report.samplesUncovered;
      else if (inside > 1)
        ++report.samplesOverlapped;
    }
  }
  return report;
}

}  // namespace polder::terrain
