// The terrain generator's erosion stages.
//
// - Flow routing: Priority-Flood (Barnes, Lehman & Mulla, "Priority-Flood: An optimal
//   depression-filling and watershed-labeling algorithm", 2014) from the border inwards
//   gives the depression-filled surface and an order in which every sample follows its
//   lower neighbours; water splits over the lower neighbours in proportion to slope (Quinn
//   et al., "The prediction of hillslope flow paths", 1991).
// - Fluvial: the stream-power law dh/dt = -K A^m S^n with m = 1/2, n = 1, integrated
//   implicitly along that order (Braun & Willett, "A very efficient O(n), implicit and
//   parallel method to solve the stream power equation", 2013), above a channel-initiation
//   area. Lakes silt up while their outlets cut down, so closed basins drain over the
//   iterations; rivers leaving the map cut towards its lowest ground.
// - Thermal: talus relaxation (Musgrave, Kolb & Mace, "The synthesis and rendering of eroded
//   fractal terrains", 1989), Jacobi-style so the result does not depend on visiting order.
// - Droplets: particle hydraulic erosion as in Beyer, "Implementation of a method for
//   hydraulic erosion" (2015), which builds on Mei, Decaudin & Hu (2007)'s sediment capacity.
// - Fill: Priority-Flood+Epsilon (Barnes et al. 2014, algorithm 3).
#include <polder/terrain/generator.hpp>

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <cstddef>
#include <functional>
#include <limits>
#include <queue>
#include <vector>

namespace polder::terrain {
namespace {

// The eight neighbours, in a fixed order (the order matters for determinism, not for the result).
constexpr int kNeighbourDx[8] = {1, 1, 0, -1, -1, -1, 0, 1};
constexpr int kNeighbourDy[8] = {0, 1, 1, 1, 0, -1, -1, -1};
constexpr std::uint8_t kOutlet = 0xff;  // a border sample: water leaves the map
constexpr std::uint8_t kUnvisited = 0xfe;
constexpr float kChannelArea = 16.0f;  // samples draining through a sample before rivers erode it
constexpr double kLakeSilting = 0.3;   // share of a lake's depth filled with sediment per iteration

// Floats as unsigned integers in the same order, so a heap key packs height and index and
// every key is unique: the flood's order is then the same for any heap implementation.
std::uint64_t floodKey(float height, std::uint32_t index) {
  const auto bits = std::bit_cast<std::uint32_t>(height);
  const std::uint32_t ordered = (bits & 0x80000000u) ? ~bits : (bits | 0x80000000u);
  return (std::uint64_t(ordered) << 32) | index;
}

// The open set of a Priority-Flood (Barnes et al. 2014): a min-heap by height, plus a FIFO
// for samples inside a depression, which drain before the heap's next sample.
class FloodQueue {
 public:
  explicit FloodQueue(std::size_t capacity) {
    std::vector<std::uint64_t> storage;
    storage.reserve(capacity);
    m_heap = MinHeap(std::greater<>(), std::move(storage));
  }
  void push(float height, std::uint32_t index) { m_heap.push(floodKey(height, index)); }
  void pushPit(std::uint32_t index) { m_pit.push_back(index); }
  bool empty() const { return m_heap.empty() && m_pitHead == m_pit.size(); }
  std::uint32_t pop() {
    if (m_pitHead < m_pit.size()) {
      const std::uint32_t c = m_pit[m_pitHead++];
      if (m_pitHead == m_pit.size()) m_pit.clear(), m_pitHead = 0;
      return c;
    }
    const auto c = std::uint32_t(m_heap.top());
    m_heap.pop();
    return c;
  }

 private:
  using MinHeap = std::priority_queue<std::uint64_t, std::vector<std::uint64_t>, std::greater<>>;
  MinHeap m_heap;
  std::vector<std::uint32_t> m_pit;
  std::size_t m_pitHead = 0;  // next FIFO entry
};

// Grid geometry shared by the stages: neighbour index offsets and distances in metres.
struct Grid {
  int width, height;
  std::ptrdiff_t offset[8];
  double distance[8];

