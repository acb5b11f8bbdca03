// What one terrain frame hands a host: the pieces to draw, with their lifetimes, and the
// frame's figures (docs/design.md, "Block lifetimes").
//
// The contract. Every frame lists its drawable pieces: one per visible block, and the dike
// triangles in pieces, one per node that owns some of the frame's visible dike triangles
// (terrain/dikes.hpp, DikeMesh::owners). A piece has a key, stable across frames, and a
// version that changes only when its geometry changes: for a block, when the LOD cache
// rebuilds its mesh into a different one; for dikes, when the triangles the node owns differ from last frame's
// (a neighbour on either side changed). `created`, `changed` and `retired` say what happened
// since the previous frame:
//   - created: pieces not in the previous frame (prepare GPU data for them);
//   - changed: pieces whose version differs (replace their GPU data);
//   - retired: keys of the previous frame's pieces that are gone (free their GPU data).
// Everything else is as it was, so a host keeps one GPU buffer per piece and uploads only
// what was created or changed; a frame where nothing changed uploads nothing.
//
// A piece's vertex data (GridMeshView, polder/grid_mesh.hpp) is produced once per version
// and stays valid and unchanged until the update that changes or retires the piece. Its
// positions are integer sample offsets from the piece's anchor, so vertices shared by two
// pieces reach the rasteriser bit-identical when drawn as grid_mesh.hpp says.
#pragma once

#include <compare>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <polder/grid_mesh.hpp>
#include <polder/terrain/block_layout.hpp>
#include <polder/terrain/block_mesh.hpp>
#include <polder/terrain/dikes.hpp>

namespace polder {

enum class TerrainPieceKind : std::uint8_t { Block, Dikes };

// A piece's identity across frames: its kind and its node.
struct TerrainPieceKey {
  std::uint64_t value = 0;
  friend auto operator<=>(const TerrainPieceKey&, const TerrainPieceKey&) = default;
};

inline TerrainPieceKey terrainPieceKey(TerrainPieceKind kind, const terrain::NodeId& node) {
  return TerrainPieceKey{(std::uint64_t(kind) << 63) | terrain::nodeKey(node)};
}

struct TerrainPiece {
  TerrainPieceKey key;
  TerrainPieceKind kind = TerrainPieceKind::Block;
  terrain::NodeId node;       // the block, or the node that owns these dike triangles
  std::uint64_t version = 0;  // unique over the engine's life: a new one per change
  GridMeshView mesh;          // valid until the update that changes or retires the piece
};

struct TerrainFrameStats {
  std::size_t visibleBlocks = 0;
  std::size_t culledBlocks = 0;
  std::size_t blockTriangles = 0;
  std::size_t dikeTriangles = 0;
  double selectMs = 0.0;
  double lodMs = 0.0;
  double dikesMs = 0.0;
  double piecesMs = 0.0;  // host-ready vertex data of the created and changed pieces
  double totalMs = 0.0;
  // Visible blocks drawn in place of finer ones whose data are not resident yet (BlockLoading::
  // Background); a frame with any is coarser than tau asks, its error reported apart.
  std::size_t blocksOnAncestor = 0;
  std::size_t loadsArrived = 0;    // hierarchies that became resident at the start of this frame
  std::size_t loadsRequested = 0;  // blocks this frame asked the loaders for
  std::uint64_t cacheLookups = 0;  // this frame
  std::uint64_t cacheHits = 0;
  std::uint64_t cacheRebuilds = 0;
  // Error mode's dike check: the largest projected error of a drawn dike triangle (an upper
  // bound, pixels) and how many drawn dike triangles stay over tau.
  double dikeErrorPx = 0.0;
  std::size_t dikeTrianglesOverTau = 0;
  // Nodes this frame split where pins could not bring a coarse dike strip within tau.
  std::size_t dikeSplits = 0;
  // False when no block of the cut changed, so the last frame's dikes were kept as they were.
  bool dikesStitched = false;
  // Piece lifetimes since the last frame, and the bytes of vertex and index data the created
  // and changed pieces carry (what a host uploads).
  std::size_t piecesCreated = 0;
  std::size_t piecesChanged = 0;
  std::size_t piecesRetired = 0;
  std::size_t pieceBytesProduced = 0;
  std::size_t triangles() const { return blockTriangles + dikeTriangles; }
};

struct TerrainBlockDraw {
  terrain::NodeId node;
  const terrain::BlockMesh* mesh = nullptr;  // valid until the next update()
};

// The dike triangles to draw: those touching a visible block, in global full-resolution
// sample coordinates, counter-clockwise seen from above.
struct TerrainDikes {
  std::span<const terrain::DikeVertex> vertices;
  std::span<const std::uint32_t> indices;
};

struct TerrainFrame {
  std::vector<TerrainBlockDraw> blocks;  // visible blocks only, in the grid's own terms
  TerrainDikes dikes;

  std::span<const TerrainPiece> pieces;      // everything to draw: blocks first, then dikes
  std::span<const std::uint32_t> created;    // indices into pieces
  std::span<const std::uint32_t> changed;    // indices into pieces
  std::span<const TerrainPieceKey> retired;  // keys of the last frame's pieces now gone

  TerrainFrameStats stats;
};

}  // namespace polder
