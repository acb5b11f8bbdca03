// The frame's drawable pieces and their lifetimes (polder/terrain_frame.hpp): which pieces
// are new, which changed, which are gone, and each piece's host-ready vertex data, made once
// per version.
//
// Blocks are compared by their mesh's revision (the LOD cache numbers its builds), so an
// unchanged block costs one table lookup; a rebuilt one by a hash of its geometry, so a
// rebuild that gives the same mesh keeps the version. Dike pieces are compared by a hash of the
// triangles their node owns, independent of the triangles' order and of where each starts;
// only a piece whose hash differs is rebuilt. Storage (records, vertex data, tables) is kept
// and recycled, so once frames stop growing the pieces allocate nothing.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <polder/terrain/block_layout.hpp>
#include <polder/terrain/block_mesh.hpp>
#include <polder/terrain/dikes.hpp>
#include <polder/terrain/heightfield.hpp>
#include <polder/terrain_frame.hpp>

#include "sample_grid.hpp"

namespace polder {

class TerrainPieces {
 public:
  TerrainPieces(GridSpacing spacing, const terrain::BlockLayout& layout);
  ~TerrainPieces();
  TerrainPieces(const TerrainPieces&) = delete;
  TerrainPieces& operator=(const TerrainPieces&) = delete;

  // Room for frames of up to `maxPieces` pieces.
  void reserve(std::size_t maxPieces);

  // One frame: begin, add every visible block and the visible dike triangles, finish.
  void beginFrame();
  // `samples` holds the block's vertices.
  void addBlock(const terrain::NodeId& node, const terrain::BlockMesh& mesh, const SampleGrid& samples);
  // The visible dike triangles (three indices into `vertices` each) and, per triangle, the
  // node of the cut that owns it; `samples` holds the vertices.
  void addDikes(std::span<const terrain::DikeVertex> vertices, std::span<const std::uint32_t> indices,
                std::span<const std::uint32_t> owners, std::span<const terrain::NodeId> ownerNodes,
                const DikeVertexSamples& samples);
  // The last frame's dike pieces as they were: for a frame whose dikes were not stitched
  // again (DikeStage::stitch kept them), so the same triangles need no hashing.
  void keepDikes();
  void finishFrame();

  std::span<const TerrainPiece> pieces() const { return m_pieces; }
  std::span<const std::uint32_t> created() const { return m_created; }
  std::span<const std::uint32_t> changed() const { return m_changed; }
  std::span<const TerrainPieceKey> retired() const { return m_retired; }
  std::size_t bytesProduced() const { return m_bytesProduced; }  // this frame

 private:
  struct Record;
  class KeyIndex;

  // The record for `key`, marked as used this frame; `fresh` when it had none.
  std::uint32_t touch(TerrainPieceKey key, bool& fresh);
  void publish(std::uint32_t record, bool fresh, bool rebuilt);
  void buildBlock(Record& record, const terrain::BlockMesh& mesh, const SampleGrid& samples);
  void buildDikes(Record& record, std::span<const terrain::DikeVertex> vertices, std::span<const std::uint32_t> indices,
                  std::span<const std::uint32_t> triangles, const DikeVertexSamples& samples);
  terrain::DikeVertex anchorOf(const terrain::NodeId& node) const;

  GridSpacing m_spacing;
  terrain::BlockLayout m_layout;
  std::vector<std::unique_ptr<Record>> m_records;  // stable addresses: pieces point into them
  std::vector<std::uint32_t> m_freeRecords;
  std::unique_ptr<KeyIndex> m_index;
  std::vector<std::uint32_t> m_live;             // records of the last finished frame
  std::vector<std::uint32_t> m_dikeRecords;      // this frame's dike pieces, in order
  std::vector<std::uint32_t> m_lastDikeRecords;  // the last finished frame's
  std::uint64_t m_frame = 0;
  std::uint64_t m_nextVersion = 1;

  std::vector<TerrainPiece> m_pieces;
  std::vector<std::uint32_t> m_pieceRecords;  // parallel to m_pieces
  std::vector<std::uint32_t> m_created;
  std::vector<std::uint32_t> m_changed;
  std::vector<TerrainPieceKey> m_retired;
  std::size_t m_bytesProduced = 0;

  // addDikes' scratch: triangles grouped by owner, and a vertex table for welding a piece's
  // triangle corners.
  std::vector<std::uint32_t> m_ownerStart;
  std::vector<std::uint32_t> m_byOwner;
  struct WeldSlot {
    std::uint64_t key = 0;
    std::uint32_t stamp = 0;
    std::uint32_t vertex = 0;
  };
  std::vector<WeldSlot> m_weld;
  std::uint32_t m_weldStamp = 0;
};

}  // namespace polder
