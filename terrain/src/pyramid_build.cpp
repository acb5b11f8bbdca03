// buildPyramid: the DEM's rows flow through the levels; each level finishes a row of nodes as
// soon as it holds their rows (and, above level 0, its children are done), writes their
// tiles, and lets go of the rows no node needs any more.
#include <polder/terrain/pyramid_build.hpp>

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <deque>
#include <limits>
#include <mutex>
#include <new>
#include <optional>
#include <vector>

#include <polder/checksum.hpp>
#include <polder/partial_file.hpp>
#include <polder/terrain/block_layout.hpp>
#include <polder/terrain/pyramid.hpp>
#include <polder/terrain/rtin.hpp>
#include <polder/thread_pool.hpp>

#include "pyramid_layout.hpp"

namespace polder::terrain {
namespace {

using namespace pyramid_layout;

constexpr float kInfinity = std::numeric_limits<float>::infinity();
constexpr int kBandRows = 64;  // source rows per read

// Rounds a non-negative value up to float, so that stored bounds never fall below the exact ones.
float roundUp(double x) {
  const float f = float(x);
  return std::bit_cast<float>(std::bit_cast<std::uint32_t>(f) + std::uint32_t(double(f) < x));
}

// The cells' residuals as the tile slot holds them (pyramid_layout.hpp): a step of at least
// largest / 255 and, per cell, the least byte whose multiple of the step, in float as the
// reader computes it, is not below the residual. `residual` becomes what the reader will get
// back, which is what the node's bounds are built from; returns its largest.
float encodeResiduals(std::vector<float>& residual, unsigned char* out) {
  const float largest = residual.empty() ? 0.0f : *std::max_element(residual.begin(), residual.end());
  float step = largest > 0.0f ? roundUp(double(largest) / 255.0 * (1.0 + 1e-6)) : 0.0f;
  for (;; step = std::nextafter(step, kInfinity)) {
    bool fits = true;
    for (std::size_t c = 0; c < residual.size() && fits; ++c) {
      int code = residual[c] == 0.0f ? 0 : int(std::ceil(double(residual[c]) / double(step)));
      while (code <= 255 && float(code) * step < residual[c]) ++code;
      fits = code <= 255;
      out[sizeof(float) + c] = std::uint8_t(std::min(code, 255));
    }
    if (fits) break;
  }
  std::memcpy(out, &step, sizeof step);
  float decodedLargest = 0.0f;
  for (std::size_t c = 0; c < residual.size(); ++c) {
    residual[c] = float(out[sizeof(float) + c]) * step;
    decodedLargest = std::max(decodedLargest, residual[c]);
  }
  return decodedLargest;
}

// A window of consecutive rows of one level's samples or cells.
template <class T>
class RowWindow {
 public:
  explicit RowWindow(int width) : m_width(width) {}
  int width() const { return m_width; }
  int end() const { return m_first + int(m_rows.size()); }  // one past the last row held
  const T* row(int y) const { return m_rows[std::size_t(y - m_first)].data(); }
  std::vector<T>& append() {
    if (m_spare.empty()) {
      m_rows.emplace_back(std::size_t(m_width));
    } else {
      m_rows.push_back(std::move(m_spare.back()));
      m_spare.pop_back();
    }
    return m_rows.back();
  }
  void dropBelow(int y) {
    while (!m_rows.empty() && m_first < y) {
      m_spare.push_back(std::move(m_rows.front()));
      m_rows.pop_front();
      ++m_first;
    }
  }