  explicit Grid(const Heightfield& field) : width(field.width), height(field.height) {
    for (int k = 0; k < 8; ++k) {
      offset[k] = std::ptrdiff_t(kNeighbourDy[k]) * width + kNeighbourDx[k];
      distance[k] = std::sqrt(kNeighbourDx[k] * kNeighbourDx[k] * field.spacingX * field.spacingX +
                              kNeighbourDy[k] * kNeighbourDy[k] * field.spacingY * field.spacingY);
    }
  }
  bool onBorder(int x, int y) const { return x == 0 || y == 0 || x == width - 1 || y == height - 1; }
};

// Where each sample's water goes on the depression-filled surface, and an order in which
// every sample comes after all its lower neighbours.
struct Drainage {
  std::vector<std::uint8_t> direction;  // neighbour the flood reached it from, or kOutlet
  std::vector<std::uint32_t> order;     // outlets first, then up the drainage tree
  std::vector<float> filled;            // the depression-filled surface the routing follows
};

// Priority-Flood from the border; the heap pops in non-decreasing filled height, so a
// sample's lower neighbours are always ordered before it. Samples inside a depression (at or
// below the spill level) go through a FIFO instead of the heap, as in Barnes' improved
// variant, and drain towards the spill point.
void routeFlow(const Heightfield& field, const Grid& grid, Drainage& out) {
  const int w = grid.width, h = grid.height;
  const std::size_t n = field.sampleCount();
  out.direction.assign(n, kUnvisited);
  out.order.clear();
  out.order.reserve(n);
  out.filled.assign(field.heights.begin(), field.heights.end());
  FloodQueue queue(std::size_t(2 * (w + h)));

  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (grid.onBorder(x, y)) {
        const auto i = std::uint32_t(field.index(x, y));
        out.direction[i] = kOutlet;
        queue.push(out.filled[i], i);
      }

  while (!queue.empty()) {
    const std::uint32_t c = queue.pop();
    out.order.push_back(c);
    const int cx = int(c % std::uint32_t(w)), cy = int(c / std::uint32_t(w));
    const float level = out.filled[c];
    for (int k = 0; k < 8; ++k) {
      const int nx = cx + kNeighbourDx[k], ny = cy + kNeighbourDy[k];
      if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
      const auto nb = std::uint32_t(std::ptrdiff_t(c) + grid.offset[k]);
      if (out.direction[nb] != kUnvisited) continue;
      out.direction[nb] = std::uint8_t((k + 4) & 7);  // towards c
      if (out.filled[nb] <= level) {
        out.filled[nb] = level;
        queue.pushPit(nb);
      } else {
        queue.push(out.filled[nb], nb);
      }
    }
  }
}

// Progress within a stage, clamped to 0..1.
void report(const std::function<void(float)>& progress, double f) {
  if (progress) progress(float(std::clamp(f, 0.0, 1.0)));
}

}  // namespace

void erodeFluvial(Heightfield& field, const FluvialOptions& options, const std::function<void(float)>& progress) {
  assert(options.iterations >= 0 && options.strength >= 0.0 && "erodeFluvial: invalid options");
  if (field.width < 3 || field.height < 3 || options.iterations == 0 || options.strength == 0.0) {
    report(progress, 1.0);
    return;
  }
  const Grid grid(field);
  const int w = grid.width, h = grid.height;
  const std::size_t n = field.sampleCount();
  Drainage drainage;
  std::vector<float> area(n);
  // With m = 1/2 and A counted in samples, K*dt*A^m/d is dimensionless: the same strength
  // carves the same shapes at any spacing.
  const double cellSide = std::sqrt(field.spacingX * field.spacingY);

  // Water leaves a sample towards all its lower neighbours (on the filled surface), in
  // proportion to slope (Quinn et al. 1991): single-direction routing (D8) scores parallel,
  // grid-aligned grooves into planar slopes; valleys still gather the flow by convergence.
  // On a flat (a filled lake) the one receiver is the neighbour the flood came from.
  struct Receivers {
    int count;
    std::uint32_t index[8];
    double share[8];     // of the sample's water, summing to 1
    double distance[8];  // metres
  };
  auto receiversOf = [&](std::uint32_t c, Receivers& out) {
    out.count = 0;
    const int cx = int(c % std::uint32_t(w)), cy = int(c / std::uint32_t(w));
    const float level = drainage.filled[c];
    double total = 0.0;
    for (int k = 0; k < 8; ++k) {
      const int nx = cx + kNeighbourDx[k], ny = cy + kNeighbourDy[k];
      if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
      const auto j = std::uint32_t(std::ptrdiff_t(c) + grid.offset[k]);
      const float below = drainage.filled[j];
      if (below >= level) continue;
      const double slope = (double(level) - below) / grid.distance[k];
      out.index[out.count] = j;
      out.share[out.count] = slope;
      out.distance[out.count] = grid.distance[k];
      total += slope;
      ++out.count;
    }
    if (out.count == 0 || !(total > 0.0)) {
      const std::uint8_t k = drainage.direction[c];
      out.count = 1;
      out.index[0] = std::uint32_t(std::ptrdiff_t(c) + grid.offset[k]);
      out.share[0] = 1.0;
      out.distance[0] = grid.distance[k];
      return;
    }
    for (int r = 0; r < out.count; ++r) out.share[r] /= total;
  };

  const double baseLevel = *std::min_element(field.heights.begin(), field.heights.end());
  Receivers receivers;
  for (int iteration = 0; iteration < options.iterations; ++iteration) {
    routeFlow(field, grid, drainage);
    std::fill(area.begin(), area.end(), 1.0f);
    // Donors before receivers: the flood's order, reversed.
    for (std::size_t j = n; j-- > 0;) {
      const std::uint32_t c = drainage.order[j];
      if (drainage.direction[c] == kOutlet) continue;
      receiversOf(c, receivers);
      for (int r = 0; r < receivers.count; ++r) area[receivers.index[r]] += float(area[c] * receivers.share[r]);
    }
    // Receivers before donors: each sample's receivers already hold their new heights, so
    // the implicit step is explicit here.
    for (const std::uint32_t c : drainage.order) {
      const double here = field.heights[c];
      if (drainage.filled[c] > here) {
        // Under a lake: the river drops its load and the lake silts up, while its outlet cuts
        // down; both drain closed basins over the iterations.
        field.heights[c] = float(here + kLakeSilting * (double(drainage.filled[c]) - here));
        continue;
      }
      // Channels start where enough water gathers; hillslopes above them keep their shape
      // (eroding them too scores grid-aligned rills into every planar slope).
      if (area[c] < kChannelArea) continue;
      const double k = options.strength * std::sqrt(double(area[c])) * cellSide;
      if (drainage.direction[c] == kOutlet) {
        // The map ends but the river goes on: it leaves towards the lowest ground of the map,
        // one sample beyond the border, so it cuts down at the edge as it does upstream and
        // basins lower than the border can still drain out.
        if (here > baseLevel) {
          const double f = k / cellSide;
          field.heights[c] = float((here + f * baseLevel) / (1.0 + f));
        }
        continue;
      }
      receiversOf(c, receivers);
      double sumF = 0.0, sumFh = 0.0;
      for (int r = 0; r < receivers.count; ++r) {
        const double below = field.heights[receivers.index[r]];
        if (below >= here) continue;
        const double f = k * receivers.share[r] / receivers.distance[r];
        sumF += f;
        sumFh += f * below;
      }
      if (sumF > 0.0) field.heights[c] = float((here + sumFh) / (1.0 + sumF));
    }
    report(progress, double(iteration + 1) / options.iterations);
  }
}

void erodeThermal(Heightfield& field, const ThermalOptions& options) {
  assert(options.iterations >= 0 && options.talusSlope > 0.0 && "erodeThermal: invalid options");
  if (field.width < 2 || field.height < 2 || options.iterations == 0) return;
  const Grid grid(field);
  const int w = grid.width, h = grid.height;
  // Each sample has eight neighbours; moving a tenth of the excess per pair keeps a spike
  // from overshooting below its neighbours.
  constexpr double kRate = 0.1;
  double talusDrop[8];
  for (int k = 0; k < 8; ++k) talusDrop[k] = options.talusSlope * grid.distance[k];
  std::vector<float> delta(field.sampleCount());
  for (int iteration = 0; iteration < options.iterations; ++iteration) {
    std::fill(delta.begin(), delta.end(), 0.0f);
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const std::size_t i = field.index(x, y);
        // Each unordered pair once: east, north-east, north, north-west.
        for (int k = 0; k < 4; ++k) {
          const int nx = x + kNeighbourDx[k], ny = y + kNeighbourDy[k];
          if (nx < 0 || nx >= w || ny >= h) continue;
          const std::size_t j = std::size_t(std::ptrdiff_t(i) + grid.offset[k]);
          const double diff = double(field.heights[i]) - field.heights[j];
          const double excess = std::abs(diff) - talusDrop[k];
          if (excess <= 0.0) continue;
          const float moved = float(kRate * (diff > 0.0 ? excess : -excess));
          delta[i] -= moved;
          delta[j] += moved;
        }
      }
    }
    for (std::size_t i = 0; i < delta.size(); ++i) field.heights[i] += delta[i];
  }
}

