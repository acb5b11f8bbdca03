#include <polder/terrain_drawer.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace polder {

namespace {

// Quadtree levels under TerrainDebugView::Lod: level 0 keeps the terrain's colours, coarser
// levels shift towards blue, violet, orange...
constexpr glm::vec3 kLevelTints[] = {{1.0f, 1.0f, 1.0f}, {0.55f, 0.75f, 1.0f}, {0.85f, 0.55f, 1.0f},
                                     {1.0f, 0.7f, 0.4f}, {0.5f, 1.0f, 0.6f},   {1.0f, 0.5f, 0.5f}};

glm::vec3 tintOf(const TerrainPiece& piece, TerrainDebugView view) {
  const bool dikes = piece.kind == TerrainPieceKind::Dikes;
  switch (view) {
    case TerrainDebugView::Lod:
      return dikes ? glm::vec3(1.0f) : kLevelTints[std::min<std::size_t>(piece.node.level, 5)];
    case TerrainDebugView::Dikes:
      return dikes ? glm::vec3(1.6f, 0.25f, 0.2f) : glm::vec3(0.8f);
    case TerrainDebugView::None:
    case TerrainDebugView::Wire:
      break;
  }
  return glm::vec3(1.0f);
}

}  // namespace

TerrainDrawer::TerrainDrawer(render::Renderer& renderer) : m_renderer(renderer) {}

TerrainDrawer::~TerrainDrawer() { clear(); }

void TerrainDrawer::release(std::unordered_map<std::uint64_t, Resident>::iterator it) {
  m_renderer.release(it->second.handle);
  m_stats.residentBytes -= it->second.bytes;
  m_resident.erase(it);
  ++m_stats.piecesReleased;
}

Status TerrainDrawer::sync(const TerrainFrame& frame) {
  m_stats.uploadedBytes = 0;
  m_stats.piecesUploaded = 0;
  m_stats.piecesReleased = 0;
  m_stats.uploadFailures = 0;
  ++m_syncs;
  // Versions decide, so a frame that was never synced (or a failed upload) is caught up here;
  // when every frame is synced this uploads exactly the frame's created and changed pieces.
  Status firstFailure;
  for (const TerrainPiece& piece : frame.pieces) {
    auto it = m_resident.find(piece.key.value);
    if (it != m_resident.end() && it->second.version == piece.version) {
      it->second.lastSync = m_syncs;
      continue;
    }
    if (it != m_resident.end()) release(it);
    auto handle = m_renderer.upload(piece.mesh);
    if (!handle) {
      ++m_stats.uploadFailures;
      if (firstFailure) firstFailure = handle.error();
      continue;
    }
    const std::size_t bytes = piece.mesh.vertices.size_bytes() + piece.mesh.indices.size_bytes();
    m_resident.emplace(piece.key.value, Resident{*handle, piece.version, bytes, m_syncs});
    m_stats.residentBytes += bytes;
    m_stats.uploadedBytes += bytes;
    ++m_stats.piecesUploaded;
  }
  // What the frame no longer has is retired.
  for (auto it = m_resident.begin(); it != m_resident.end();) {
    if (it->second.lastSync == m_syncs) {
      ++it;
      continue;
    }
    auto retired = it++;
    release(retired);
  }
  m_stats.residentPieces = m_resident.size();
  if (!firstFailure) {
    return makeError(firstFailure.error().kind,
                     std::to_string(m_stats.uploadFailures) +
                         " terrain pieces could not be uploaded: " + firstFailure.error().message);
  }
  return {};
}

void TerrainDrawer::draw(const TerrainFrame& frame, TerrainDebugView view) {
  for (const TerrainPiece& piece : frame.pieces) {
    const auto it = m_resident.find(piece.key.value);
    if (it == m_resident.end() || it->second.version != piece.version) continue;
    m_renderer.draw(it->second.handle, tintOf(piece, view));
  }
}

void TerrainDrawer::clear() {
  for (auto& [key, resident] : m_resident) m_renderer.release(resident.handle);
  m_resident.clear();
  m_stats = TerrainDrawStats{};
}

TerrainStyle defaultTerrainStyle(const terrain::Heightfield& field) {
  const auto [low, high] = field.heightRange();
  return defaultTerrainStyle(low, high, field.extentX(), field.extentY());
}

TerrainStyle defaultTerrainStyle(float minHeightM, float maxHeightM, double extentX, double extentY) {
  TerrainStyle style;
  style.minHeightM = minHeightM;
  style.maxHeightM = float(std::max(double(maxHeightM), double(minHeightM) + 1.0));
  style.fogDensity = fogDensityForDistance(float(0.6 * std::hypot(extentX, extentY)));
  return style;
}

}  // namespace polder