 private:
  int m_width;
  int m_first = 0;
  std::deque<std::vector<T>> m_rows;
  std::vector<std::vector<T>> m_spare;
};
using LevelRows = RowWindow<float>;

// What level L >= 1 knows of one of its cells: the exact range of the full-resolution samples
// under it (the closed cell) and a bound on |full resolution - level surface| over it.
struct CellBound {
  float residual = 0.0f;
  float minHeight = 0.0f;
  float maxHeight = 0.0f;
};

Error ioError(const std::filesystem::path& path, const std::string& what) {
  return Error{ErrorKind::Io, path.string() + ": cannot " + what + ": " + std::strerror(errno)};
}

Status writeExactly(int fd, const void* data, std::size_t size, std::uint64_t offset,
                    const std::filesystem::path& path) {
  const auto* bytes = static_cast<const unsigned char*>(data);
  std::size_t done = 0;
  while (done < size) {
    const ssize_t wrote = ::pwrite(fd, bytes + done, size - done, off_t(offset + done));
    if (wrote < 0 && errno == EINTR) continue;
    if (wrote <= 0) return ioError(path, "write");
    done += std::size_t(wrote);
  }
  return {};
}

class Builder {
 public:
  Builder(HeightRows& source, const BlockLayout& layout, const PyramidBuildOptions& options, int fd,
          const std::filesystem::path& path, std::uint64_t tilesOffset)
      : m_source(source), m_layout(layout), m_options(options), m_fd(fd), m_path(path), m_tilesOffset(tilesOffset) {
    const int levels = layout.rootLevel() + 1;
    std::uint64_t total = 0;
    for (int level = 0; level < levels; ++level) {
      m_levelOffset.push_back(total);
      total += std::uint64_t(layout.nodesX(level)) * std::uint64_t(layout.nodesY(level));
      m_rows.emplace_back(levelSamples(layout.width(), level));
      m_cells.emplace_back(level == 0 ? 0 : levelSamples(layout.width(), level) - 1);
      m_levelHeight.push_back(levelSamples(layout.height(), level));
    }
    m_nextRow.assign(std::size_t(levels), 0);
    m_nodeCount = total;
  }

  std::uint64_t nodeCount() const { return m_nodeCount; }
  const std::vector<PyramidNode>& nodes() const { return m_nodes; }
  const std::vector<float>& eastBorder() const { return m_east; }
  const std::vector<float>& northBorder() const { return m_north; }
  float minHeight() const { return m_min; }
  float maxHeight() const { return m_max; }

  Status run() {
    const int width = m_layout.width(), height = m_layout.height();
    std::vector<float> bands[2];
    try {
      m_nodes.resize(std::size_t(m_nodeCount));
      m_east.resize(std::size_t(height));
      m_north.resize(std::size_t(width));
      for (auto& band : bands) band.resize(std::size_t(kBandRows) * std::size_t(width));
    } catch (const std::bad_alloc&) {
      return makeError(ErrorKind::OutOfMemory,
                       m_path.string() + ": no memory for " + std::to_string(m_nodeCount) + " node records");
    }
    // While one band goes through the levels the next one is read.
    int current = 0;
    if (Status read = readBand(0, bands[current]); !read) return read;
    for (int y0 = 0; y0 < height; y0 += kBandRows) {
      const int next = y0 + kBandRows;
      Status nextRead, processed;
      auto half = [&](int which) {
        if (which == 0) {
          if (next < height) nextRead = readBand(next, bands[1 - current]);
        } else {
          processed = processBand(y0, bands[current]);
        }
      };
      if (m_options.pool != nullptr) {
        m_options.pool->runHalves(half);
      } else {
        half(1);
        half(0);
      }
      if (!processed) return processed;
      if (!nextRead) return nextRead;
      current = 1 - current;
      if (m_options.progress) m_options.progress(0.98f * float(std::min(next, height)) / float(height));
    }
    for (int level = 0; level <= m_layout.rootLevel(); ++level)
      if (m_nextRow[std::size_t(level)] != m_layout.nodesY(level))
        return makeError(ErrorKind::InvalidData,
                         m_path.string() + ": internal: level " + std::to_string(level) + " was left unfinished");
    return {};
  }

