// The terrain frame on Polder's own GL renderer, the way a host would keep GPU data for it
// (polder/terrain_frame.hpp): one buffer per resident piece, uploaded when the piece is
// created or changed, freed when it retires; a frame in which nothing changed uploads
// nothing and costs one draw per piece.
//
//   TerrainDrawer drawer(renderer);                   // GL context current
//   const TerrainFrame& frame = engine->update(camera);
//   drawer.sync(frame);                               // every frame update() returns
//   renderer.beginFrame(camera, style);
//   drawer.draw(frame);
//   renderer.endFrame();
//
// Threads and lifetime: as the renderer's (the thread whose context is current). Destroy
// the drawer before the renderer.
#pragma once

#include <cstddef>
#include <cstdint>
#include <unordered_map>

#include <polder/render/renderer.hpp>
#include <polder/result.hpp>
#include <polder/terrain/heightfield.hpp>
#include <polder/terrain_frame.hpp>
#include <polder/terrain_style.hpp>

namespace polder {

// Colouring for inspection: quadtree levels tinted, dikes in red, or triangle edges.
enum class TerrainDebugView { None, Lod, Dikes, Wire };

struct TerrainDrawStats {
  std::size_t residentPieces = 0;
  std::size_t residentBytes = 0;   // GPU bytes of the resident pieces
  std::size_t uploadedBytes = 0;   // by the last sync()
  std::size_t piecesUploaded = 0;  // by the last sync()
  std::size_t piecesReleased = 0;  // by the last sync()
  std::size_t uploadFailures = 0;  // pieces the last sync() could not upload (not drawn)
};

class TerrainDrawer {
 public:
  explicit TerrainDrawer(render::Renderer& renderer);
  ~TerrainDrawer();
  TerrainDrawer(const TerrainDrawer&) = delete;
  TerrainDrawer& operator=(const TerrainDrawer&) = delete;

  // Brings the GPU up to `frame`: uploads the pieces whose version it does not hold (the
  // frame's created and changed ones) and releases those the frame no longer has (its
  // retired ones). Frames may be skipped: versions decide what is stale. An upload the GPU
  // refuses is reported and tried again at the next sync; the rest go on.
  Status sync(const TerrainFrame& frame);
  // Draws the frame's resident pieces; between the renderer's beginFrame and endFrame. For
  // TerrainDebugView::Wire, turn on the style's wireframe instead (the renderer draws edges).
  void draw(const TerrainFrame& frame, TerrainDebugView view = TerrainDebugView::None);
  // Releases every piece (e.g. before switching to another engine).
  void clear();

  TerrainDrawStats stats() const { return m_stats; }

 private:
  struct Resident {
    render::MeshHandle handle;
    std::uint64_t version = 0;
    std::size_t bytes = 0;
    std::uint64_t lastSync = 0;
  };
  void release(std::unordered_map<std::uint64_t, Resident>::iterator it);

  render::Renderer& m_renderer;
  std::unordered_map<std::uint64_t, Resident> m_resident;  // by TerrainPieceKey::value
  TerrainDrawStats m_stats;
  std::uint64_t m_syncs = 0;
};

// A sensible style for a heightfield: the elevation ramp spans its height range, and fog
// half-hides terrain at about 60% of its diagonal.
TerrainStyle defaultTerrainStyle(const terrain::Heightfield& field);
// The same for a DEM known by its height range and extent in metres (a pyramid's header).
TerrainStyle defaultTerrainStyle(float minHeightM, float maxHeightM, double extentX, double extentY);

}  // namespace polder
