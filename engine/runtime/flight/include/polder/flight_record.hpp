// What a recorded flight measured (polder/flight_recorder.hpp), as plain data: one entry per
// frame for the figures that vary, sums and maxima for the rest; and the summaries a report
// prints from it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <polder/flight_statistics.hpp>

namespace polder {

// Pixels of one drawn frame read back: background enclosed by terrain, and of those the
// pixels the frame's own mesh covers (cracks between its triangles).
struct FramePixelCracks {
  std::size_t enclosedBackgroundPx = 0;
  std::size_t crackPx = 0;
};

// One frame's measured screen-space error against the full-resolution terrain.
struct FrameScreenError {
  double maxPx = 0.0;
  double p99Px = 0.0;
  std::size_t holePixels = 0;  // pixels looking through a gap in the frame's mesh
};

struct FlightRecord {
  int frames = 0;

  // Per frame, in flight order: the engine's figures (TerrainFrameStats).
  std::vector<double> selectMs, lodMs, dikesMs, piecesMs, totalMs;
  std::vector<double> triangles, dikeTriangles, visibleBlocks, culledBlocks;
  // Per frame with a draw hook, else empty: the hook's time and the bytes it uploaded.
  std::vector<double> renderMs, uploadBytes;

  // Sums over the frames.
  std::uint64_t cacheLookups = 0, cacheHits = 0, cacheRebuilds = 0;
  std::uint64_t piecesCreated = 0, piecesChanged = 0, piecesRetired = 0;
  double pieceBytes = 0.0;  // vertex and index bytes of the created and changed pieces
  FramePixelCracks cracks;  // with a crack-counting hook

  // The engine's dike check (error mode) over the frames: the largest bound, the frames
  // that left a dike triangle over tau, and the most such triangles in one frame.
  double dikeBoundMaxPx = 0.0;
  int dikeFramesOverTau = 0;
  std::size_t dikeTrianglesOverTauMax = 0;

  // Background block loading: frames drawn partly from resident ancestors (coarser than
  // tau asks while their blocks load), hierarchies that arrived, and the most LOD data
  // resident at once.
  int framesOnAncestor = 0;
  std::uint64_t loadsArrived = 0;
  std::size_t residentBytesPeak = 0;
  // Over the recorded frames (not the settled first view): times the frame thread waited for
  // the loaders, and hand-offs put off a frame because a loader held them.
  std::uint64_t frameWaits = 0;
  std::uint64_t handoffsDeferred = 0;

  // The checked frames: screen-space error (the largest max and p99 over the frames the
  // hook measured at their selected level; frames partly on ancestors apart) and
  // watertightness (sums of open edges and T-junctions).
  int framesMeasured = 0;
  double errorMaxPx = 0.0;
  double errorP99Px = 0.0;
  int framesMeasuredOnAncestor = 0;
  double errorOnAncestorMaxPx = 0.0;
  double errorOnAncestorP99Px = 0.0;
  int framesChecked = 0;
  std::size_t openEdges = 0, tJunctions = 0;
  std::size_t holePixels = 0;        // over every measured frame
  std::vector<int> framesWithHoles;  // the measured frames that had any, in order
};

struct FlightSummary {
  double trianglesMean = 0.0, trianglesMax = 0.0, dikeTrianglesMean = 0.0;
  double visibleBlocksMean = 0.0, culledBlocksMean = 0.0;
  double cacheReuseRate = 0.0;  // hits per lookup; 0 without lookups
  Percentiles selectMs, lodMs, dikesMs, piecesMs, totalMs;
  double pieceBytesPerFrame = 0.0;
  // Median over the frames of the pieces' time against the rest of the frame's: what
  // host-ready vertex data costs next to selection, LOD and dikes.
  double hostDataRatio = 0.0;
  // With a draw hook (drawn), else zeros.
  bool drawn = false;
  Percentiles renderMs, uploadBytes;
  double uploadBytesMean = 0.0;
  std::size_t framesUploadingNothing = 0;
};

FlightSummary summarizeFlight(const FlightRecord& record);

// The same flight with and without the LOD cache: the shares of LOD and whole-frame time the
// cache saved, and the cached flight's triangles against the uncached one's (means).
struct CacheComparison {
  double lodMsSavedFraction = 0.0;
  double totalMsSavedFraction = 0.0;
  double trianglesRatio = 0.0;
};

CacheComparison compareCache(const FlightRecord& cached, const FlightRecord& uncached);

}  // namespace polder