 private:
  // Rows [y0, y0 + kBandRows) of the source, fewer at the top, checked.
  Status readBand(int y0, std::vector<float>& band) {
    const int width = m_layout.width();
    const int count = std::min(kBandRows, m_layout.height() - y0);
    const std::span<float> rows(band.data(), std::size_t(count) * std::size_t(width));
    if (Status read = m_source.readRows(y0, count, rows); !read) return read;
    for (int r = 0; r < count; ++r) {
      const float* row = rows.data() + std::size_t(r) * std::size_t(width);
      for (int x = 0; x < width; ++x)
        if (!std::isfinite(row[x]))
          return makeError(ErrorKind::InvalidData, sourceName() + ": sample (" + std::to_string(x) + ", " +
                                                       std::to_string(y0 + r) + ") is not a finite height");
    }
    return {};
  }

  Status processBand(int y0, const std::vector<float>& band) {
    const int width = m_layout.width(), height = m_layout.height();
    const int count = std::min(kBandRows, height - y0);
    for (int r = 0; r < count; ++r) {
      const float* row = band.data() + std::size_t(r) * std::size_t(width);
      const auto [lo, hi] = std::minmax_element(row, row + width);
      m_min = std::min(m_min, *lo);
      m_max = std::max(m_max, *hi);
      m_east[std::size_t(y0 + r)] = row[width - 1];
      if (y0 + r == height - 1) std::copy(row, row + width, m_north.begin());
      try {
        pushRow(0, y0 + r, row);
      } catch (const std::bad_alloc&) {
        return makeError(ErrorKind::OutOfMemory, m_path.string() + ": no memory for the level rows");
      }
    }
    return finishReadyNodes();
  }

  std::string sourceName() const { return m_options.sourceName.empty() ? "the source" : m_options.sourceName; }

  // Row y of level L: kept, the cells below it bounded, and every other row passed to level
  // L + 1 (every other sample).
  void pushRow(int level, int y, const float* row) {
    LevelRows& rows = m_rows[std::size_t(level)];
    std::vector<float>& kept = rows.append();
    std::copy(row, row + rows.width(), kept.begin());
    if (level > 0 && y > 0) boundCellRow(level, y - 1);
    if (level < m_layout.rootLevel() && y % 2 == 0) {
      std::vector<float>& coarse = m_scratchRow;
      coarse.resize(std::size_t(m_rows[std::size_t(level) + 1].width()));
      for (std::size_t x = 0; x < coarse.size(); ++x) coarse[x] = kept[2 * x];
      pushRow(level + 1, y / 2, coarse.data());
    }
  }

