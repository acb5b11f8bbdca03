#include "terrain_pieces.hpp"

#include <algorithm>
#include <cassert>
#include <utility>

#include <polder/mix_bits.hpp>

namespace polder {

namespace {

constexpr std::uint32_t kNoRecord = 0xffffffffu;

std::uint64_t packSample(std::int64_t x, std::int64_t y) {
  return (std::uint64_t(std::uint32_t(x)) << 32) | std::uint32_t(y);
}

GridMeshVertex gridVertex(const SampleGrid& samples, int x, int y, const terrain::DikeVertex& anchor) {
  const glm::vec3 n = samples.normal(x, y);
  GridMeshVertex v;
  v.x = float(x - anchor.x);
  v.y = float(y - anchor.y);
  v.z = samples.height(x, y);
  v.nx = snorm8(n.x);
  v.ny = snorm8(n.y);
  v.nz = snorm8(n.z);
  return v;
}

// A triangle's hash, the same whichever corner it starts at (the winding is kept).
std::uint64_t triangleHash(const terrain::DikeVertex& a, const terrain::DikeVertex& b, const terrain::DikeVertex& c) {
  std::uint64_t k[3] = {packSample(a.x, a.y), packSample(b.x, b.y), packSample(c.x, c.y)};
  const int first = k[0] <= k[1] && k[0] <= k[2] ? 0 : (k[1] <= k[2] ? 1 : 2);
  std::rotate(k, k + first, k + 3);
  return mixBits(mixBits(mixBits(k[0]) ^ k[1]) ^ k[2]);
}

// A block mesh's geometry, hashed: a rebuild that gives the same mesh keeps its version.
std::uint64_t blockHash(const terrain::BlockMesh& mesh) {
  std::uint64_t h =
      mixBits(packSample(mesh.footprint.x0, mesh.footprint.y0) ^ std::uint64_t(mesh.footprint.stride) << 20);
  for (const terrain::GridVertex& v : mesh.vertices) h = mixBits(h ^ (std::uint64_t(v.i) << 16 | v.j));
  for (const std::uint32_t index : mesh.indices) h = mixBits(h ^ index);
  return h;
}

}  // namespace

struct TerrainPieces::Record {
  TerrainPieceKey key;
  TerrainPieceKind kind = TerrainPieceKind::Block;
  terrain::NodeId node;
  std::uint64_t version = 0;
  std::uint64_t source = 0;    // block: its mesh's revision; dikes: hash of the owned triangles
  std::uint64_t geometry = 0;  // block: blockHash of that mesh
  std::uint64_t lastFrame = 0;
  terrain::DikeVertex anchor;
  std::vector<GridMeshVertex> vertices;
  std::vector<std::uint32_t> indices;
};

// Piece key -> record, open addressing with linear probing; erasing shifts the run back, so
// there are no tombstones and lookups stay short however long the engine runs.
class TerrainPieces::KeyIndex {
 public:
  void reserve(std::size_t keys) {
    std::size_t capacity = 16;
    while (capacity < 2 * keys) capacity *= 2;
    if (capacity <= m_slots.size()) return;
    std::vector<Slot> old = std::move(m_slots);
    m_slots.assign(capacity, Slot{});
    for (const Slot& slot : old)
      if (slot.record != kNoRecord) insert(slot.key, slot.record);
  }
  std::uint32_t find(TerrainPieceKey key) const {
    for (std::size_t i = home(key);; i = next(i)) {
      if (m_slots[i].record == kNoRecord) return kNoRecord;
      if (m_slots[i].key == key) return m_slots[i].record;
    }
  }
  void insert(TerrainPieceKey key, std::uint32_t record) {
    if (2 * (m_size + 1) > m_slots.size()) reserve(m_size + 1);
    std::size_t i = home(key);
    while (m_slots[i].record != kNoRecord) i = next(i);
    m_slots[i] = Slot{key, record};
    ++m_size;
  }
  void erase(TerrainPieceKey key) {
    std::size_t i = home(key);
    while (m_slots[i].key != key || m_slots[i].record == kNoRecord) {
      assert(m_slots[i].record != kNoRecord && "TerrainPieces::KeyIndex::erase: key absent");
      i = next(i);
    }
    // Move later members of the run back into the hole where their home allows.
    for (std::size_t j = next(i);; j = next(j)) {
      if (m_slots[j].record == kNoRecord) break;
      const std::size_t h = home(m_slots[j].key);
      const bool between = i <= j ? (i < h && h <= j) : (i < h || h <= j);
      if (between) continue;
      m_slots[i] = m_slots[j];
      i = j;
    }
    m_slots[i] = Slot{};
    --m_size;
  }

 private:
  struct Slot {
    TerrainPieceKey key;
    std::uint32_t record = kNoRecord;
  };
  std::size_t home(TerrainPieceKey key) const { return std::size_t(mixBits(key.value)) & (m_slots.size() - 1); }
  std::size_t next(std::size_t i) const { return (i + 1) & (m_slots.size() - 1); }

