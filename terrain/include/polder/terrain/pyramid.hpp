// A terrain pyramid: a DEM prepared for streaming (docs/streaming.md). It holds every node of
// the block quadtree (block_layout.hpp, block_quadtree.hpp) as a tile of its own strided
// samples, with the node's height range and error bounds, so that a node can be loaded and
// drawn from its tile alone, without the full resolution: `polder prep` writes it
// (pyramid_build.hpp), the terrain engine streams from it.
//
// Levels. Level L's surface is the DEM sampled every s = 2^L samples, cut as heightfield.hpp
// cuts cells. A node's tile holds its footprint's samples of that surface: (2^k + 2)^2, its
// interior and the first column and row beyond (its dike strips' far side), fewer where the
// DEM ends. Each cell of a tile carries a residual, a bound on how far the full-resolution
// surface lies from the level surface over the cell, and the node's residual is the largest of
// its cells'; BlockLod::buildFromLevel turns a tile and its cells' residuals into an error
// hierarchy whose errors bound the full-resolution ones.
//
// The file (all little-endian):
//   header   kHeaderBytes at offset 0: magic "PLDRPYR1", version, sizes, spacing, k, levels,
//            the offsets and sizes of the sections below, the source's name; CRC-32C of the
//            header in its last 4 bytes. The magic is written last, after everything else is
//            on disk, and the file is renamed into place only then: a prep that dies leaves
//            nothing that opens.
//   nodes    one PyramidNode record (24 bytes) per node, levels finest first, rows south
//            first (BlockQuadtree's order), then one CRC-32C per kNodeChunk records.
//   border   the DEM's east column (x = width - 1) and north row (y = height - 1) at full
//            resolution, the samples the dikes use along the border, each followed by its
//            CRC-32C.
//   tiles    one slot of tileSlotBytes per node in node order: CRC-32C of the rest of the slot,
//            the node's index, columns and rows, then the samples, row-major, south row first,
//            in room for tileSide^2; then the cells' residuals: a float step and one byte per
//            cell, row-major, the residual at most byte * step (rounded up when written).
// Every read checks the CRC of what it read: corruption is an error, never a height.
//
// Threads: an open Pyramid is immutable; readTile() may run on any number of threads at once.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <polder/result.hpp>
#include <polder/terrain/block_layout.hpp>
#include <polder/terrain/heightfield.hpp>

namespace polder::terrain {

static_assert(std::endian::native == std::endian::little, "pyramid files are little-endian");

inline constexpr char kPyramidMagic[8] = {'P', 'L', 'D', 'R', 'P', 'Y', 'R', '1'};
inline constexpr std::uint32_t kPyramidVersion = 2;
inline constexpr std::size_t kPyramidHeaderBytes = 4096;
inline constexpr std::size_t kPyramidNodeChunk = 4096;  // node records per CRC
inline constexpr std::size_t kPyramidTileHeaderBytes = 16;

// What the pyramid knows of one node: the block quadtree's NodeInfo (block_quadtree.hpp), from
// the levels instead of the full resolution.
struct PyramidNode {
  float minHeight = 0.0f;  // exact range of the full-resolution samples of the footprint
  float maxHeight = 0.0f;
  float lodError = 0.0f;    // the coarsest mesh's error bound; +inf when not drawable at its stride
  float floorError = 0.0f;  // the finest mesh's error bound (at least the residual); +inf likewise
  float dikeRange = 0.0f;   // height range of dikeBoundRegion (dike_errors.hpp): bounds its dikes
  float residual = 0.0f;    // bound on |full resolution - level surface| over the footprint
};
static_assert(sizeof(PyramidNode) == 24);

struct PyramidHeader {
  int width = 0;  // full-resolution samples
  int height = 0;
  double spacingX = 1.0;  // metres
  double spacingY = 1.0;
  int k = 5;  // blocks of 2^k + 1 samples
  int rootLevel = 0;
  float minHeight = 0.0f;  // the whole DEM
  float maxHeight = 0.0f;
  std::uint64_t nodeCount = 0;
  std::uint64_t nodesOffset = 0;
  std::uint64_t borderOffset = 0;
  std::uint64_t tilesOffset = 0;
  std::uint32_t tileSlotBytes = 0;
  std::uint32_t tileSide = 0;  // 2^k + 2
  std::uint64_t fileBytes = 0;
  std::string source;  // the DEM it was prepared from (file name), for `polder info`
};

// One node's tile: its footprint's samples at its stride, vertex (i, j) of the node's
// interior at samples.at(i, j); spacing stride times the DEM's.
struct PyramidTile {
  NodeId node;
  Heightfield samples;
  // Per cell of `samples` ((width - 1) x (height - 1), row-major, south row first): a bound on
  // |full resolution - level surface| over the cell; all 0 at level 0.
  std::vector<float> cellResidual;
};

class Pyramid {
 public:
  // Opens and checks the header, the node table and the border (read into memory). Io when the
  // file cannot be read; InvalidData (naming the file) when it is not a complete pyramid: bad
  // magic or version, a CRC that does not match, a size that disagrees with the header.
  static Result<std::unique_ptr<Pyramid>> open(const std::filesystem::path& path);
  ~Pyramid();
  Pyramid(const Pyramid&) = delete;
  Pyramid& operator=(const Pyramid&) = delete;