  // Cell row y of level L >= 1, from level L - 1's samples and cells under it. A level-L cell
  // covers 2 x 2 cells of level L - 1, whose triangulation refines the level-L one (every cell
  // is cut along the same diagonal), so |level L - 1 - level L| over the cell is largest at the
  // five level L - 1 samples the level-L cell does not share. Two bounds on |full resolution -
  // level L|: the finer cells' residual plus that gap, and the distance between the cell's
  // full-resolution range and its corners' range; the smaller is kept.
  void boundCellRow(int level, int y) {
    const LevelRows& rows = m_rows[std::size_t(level)];
    const LevelRows& finer = m_rows[std::size_t(level) - 1];
    const float* s0 = rows.row(y);
    const float* s1 = rows.row(y + 1);
    const float* f0 = finer.row(2 * y);
    const float* f1 = finer.row(2 * y + 1);
    const float* f2 = finer.row(2 * y + 2);
    const CellBound* c0 = level > 1 ? m_cells[std::size_t(level) - 1].row(2 * y) : nullptr;
    const CellBound* c1 = level > 1 ? m_cells[std::size_t(level) - 1].row(2 * y + 1) : nullptr;
    CellBound* out = m_cells[std::size_t(level)].append().data();
    auto body = [&](std::size_t begin, std::size_t end) {
      for (std::size_t x = begin; x < end; ++x) {
        const std::size_t i = 2 * x;
        const double a = s0[x], b = s0[x + 1], c = s1[x], d = s1[x + 1];
        const double gap = std::max({std::abs(f0[i + 1] - 0.5 * (a + b)), std::abs(f1[i] - 0.5 * (a + c)),
                                     std::abs(f1[i + 1] - 0.5 * (b + c)), std::abs(f1[i + 2] - 0.5 * (b + d)),
                                     std::abs(f2[i + 1] - 0.5 * (c + d))});
        double below = 0.0;
        float lo, hi;
        if (c0 == nullptr) {  // level 1: the finer level is the full resolution
          lo = std::min({f0[i], f0[i + 1], f0[i + 2], f1[i], f1[i + 1], f1[i + 2], f2[i], f2[i + 1], f2[i + 2]});
          hi = std::max({f0[i], f0[i + 1], f0[i + 2], f1[i], f1[i + 1], f1[i + 2], f2[i], f2[i + 1], f2[i + 2]});
        } else {
          const CellBound* under[4] = {&c0[i], &c0[i + 1], &c1[i], &c1[i + 1]};
          lo = under[0]->minHeight;
          hi = under[0]->maxHeight;
          for (const CellBound* u : under) {
            below = std::max(below, double(u->residual));
            lo = std::min(lo, u->minHeight);
            hi = std::max(hi, u->maxHeight);
          }
        }
        const double cornersLo = std::min({a, b, c, d}), cornersHi = std::max({a, b, c, d});
        const double byRange = std::max(double(hi) - cornersLo, cornersHi - double(lo));
        out[x] = CellBound{roundUp(std::min(below + gap, byRange)), lo, hi};
      }
    };
    const std::size_t cells = std::size_t(m_cells[std::size_t(level)].width());
    if (m_options.pool != nullptr)
      m_options.pool->forRanges(cells, 4096, body);
    else
      body(0, cells);
  }

  bool ready(int level) const {
    const int by = m_nextRow[std::size_t(level)];
    if (by >= m_layout.nodesY(level)) return false;
    const int pitch = m_layout.pitch();
    const int lastRow = std::min(pitch * by + pitch, m_levelHeight[std::size_t(level)] - 1);
    if (m_rows[std::size_t(level)].end() <= lastRow) return false;
    if (level == 0) return true;
    const int finer = level - 1;  // the children's ranges
    return m_nextRow[std::size_t(finer)] >= std::min(2 * by + 2, m_layout.nodesY(finer));
  }

  Status finishReadyNodes() {
    for (bool progressed = true; progressed;) {
      progressed = false;
      for (int level = 0; level <= m_layout.rootLevel(); ++level) {
        while (ready(level)) {
          if (Status done = finishNodeRow(level, m_nextRow[std::size_t(level)]); !done) return done;
          ++m_nextRow[std::size_t(level)];
          progressed = true;
        }
      }
    }
    // Level L's sample and cell rows from pitch * (next row of L) on are still needed by its
    // nodes, the last two of each by the cells of L + 1 still to come.
    const int pitch = m_layout.pitch();
    for (int level = 0; level <= m_layout.rootLevel(); ++level) {
      const int nodesFrom = pitch * m_nextRow[std::size_t(level)];
      auto& samples = m_rows[std::size_t(level)];
      auto& cells = m_cells[std::size_t(level)];
      samples.dropBelow(std::min(nodesFrom, samples.end() - 2));
      cells.dropBelow(std::min(nodesFrom, cells.end() - 2));
    }
    return {};
  }

  std::size_t index(const NodeId& node) const {
    return std::size_t(m_levelOffset[node.level]) + std::size_t(node.by) * std::size_t(m_layout.nodesX(node.level)) +
           node.bx;
  }