namespace {

// PCG32 (O'Neill 2014, XSH-RR): a small, well-mixed generator with the same stream everywhere.
class Pcg32 {
 public:
  explicit Pcg32(std::uint64_t seed) : m_state(0) {
    next();
    m_state += seed;
    next();
  }
  std::uint32_t next() {
    const std::uint64_t old = m_state;
    m_state = old * 6364136223846793005ULL + 1442695040888963407ULL;
    const auto xorshifted = std::uint32_t(((old >> 18u) ^ old) >> 27u);
    const auto rot = std::uint32_t(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
  }
  // Uniform in [0, 1): 24 random bits, exact in a float and a double.
  double uniform() { return double(next() >> 8) * (1.0 / 16777216.0); }

 private:
  std::uint64_t m_state;
};

// Height and gradient of the bilinear surface at (x, y), in the work grid's units.
struct Sample {
  double height, gx, gy;
};

inline Sample bilinear(const float* h, std::size_t w, double x, double y) {
  const int ix = int(x), iy = int(y);
  const double u = x - ix, v = y - iy;
  const float* p = h + std::size_t(iy) * w + std::size_t(ix);
  const double h00 = p[0], h10 = p[1], h01 = p[w], h11 = p[w + 1];
  return {h00 * (1 - u) * (1 - v) + h10 * u * (1 - v) + h01 * (1 - u) * v + h11 * u * v,
          (h10 - h00) * (1 - v) + (h11 - h01) * v, (h01 - h00) * (1 - u) + (h11 - h10) * u};
}

inline double bilinearHeight(const float* h, std::size_t w, double x, double y) {
  const int ix = int(x), iy = int(y);
  const double u = x - ix, v = y - iy;
  const float* p = h + std::size_t(iy) * w + std::size_t(ix);
  const double south = p[0] + u * (double(p[1]) - p[0]);
  const double north = p[w] + u * (double(p[w + 1]) - p[w]);
  return south + v * (north - south);
}

}  // namespace

void erodeDroplets(Heightfield& field, const DropletOptions& options, std::uint64_t seed,
                   const std::function<void(float)>& progress) {
  assert(options.dropletsPerSample >= 0.0 && options.maxSteps >= 1 && "erodeDroplets: invalid options");
  const int w = field.width, h = field.height;
  if (w < 4 || h < 4 || options.dropletsPerSample == 0.0) {
    report(progress, 1.0);
    return;
  }
  // Beyer's parameters assume slopes of order one per cell: work in heights divided by the
  // spacing, so the same options erode alike at any spacing.
  const double cellSide = std::sqrt(field.spacingX * field.spacingY);
  std::vector<float> work(field.heights.size());
  for (std::size_t i = 0; i < work.size(); ++i) work[i] = float(field.heights[i] / cellSide);

  constexpr double kInertia = 0.05;   // how much a droplet keeps its direction
  constexpr double kCapacity = 4.0;   // sediment a unit of water carries per unit of drop and speed
  constexpr double kMinSlope = 0.01;  // keeps capacity above zero on flats
  constexpr double kGravity = 4.0;
  constexpr double kEvaporation = 0.02;  // per step
  constexpr double kMaxSpeed = 4.0;      // caps capacity on long steep runs
  // Erosion brush: radius 2 samples, weights falling off linearly, normalised.
  struct BrushTap {
    int dx, dy;
    double weight;
  };
  std::vector<BrushTap> brush;
  double brushSum = 0.0;
  constexpr double kRadius = 2.0;
  for (int dy = -1; dy <= 2; ++dy)
    for (int dx = -1; dx <= 2; ++dx) {
      // Centred on the droplet's cell (between samples 0 and 1 on each axis).
      const double ex = dx - 0.5, ey = dy - 0.5;
      const double d = std::sqrt(ex * ex + ey * ey);
      if (d < kRadius) {
        brush.push_back({dx, dy, kRadius - d});
        brushSum += kRadius - d;
      }
    }
  for (BrushTap& tap : brush) tap.weight /= brushSum;

  // One droplet from (x, y) until it stops, leaves or evaporates.
  auto runDroplet = [&](double x, double y) {
    double dirX = 0.0, dirY = 0.0, speed = 1.0, water = 1.0, sediment = 0.0;
    for (int step = 0; step < options.maxSteps; ++step) {
      const int cellX = int(x), cellY = int(y);
      const double u = x - cellX, v = y - cellY;
      const Sample here = bilinear(work.data(), std::size_t(w), x, y);
      dirX = dirX * kInertia - here.gx * (1.0 - kInertia);
      dirY = dirY * kInertia - here.gy * (1.0 - kInertia);
      const double length = std::sqrt(dirX * dirX + dirY * dirY);
      if (length < 1e-12) return;  // a perfectly flat spot: the droplet stays and evaporates
      dirX /= length;
      dirY /= length;
      x += dirX;
      y += dirY;
      // Droplets stop one sample short of the border and never erode it. On their way out they
      // may still only fill: water leaving the map with its sediment would otherwise dig a
      // hole beside the border, droplet after droplet, that nothing ever refills.
      const bool leaving = !(x >= 1.0 && y >= 1.0 && x < w - 2 && y < h - 2);
      const double nextX = std::clamp(x, 0.0, w - 1.0 - 1e-6), nextY = std::clamp(y, 0.0, h - 1.0 - 1e-6);
      const double drop = here.height - bilinearHeight(work.data(), std::size_t(w), nextX, nextY);  // > 0 downhill
      const double capacity = std::max(drop, kMinSlope) * speed * water * kCapacity;
      const std::size_t cell = std::size_t(cellY) * std::size_t(w) + std::size_t(cellX);
      if (drop < 0.0 || sediment > capacity) {
        // Uphill: fill the pit behind the droplet (at most up to the new height); otherwise
        // drop a share of the excess. Bilinear weights put it where the droplet was.
        const double amount = drop < 0.0 ? std::min(-drop, sediment) : (sediment - capacity) * options.depositionRate;
        sediment -= amount;
        work[cell] += float(amount * (1 - u) * (1 - v));
        work[cell + 1] += float(amount * u * (1 - v));
        work[cell + std::size_t(w)] += float(amount * (1 - u) * v);
        work[cell + std::size_t(w) + 1] += float(amount * u * v);
      } else if (!leaving) {
        // Never dig deeper than the drop, or the droplet would carve a pit it then fills.
        const double amount = std::min((capacity - sediment) * options.erosionRate, drop);
        double taken = 0.0;
        for (const BrushTap& tap : brush) {
          const int tx = cellX + tap.dx, ty = cellY + tap.dy;
          if (tx < 1 || ty < 1 || tx >= w - 1 || ty >= h - 1) continue;
          const double part = amount * tap.weight;
          work[std::size_t(ty) * std::size_t(w) + std::size_t(tx)] -= float(part);
          taken += part;
        }
        sediment += taken;
      }
      if (leaving) return;
      speed = std::min(std::sqrt(std::max(speed * speed + drop * kGravity, 0.0)), kMaxSpeed);
      water *= 1.0 - kEvaporation;
    }
  };

  // Droplets start tile by tile, the tiles in random order: each tile's samples stay in
  // cache while its droplets run (about twice as fast as starting anywhere at random), and
  // the shuffled order keeps a sweep direction out of the result.
  constexpr int kTile = 64;
  const int spanX = w - 3, spanY = h - 3;  // starts lie in [1, w - 2) x [1, h - 2)
  const int tilesX = (spanX + kTile - 1) / kTile, tilesY = (spanY + kTile - 1) / kTile;
  std::vector<std::uint32_t> tiles(std::size_t(tilesX) * std::size_t(tilesY));
  for (std::size_t i = 0; i < tiles.size(); ++i) tiles[i] = std::uint32_t(i);
  Pcg32 random(seed);
  for (std::size_t i = tiles.size(); i > 1; --i) {  // Fisher-Yates
    const auto j = std::size_t((std::uint64_t(random.next()) * i) >> 32);
    std::swap(tiles[i - 1], tiles[j]);
  }
  for (std::size_t t = 0; t < tiles.size(); ++t) {
    const int x0 = 1 + int(tiles[t] % std::uint32_t(tilesX)) * kTile;
    const int y0 = 1 + int(tiles[t] / std::uint32_t(tilesX)) * kTile;
    const int tileW = std::min(kTile, spanX - (x0 - 1)), tileH = std::min(kTile, spanY - (y0 - 1));
    const auto count = std::uint64_t(options.dropletsPerSample * tileW * tileH + 0.5);
    for (std::uint64_t i = 0; i < count; ++i) {
      const double x = x0 + random.uniform() * tileW, y = y0 + random.uniform() * tileH;
      runDroplet(x, y);
    }
    if (t % 16 == 15) report(progress, double(t + 1) / double(tiles.size()));
  }
  for (std::size_t i = 0; i < work.size(); ++i) field.heights[i] = float(work[i] * cellSide);
  report(progress, 1.0);
}

void fillDepressions(Heightfield& field) {
  const int w = field.width, h = field.height;
  if (w < 3 || h < 3) return;
  const Grid grid(field);
  const std::size_t n = field.sampleCount();
  std::vector<std::uint8_t> visited(n, 0);
  FloodQueue queue(std::size_t(2 * (w + h)));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (grid.onBorder(x, y)) {
        const auto i = std::uint32_t(field.index(x, y));
        visited[i] = 1;
        queue.push(field.heights[i], i);
      }
  constexpr float kEpsilonM = 0.001f;
  while (!queue.empty()) {
    const std::uint32_t c = queue.pop();
    const int cx = int(c % std::uint32_t(w)), cy = int(c / std::uint32_t(w));
    // Strictly above c even where a millimetre is below the float's resolution.
    const float level = field.heights[c];
    const float raised = std::max(level + kEpsilonM, std::nextafter(level, std::numeric_limits<float>::infinity()));
    for (int k = 0; k < 8; ++k) {
      const int nx = cx + kNeighbourDx[k], ny = cy + kNeighbourDy[k];
      if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
      const auto nb = std::uint32_t(std::ptrdiff_t(c) + grid.offset[k]);
      if (visited[nb]) continue;
      visited[nb] = 1;
      if (field.heights[nb] < raised) {
        field.heights[nb] = raised;
        queue.pushPit(nb);
      } else {
        queue.push(field.heights[nb], nb);
      }
    }
  }
}

}  // namespace polder::terrain