  std::vector<Slot> m_slots = std::vector<Slot>(16);
  std::size_t m_size = 0;
};

TerrainPieces::TerrainPieces(GridSpacing spacing, const terrain::BlockLayout& layout)
    : m_spacing(spacing), m_layout(layout), m_index(std::make_unique<KeyIndex>()) {}

TerrainPieces::~TerrainPieces() = default;

void TerrainPieces::reserve(std::size_t maxPieces) {
  m_index->reserve(2 * maxPieces);  // a frame's pieces and the last frame's, being retired
  m_records.reserve(2 * maxPieces);
  m_freeRecords.reserve(2 * maxPieces);
  m_live.reserve(2 * maxPieces);
  m_dikeRecords.reserve(2 * maxPieces);
  m_lastDikeRecords.reserve(2 * maxPieces);
  m_pieces.reserve(2 * maxPieces);
  m_pieceRecords.reserve(2 * maxPieces);
  m_created.reserve(2 * maxPieces);
  m_changed.reserve(2 * maxPieces);
  m_retired.reserve(2 * maxPieces);
}

void TerrainPieces::beginFrame() {
  ++m_frame;
  m_pieces.clear();
  m_pieceRecords.clear();
  m_created.clear();
  m_changed.clear();
  m_retired.clear();
  m_dikeRecords.clear();
  m_bytesProduced = 0;
}

std::uint32_t TerrainPieces::touch(TerrainPieceKey key, bool& fresh) {
  std::uint32_t index = m_index->find(key);
  fresh = index == kNoRecord;
  if (fresh) {
    if (!m_freeRecords.empty()) {
      index = m_freeRecords.back();
      m_freeRecords.pop_back();
    } else {
      index = std::uint32_t(m_records.size());
      m_records.push_back(std::make_unique<Record>());
      // Room for the finest mesh a block can have, which holds a piece of dikes too: grown
      // piece by piece instead, every record would in time grow to the largest piece it ever
      // held, and the records' memory would creep up for as long as the camera finds new ground.
      const std::size_t side = std::size_t(1) << m_layout.k();
      m_records.back()->vertices.reserve((side + 1) * (side + 1));
      m_records.back()->indices.reserve(6 * side * side);
    }
    m_records[index]->key = key;
    m_index->insert(key, index);
  }
  m_records[index]->lastFrame = m_frame;
  return index;
}

void TerrainPieces::publish(std::uint32_t index, bool fresh, bool rebuilt) {
  Record& record = *m_records[index];
  if (rebuilt) {
    record.version = m_nextVersion++;
    m_bytesProduced += record.vertices.size() * sizeof(GridMeshVertex) + record.indices.size() * sizeof(std::uint32_t);
  }
  const auto position = std::uint32_t(m_pieces.size());
  if (fresh) {
    m_created.push_back(position);
  } else if (rebuilt) {
    m_changed.push_back(position);
  }
  GridMeshView view;
  view.anchor = GridAnchor{record.anchor.x, record.anchor.y};
  view.spacing = m_spacing;
  view.vertices = record.vertices;
  view.indices = record.indices;
  m_pieces.push_back(TerrainPiece{record.key, record.kind, record.node, record.version, view});
  m_pieceRecords.push_back(index);
}

terrain::DikeVertex TerrainPieces::anchorOf(const terrain::NodeId& node) const {
  const terrain::SampleRect footprint = m_layout.footprint(node);
  return terrain::DikeVertex{footprint.x0, footprint.y0};
}

void TerrainPieces::addBlock(const terrain::NodeId& node, const terrain::BlockMesh& mesh, const SampleGrid& samples) {
  bool fresh = false;
  const std::uint32_t index = touch(terrainPieceKey(TerrainPieceKind::Block, node), fresh);
  Record& record = *m_records[index];
  bool rebuilt = fresh;
  if (fresh || record.source != mesh.revision || mesh.revision == 0) {
    const std::uint64_t geometry = blockHash(mesh);
    rebuilt = fresh || geometry != record.geometry;
    record.source = mesh.revision;
    record.geometry = geometry;
  }
  if (rebuilt) {
    record.kind = TerrainPieceKind::Block;
    record.node = node;
    buildBlock(record, mesh, samples);
  }
  publish(index, fresh, rebuilt);
}

void TerrainPieces::buildBlock(Record& record, const terrain::BlockMesh& mesh, const SampleGrid& samples) {
  const terrain::BlockFootprint& footprint = mesh.footprint;
  record.anchor = terrain::DikeVertex{footprint.x0, footprint.y0};
  record.vertices.clear();
  for (const terrain::GridVertex& v : mesh.vertices)
    record.vertices.push_back(gridVertex(samples, footprint.x0 + v.i * footprint.stride,
                                         footprint.y0 + v.j * footprint.stride, record.anchor));
  record.indices.assign(mesh.indices.begin(), mesh.indices.end());
}

void TerrainPieces::addDikes(std::span<const terrain::DikeVertex> vertices, std::span<const std::uint32_t> indices,
                             std::span<const std::uint32_t> owners, std::span<const terrain::NodeId> ownerNodes,
                             const DikeVertexSamples& samples) {
  assert(indices.size() == 3 * owners.size() && "TerrainPieces::addDikes: one owner per triangle");
  // Group the triangles by owner (a counting sort over the cut).
  m_ownerStart.assign(ownerNodes.size() + 1, 0);
  for (const std::uint32_t owner : owners) ++m_ownerStart[owner + 1];
  for (std::size_t i = 1; i < m_ownerStart.size(); ++i) m_ownerStart[i] += m_ownerStart[i - 1];
  m_byOwner.resize(owners.size());
  for (std::size_t t = 0; t < owners.size(); ++t) m_byOwner[m_ownerStart[owners[t]]++] = std::uint32_t(t);
  for (std::size_t i = m_ownerStart.size() - 1; i > 0; --i) m_ownerStart[i] = m_ownerStart[i - 1];
  m_ownerStart[0] = 0;

  for (std::size_t owner = 0; owner < ownerNodes.size(); ++owner) {
    const std::span<const std::uint32_t> triangles(m_byOwner.data() + m_ownerStart[owner],
                                                   m_ownerStart[owner + 1] - m_ownerStart[owner]);
    if (triangles.empty()) continue;
    // Order-free summary of the owned triangles: sum and xor of their hashes, and their count.
    std::uint64_t sum = 0, xored = 0;
    for (const std::uint32_t t : triangles) {
      const std::uint64_t h =
          triangleHash(vertices[indices[3 * t]], vertices[indices[3 * t + 1]], vertices[indices[3 * t + 2]]);
      sum += h;
      xored ^= mixBits(h);
    }
    const std::uint64_t summary = mixBits(sum ^ mixBits(xored + triangles.size()));

    bool fresh = false;
    const std::uint32_t index = touch(terrainPieceKey(TerrainPieceKind::Dikes, ownerNodes[owner]), fresh);
    Record& record = *m_records[index];
    const bool rebuilt = fresh || record.source != summary;
    if (rebuilt) {
      record.kind = TerrainPieceKind::Dikes;
      record.node = ownerNodes[owner];
      record.source = summary;
      buildDikes(record, vertices, indices, triangles, samples);
    }
    publish(index, fresh, rebuilt);
    m_dikeRecords.push_back(index);
  }
}

void TerrainPieces::keepDikes() {
  for (const std::uint32_t index : m_lastDikeRecords) {
    m_records[index]->lastFrame = m_frame;
    publish(index, false, false);
    m_dikeRecords.push_back(index);
  }
}

void TerrainPieces::buildDikes(Record& record, std::span<const terrain::DikeVertex> vertices,
                               std::span<const std::uint32_t> indices, std::span<const std::uint32_t> triangles,
                               const DikeVertexSamples& samples) {
  record.anchor = anchorOf(record.node);
  record.vertices.clear();
  record.indices.clear();
  // Weld the corners through a table at most half full, cleared by a new stamp.
  std::size_t capacity = 64;
  while (capacity < 6 * triangles.size()) capacity *= 2;
  if (m_weld.size() < capacity) m_weld.assign(capacity, WeldSlot{});
  if (++m_weldStamp == 0) {
    std::fill(m_weld.begin(), m_weld.end(), WeldSlot{});
    m_weldStamp = 1;
  }
  const std::size_t mask = m_weld.size() - 1;
  for (const std::uint32_t t : triangles) {
    for (int corner = 0; corner < 3; ++corner) {
      const std::uint32_t vertex = indices[3 * t + std::size_t(corner)];
      const terrain::DikeVertex& g = vertices[vertex];
      const std::uint64_t key = packSample(g.x, g.y);
      std::size_t slot = std::size_t(mixBits(key)) & mask;
      while (m_weld[slot].stamp == m_weldStamp && m_weld[slot].key != key) slot = (slot + 1) & mask;
      if (m_weld[slot].stamp != m_weldStamp) {
        m_weld[slot] = WeldSlot{key, m_weldStamp, std::uint32_t(record.vertices.size())};
        record.vertices.push_back(gridVertex(samples.of(vertex, g), g.x, g.y, record.anchor));
      }
      record.indices.push_back(m_weld[slot].vertex);
    }
  }
}

void TerrainPieces::finishFrame() {
  // Records not used this frame are retired; their memory waits for the next new piece.
  for (const std::uint32_t index : m_live) {
    Record& record = *m_records[index];
    if (record.lastFrame == m_frame) continue;
    m_retired.push_back(record.key);
    m_index->erase(record.key);
    record.lastFrame = 0;
    m_freeRecords.push_back(index);
  }
  m_live.assign(m_pieceRecords.begin(), m_pieceRecords.end());
  m_lastDikeRecords.assign(m_dikeRecords.begin(), m_dikeRecords.end());
}

}  // namespace polder