  // Everything but the dikes' bound of node (level, bx, by), and its tile written.
  Status finishNode(const NodeId& node, std::vector<unsigned char>& slot, Heightfield& tile,
                    std::vector<float>& residual) {
    const LevelRows& rows = m_rows[node.level];
    const int pitch = m_layout.pitch();
    const int c0 = pitch * int(node.bx), r0 = pitch * int(node.by);
    const int columns = std::min(pitch + 1, rows.width() - c0);
    const int tileRows = std::min(pitch + 1, m_levelHeight[node.level] - r0);
    const int stride = m_layout.stride(node);
    tile.width = columns;
    tile.height = tileRows;
    tile.spacingX = m_source.spacingX() * stride;
    tile.spacingY = m_source.spacingY() * stride;
    tile.heights.resize(std::size_t(columns) * std::size_t(tileRows));
    for (int j = 0; j < tileRows; ++j)
      std::copy_n(rows.row(r0 + j) + c0, columns, tile.heights.begin() + std::ptrdiff_t(j) * columns);

    PyramidNode& data = m_nodes[index(node)];
    const std::size_t cellCount =
        columns >= 2 && tileRows >= 2 ? std::size_t(columns - 1) * std::size_t(tileRows - 1) : 0;
    residual.assign(cellCount, 0.0f);
    if (node.level == 0) {
      const auto [lo, hi] = std::minmax_element(tile.heights.begin(), tile.heights.end());
      data.minHeight = *lo;
      data.maxHeight = *hi;
    } else {
      float lo = kInfinity, hi = -kInfinity;
      for (int quadrant = 0; quadrant < 4; ++quadrant) {
        const NodeId child = node.child(quadrant);
        if (!m_layout.exists(child)) continue;
        const PyramidNode& c = m_nodes[index(child)];
        lo = std::min(lo, c.minHeight);
        hi = std::max(hi, c.maxHeight);
      }
      data.minHeight = lo;
      data.maxHeight = hi;
      const RowWindow<CellBound>& cells = m_cells[node.level];
      for (int j = 0; j + 1 < tileRows; ++j) {
        const CellBound* row = cells.row(r0 + j) + c0;
        for (int i = 0; i + 1 < columns; ++i)
          residual[std::size_t(j) * std::size_t(columns - 1) + std::size_t(i)] = row[i].residual;
      }
    }
    std::fill(slot.begin(), slot.end(), 0);
    data.residual = encodeResiduals(residual, slot.data() + tileResidualAt(m_layout.k()));
    data.lodError = kInfinity;  // not drawable at its stride: always refined
    data.floorError = kInfinity;
    if (cellCount > 0) {
      auto lod = BlockLod::buildFromLevel(tile, m_layout.interior(node), residual);
      if (!lod) return lod.error();
      data.lodError = lod->maxError();
      data.floorError = lod->floorError();
    }

    put<std::uint32_t>(slot.data(), 4, std::uint32_t(index(node)));
    put<std::uint16_t>(slot.data(), 8, std::uint16_t(columns));
    put<std::uint16_t>(slot.data(), 10, std::uint16_t(tileRows));
    std::memcpy(slot.data() + kPyramidTileHeaderBytes, tile.heights.data(), tile.heights.size() * sizeof(float));
    put<std::uint32_t>(slot.data(), 0, core::crc32c(slot.data() + 4, slot.size() - 4));
    return writeExactly(m_fd, slot.data(), slot.size(), m_tilesOffset + index(node) * std::uint64_t(slot.size()),
                        m_path);
  }

