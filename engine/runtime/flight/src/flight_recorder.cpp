#include <polder/flight_recorder.hpp>

#include <algorithm>
#include <chrono>
#include <thread>

namespace polder {
namespace {

// Reserves the per-frame series and touches their pages, so that a long flight's resident
// memory measures the engine rather than the record filling up.
void reserveFrames(FlightRecord& record, std::size_t frames, bool drawn) {
  auto reserve = [frames](std::vector<double>& series) {
    series.resize(frames);
    series.clear();
  };
  for (std::vector<double>* series :
       {&record.selectMs, &record.lodMs, &record.dikesMs, &record.piecesMs, &record.totalMs, &record.triangles,
        &record.dikeTriangles, &record.visibleBlocks, &record.culledBlocks})
    reserve(*series);
  if (drawn) {
    reserve(record.renderMs);
    reserve(record.uploadBytes);
  }
}

void recordStats(const TerrainFrameStats& stats, FlightRecord& record) {
  record.selectMs.push_back(stats.selectMs);
  record.lodMs.push_back(stats.lodMs);
  record.dikesMs.push_back(stats.dikesMs);
  record.piecesMs.push_back(stats.piecesMs);
  record.totalMs.push_back(stats.totalMs);
  record.piecesCreated += stats.piecesCreated;
  record.piecesChanged += stats.piecesChanged;
  record.piecesRetired += stats.piecesRetired;
  record.pieceBytes += double(stats.pieceBytesProduced);
  record.triangles.push_back(double(stats.triangles()));
  record.dikeTriangles.push_back(double(stats.dikeTriangles));
  record.visibleBlocks.push_back(double(stats.visibleBlocks));
  record.culledBlocks.push_back(double(stats.culledBlocks));
  record.cacheLookups += stats.cacheLookups;
  record.cacheHits += stats.cacheHits;
  record.cacheRebuilds += stats.cacheRebuilds;
  record.dikeBoundMaxPx = std::max(record.dikeBoundMaxPx, stats.dikeErrorPx);
  record.dikeFramesOverTau += stats.dikeTrianglesOverTau > 0;
  record.dikeTrianglesOverTauMax = std::max(record.dikeTrianglesOverTauMax, stats.dikeTrianglesOverTau);
  record.framesOnAncestor += stats.blocksOnAncestor > 0;
  record.loadsArrived += stats.loadsArrived;
}

}  // namespace

FlightRecorder::FlightRecorder(TerrainEngine& engine, const CameraPath& path, const Camera& lens)
    : m_engine(engine), m_path(path), m_lens(lens) {}

Camera FlightRecorder::camera(int frameIndex) const {
  const double frameTimeS = 1.0 / kFlightFramesPerSecond;
  return m_path.at(frameIndex * frameTimeS).placed(m_lens);
}

Result<FlightRecord> FlightRecorder::fly(const FlightOptions& options, const FlightHooks& hooks) {
  if (options.frames < 1)
    return makeError(ErrorKind::InvalidArgument, "a flight needs at least 1 frame (FlightOptions::frames)");
  if (options.checkEvery < 0)
    return makeError(ErrorKind::InvalidArgument, "FlightOptions::checkEvery must be 0 (never) or more");
  const TerrainEngineOptions engineOptions = m_engine.options();
  if (options.withoutCache) {
    TerrainEngineOptions without = engineOptions;
    without.cacheEnabled = false;
    m_engine.setOptions(without);
  }
  FlightRecord record;
  record.frames = options.frames;
  reserveFrames(record, std::size_t(options.frames), bool(hooks.draw));
  if (options.settleFirstFrame) (void)m_engine.updateSettled(camera(0));
  const std::uint64_t waitsBefore = m_engine.loadStats().frameWaits;
  const std::uint64_t deferredBefore = m_engine.loadStats().handoffsDeferred;
  const auto flightStart = std::chrono::steady_clock::now();
  const std::chrono::duration<double> framePeriod(1.0 / kFlightFramesPerSecond);
  for (int frameIndex = 0; frameIndex < options.frames; ++frameIndex) {
    if (options.paced)
      std::this_thread::sleep_until(
          flightStart + std::chrono::duration_cast<std::chrono::steady_clock::duration>(frameIndex * framePeriod));
    const bool checked = options.checkEvery > 0 && frameIndex % options.checkEvery == 0;
    recordFrame(frameIndex, checked, hooks, record);
    if (hooks.progress) hooks.progress(float(frameIndex + 1) / float(options.frames));
  }
  record.frameWaits = m_engine.loadStats().frameWaits - waitsBefore;
  record.handoffsDeferred = m_engine.loadStats().handoffsDeferred - deferredBefore;
  if (options.withoutCache) m_engine.setOptions(engineOptions);
  return record;
}

void FlightRecorder::recordFrame(int frameIndex, bool checked, const FlightHooks& hooks, FlightRecord& record) {
  const Camera camera = this->camera(frameIndex);
  const TerrainFrame& frame = m_engine.update(camera);
  recordStats(frame.stats, record);
  record.residentBytesPeak = std::max(record.residentBytesPeak, m_engine.loadStats().residentBytes);
  if (hooks.draw) {
    const auto start = std::chrono::steady_clock::now();
    const std::size_t uploaded = hooks.draw(frame, camera);
    record.renderMs.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    record.uploadBytes.push_back(double(uploaded));
    if (hooks.countCracks) {
      const FramePixelCracks cracks = hooks.countCracks(m_engine, camera);
      record.cracks.enclosedBackgroundPx += cracks.enclosedBackgroundPx;
      record.cracks.crackPx += cracks.crackPx;
    }
  }
  if (!checked) return;
  if (hooks.measureError) {
    if (const std::optional<FrameScreenError> error = hooks.measureError(m_engine, camera)) {
      record.holePixels += error->holePixels;
      if (error->holePixels > 0) record.framesWithHoles.push_back(frameIndex);
      if (frame.stats.blocksOnAncestor > 0) {
        record.errorOnAncestorMaxPx = std::max(record.errorOnAncestorMaxPx, error->maxPx);
        record.errorOnAncestorP99Px = std::max(record.errorOnAncestorP99Px, error->p99Px);
        ++record.framesMeasuredOnAncestor;
      } else {
        record.errorMaxPx = std::max(record.errorMaxPx, error->maxPx);
        record.errorP99Px = std::max(record.errorP99Px, error->p99Px);
        ++record.framesMeasured;
      }
    }
  }
  const terrain::WatertightReport report = m_engine.checkWatertight();
  record.openEdges += report.openEdges;
  record.tJunctions += report.tJunctions;
  ++record.framesChecked;
  if (hooks.afterCheck) hooks.afterCheck(frameIndex);
}

}  // namespace polder
