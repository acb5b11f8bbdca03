// A recorded flight: a TerrainEngine flown along a camera path, 60 frames per second of
// flight, every frame's figures written into a FlightRecord (polder/flight_record.hpp).
//
//   FlightRecorder recorder(*engine, path, lens);   // lens: field of view, viewport, clip planes
//   FlightOptions options;
//   options.frames = 600;
//   FlightHooks hooks;                              // all optional
//   hooks.draw = [&](const TerrainFrame& frame, const Camera& camera) { ...; return uploadedBytes; };
//   auto record = recorder.fly(options, hooks);
//   const FlightSummary summary = summarizeFlight(*record);
//
// What needs other modules comes in through the hooks: drawing (e.g. TerrainDrawer on the GL
// renderer), counting pixel cracks in what was drawn, and measuring screen-space error
// (e.g. polder::query against the full-resolution terrain). The recorder itself checks
// watertightness on the checked frames (TerrainEngine::checkWatertight).
//
// The frame loop allocates nothing of its own: the record's vectors are reserved for every
// frame first. The engine, the hooks and the watertightness check allocate as they do.
// Thread contract as the engine's: fly() runs on the frame thread; the engine and the path
// outlive the recorder.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>

#include <polder/camera.hpp>
#include <polder/camera_path.hpp>
#include <polder/flight_record.hpp>
#include <polder/result.hpp>
#include <polder/terrain_engine.hpp>

namespace polder {

inline constexpr double kFlightFramesPerSecond = 60.0;

struct FlightOptions {
  int frames = 600;
  // Frames 0, checkEvery, 2 checkEvery, ...: the measureError hook and the watertightness
  // check. 0: never.
  int checkEvery = 30;
  // Fly with the engine's LOD cache switched off, for comparisons; the engine's options are
  // restored afterwards.
  bool withoutCache = false;
  // Start frame i no sooner than i / kFlightFramesPerSecond seconds into the flight, as a
  // flight shown at that rate does, so that background loads get the time they would there
  // (the wait counts in no frame's time). false: frames back to back.
  bool paced = false;
  // Load everything the first frame needs before flying (TerrainEngine::updateSettled), as a
  // flight starts after its loading screen.
  bool settleFirstFrame = false;
};

struct FlightHooks {
  // Draws the frame the engine just made and returns once it is drawn (the recorder times
  // the call as the frame's render time) with the bytes it uploaded. Every frame.
  std::function<std::size_t(const TerrainFrame& frame, const Camera& camera)> draw;
  // After each draw, untimed: the drawn frame's pixel cracks.
  std::function<FramePixelCracks(TerrainEngine& engine, const Camera& camera)> countCracks;
  // On the checked frames: the frame's screen-space error, or nullopt where it could not be
  // measured (the frame is still checked for watertightness).
  std::function<std::optional<FrameScreenError>(TerrainEngine& engine, const Camera& camera)> measureError;
  // After each checked frame's checks, with its index: the caller's own measurements.
  std::function<void(int frameIndex)> afterCheck;
  // After each frame: the share of the flight done.
  std::function<void(float fraction)> progress;
};

class FlightRecorder {
 public:
  FlightRecorder(TerrainEngine& engine, const CameraPath& path, const Camera& lens);

  // The camera of frame `index`: the path's pose at index / 60 seconds through the lens.
  Camera camera(int frameIndex) const;

  // Errors: frames below 1, checkEvery below 0.
  Result<FlightRecord> fly(const FlightOptions& options, const FlightHooks& hooks = {});

 private:
  void recordFrame(int frameIndex, bool checked, const FlightHooks& hooks, FlightRecord& record);

  TerrainEngine& m_engine;
  const CameraPath& m_path;
  Camera m_lens;
};

}  // namespace polder