  Status finishNodeRow(int level, int by) {
    const int columns = m_layout.nodesX(level);
    std::mutex failureMutex;
    int failedAt = columns;  // the westernmost failure, so the error reported does not depend on threads
    Error failure;
    auto body = [&](std::size_t begin, std::size_t end) {
      Status status;
      std::size_t bx = begin;
      try {
        std::vector<unsigned char> slot(tileSlotBytes(m_layout.k()));
        Heightfield tile;
        std::vector<float> residual;
        for (; bx < end && status; ++bx)
          status = finishNode(NodeId{std::uint8_t(level), std::uint32_t(bx), std::uint32_t(by)}, slot, tile, residual);
        if (!status) --bx;
      } catch (const std::bad_alloc&) {
        status = makeError(ErrorKind::OutOfMemory, m_path.string() + ": no memory for a node");
      }
      if (!status) {
        std::lock_guard<std::mutex> lock(failureMutex);
        if (int(bx) < failedAt) {
          failedAt = int(bx);
          failure = status.error();
        }
      }
    };
    if (m_options.pool != nullptr)
      m_options.pool->forRanges(std::size_t(columns), 16, body);
    else
      body(0, std::size_t(columns));
    if (failedAt < columns) return failure;

    // The dikes' bound: the range over dikeBoundRegion, which is the union of the footprints
    // of the node and of its west, south and south-west neighbours.
    for (int bx = 0; bx < columns; ++bx) {
      PyramidNode& data = m_nodes[index(NodeId{std::uint8_t(level), std::uint32_t(bx), std::uint32_t(by)})];
      float lo = data.minHeight, hi = data.maxHeight;
      for (const auto& [dx, dy] : {std::pair{-1, 0}, std::pair{0, -1}, std::pair{-1, -1}}) {
        if (bx + dx < 0 || by + dy < 0) continue;
        const PyramidNode& n =
            m_nodes[index(NodeId{std::uint8_t(level), std::uint32_t(bx + dx), std::uint32_t(by + dy)})];
        lo = std::min(lo, n.minHeight);
        hi = std::max(hi, n.maxHeight);
      }
      data.dikeRange = roundUp(double(hi) - double(lo));
    }
    return {};
  }