  const std::filesystem::path& path() const { return m_path; }
  const PyramidHeader& header() const { return m_header; }
  const BlockLayout& layout() const { return m_layout; }
  std::size_t nodeIndex(const NodeId& node) const;  // asserts that it exists
  const PyramidNode& node(const NodeId& node) const { return m_nodes[nodeIndex(node)]; }
  std::span<const PyramidNode> nodes() const { return m_nodes; }
  // Full-resolution border samples: eastBorder()[y] = height at (width - 1, y), northBorder()[x]
  // at (x, height - 1).
  std::span<const float> eastBorder() const { return m_eastBorder; }
  std::span<const float> northBorder() const { return m_northBorder; }

  // Reads one node's tile into `out` (its storage reused). Io on a read error, InvalidData
  // (naming the file and node) when the slot is short, its CRC does not match, or it is not
  // that node's.
  Status readTile(const NodeId& node, PyramidTile& out) const;

  // Bytes this object keeps in memory.
  std::size_t memoryBytes() const;

 private:
  Pyramid() = default;
  std::filesystem::path m_path;
  int m_fd = -1;
  PyramidHeader m_header;
  BlockLayout m_layout;
  std::vector<std::size_t> m_levelOffset;
  std::vector<PyramidNode> m_nodes;
  std::vector<float> m_eastBorder;
  std::vector<float> m_northBorder;
};

// True when the file at `path` starts with a pyramid's magic (it may still fail to open).
bool looksLikePyramid(const std::filesystem::path& path);

// The full-resolution heightfield, from the level-0 tiles (whose footprints cover the DEM):
// for commands that work on the whole field in memory. OutOfMemory when it does not fit;
// the tiles' own errors as readTile gives them. `progress` as elsewhere, 0..1.
Result<Heightfield> readFullResolution(const Pyramid& pyramid, const std::function<void(float)>& progress = {});

// The full resolution over `window` (inclusive sample bounds, row 0 south), at least 2 x 2
// inside the DEM, from the level-0 tiles that overlap it only. InvalidArgument for a window
// outside; otherwise as readFullResolution.
Result<Heightfield> readWindow(const Pyramid& pyramid, const SampleRect& window,
                               const std::function<void(float)>& progress = {});

// The samples of level `level` per side: floor((samples - 1) / 2^level) + 1.
inline int levelSamples(int samples, int level) { return (samples - 1) / (1 << level) + 1; }

}  // namespace polder::terrain