  HeightRows& m_source;
  const BlockLayout& m_layout;
  const PyramidBuildOptions& m_options;
  int m_fd;
  const std::filesystem::path& m_path;
  std::uint64_t m_tilesOffset;
  std::uint64_t m_nodeCount = 0;
  std::vector<std::uint64_t> m_levelOffset;
  std::vector<LevelRows> m_rows;
  std::vector<RowWindow<CellBound>> m_cells;  // level 0's stays empty: its residuals are 0
  std::vector<int> m_levelHeight;
  std::vector<int> m_nextRow;  // the next row of nodes each level finishes
  std::vector<PyramidNode> m_nodes;
  std::vector<float> m_east, m_north;
  std::vector<float> m_scratchRow;
  float m_min = kInfinity, m_max = -kInfinity;
};

}  // namespace

Result<PyramidBuildReport> buildPyramid(HeightRows& source, const std::filesystem::path& out,
                                        const PyramidBuildOptions& options) {
  if (options.k < 1 || options.k > 7)
    return makeError(ErrorKind::InvalidArgument, "--block: blocks must be 2^k + 1 samples with k in 1..7");
  if (!(std::isfinite(source.spacingX()) && source.spacingX() > 0.0 && std::isfinite(source.spacingY()) &&
        source.spacingY() > 0.0))
    return makeError(ErrorKind::InvalidArgument, "buildPyramid: the source's spacing must be positive");
  const std::string name = options.sourceName.empty() ? "the source" : options.sourceName;
  auto layout = BlockLayout::create(source.width(), source.height(), options.k);
  if (!layout) return makeError(ErrorKind::InvalidArgument, name + ": " + layout.error().message);

  std::uint64_t nodes = 0;
  for (int level = 0; level <= layout->rootLevel(); ++level)
    nodes += std::uint64_t(layout->nodesX(level)) * std::uint64_t(layout->nodesY(level));
  const std::uint64_t nodesOffset = kPyramidHeaderBytes;
  const std::uint64_t borderOffset = nodesOffset + nodeTableBytes(nodes);
  const std::uint64_t tilesOffset =
      (borderOffset + borderBytes(layout->width(), layout->height()) + 4095) / 4096 * 4096;
  const std::uint32_t slotBytes = tileSlotBytes(options.k);
  const std::uint64_t fileBytes = tilesOffset + nodes * slotBytes;
  core::PartialFile file(out);
  if (Status created = file.create(fileBytes, true); !created) return created.error();

  Builder writer(source, *layout, options, file.fd(), out, tilesOffset);
  if (Status built = writer.run(); !built) return built.error();

  // Node table and its CRCs, border, then the header without its magic; the magic last.
  const auto& table = writer.nodes();
  if (Status w = writeExactly(file.fd(), table.data(), table.size() * sizeof(PyramidNode), nodesOffset, out); !w)
    return w.error();
  const std::size_t chunks = (nodes + kPyramidNodeChunk - 1) / kPyramidNodeChunk;
  std::vector<std::uint32_t> crcs(chunks);
  for (std::size_t chunk = 0; chunk < chunks; ++chunk) {
    const std::size_t first = chunk * kPyramidNodeChunk;
    crcs[chunk] = core::crc32c(table.data() + first,
                               std::min<std::size_t>(kPyramidNodeChunk, nodes - first) * sizeof(PyramidNode));
  }
  if (Status w = writeExactly(file.fd(), crcs.data(), chunks * 4, nodesOffset + nodes * sizeof(PyramidNode), out); !w)
    return w.error();
  std::uint64_t at = borderOffset;
  for (const auto* border : {&writer.eastBorder(), &writer.northBorder()}) {
    const std::size_t size = border->size() * sizeof(float);
    const std::uint32_t crc = core::crc32c(border->data(), size);
    if (Status w = writeExactly(file.fd(), border->data(), size, at, out); !w) return w.error();
    if (Status w = writeExactly(file.fd(), &crc, 4, at + size, out); !w) return w.error();
    at += size + 4;
  }

  unsigned char header[kPyramidHeaderBytes] = {};
  put<std::uint32_t>(header, kVersionAt, kPyramidVersion);
  put<std::uint32_t>(header, kHeaderBytesAt, std::uint32_t(kPyramidHeaderBytes));
  put<std::int32_t>(header, kWidthAt, layout->width());
  put<std::int32_t>(header, kHeightAt, layout->height());
  put<double>(header, kSpacingXAt, source.spacingX());
  put<double>(header, kSpacingYAt, source.spacingY());
  put<std::int32_t>(header, kKAt, options.k);
  put<std::int32_t>(header, kRootLevelAt, layout->rootLevel());
  put<float>(header, kMinAt, writer.minHeight());
  put<float>(header, kMaxAt, writer.maxHeight());
  put<std::uint64_t>(header, kNodeCountAt, nodes);
  put<std::uint64_t>(header, kNodesOffsetAt, nodesOffset);
  put<std::uint64_t>(header, kBorderOffsetAt, borderOffset);
  put<std::uint64_t>(header, kTilesOffsetAt, tilesOffset);
  put<std::uint32_t>(header, kTileSlotAt, slotBytes);
  put<std::uint32_t>(header, kTileSideAt, tileSide(options.k));
  put<std::uint64_t>(header, kFileBytesAt, fileBytes);
  const std::size_t sourceLength = std::min(options.sourceName.size(), kMaxSourceBytes);
  put<std::uint32_t>(header, kSourceLengthAt, std::uint32_t(sourceLength));
  std::memcpy(header + kSourceAt, options.sourceName.data(), sourceLength);
  put<std::uint32_t>(header, kCrcAt, core::crc32c(header + kVersionAt, kCrcAt - kVersionAt));
  if (Status w = writeExactly(file.fd(), header, sizeof header, 0, out); !w) return w.error();
  if (::fdatasync(file.fd()) != 0) return ioError(out, "sync");
  if (Status w = writeExactly(file.fd(), kPyramidMagic, sizeof kPyramidMagic, 0, out); !w) return w.error();
  if (Status committed = file.commit(); !committed) return committed.error();
  if (options.progress) options.progress(1.0f);
  return PyramidBuildReport{nodes, fileBytes, writer.minHeight(), writer.maxHeight()};
}

}  // namespace polder::terrain
