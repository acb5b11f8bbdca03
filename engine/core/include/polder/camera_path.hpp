// Recorded and built-in camera flights, for the flyover and for reproducible benchmarks.
#pragma once

#include <filesystem>
#include <functional>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include <polder/camera.hpp>

#include <polder/result.hpp>

namespace polder {

struct CameraPose {
  double timeS = 0.0;
  glm::dvec3 position{0.0};
  double yawDeg = 0.0;
  double pitchDeg = 0.0;

  // `lens` (field of view, viewport, clip planes) placed at this pose.
  Camera placed(Camera lens) const {
    lens.position = position;
    lens.yawDeg = yawDeg;
    lens.pitchDeg = pitchDeg;
    return lens;
  }
};

// Poses in time order; in between, positions interpolate linearly and angles along the
// shorter arc. Before the first pose and after the last, the path holds still (a closed
// loop wraps instead).
// Farther than any terrain reaches, near enough that single-precision view matrices and ray
// tracing stay meaningful.
inline constexpr double kMaxPoseCoordinateM = 1e9;

class CameraPath {
 public:
  // At least one pose, times finite and strictly increasing, positions within
  // kMaxPoseCoordinateM of the origin on each axis.
  static Result<CameraPath> fromPoses(std::vector<CameraPose> poses, bool closedLoop = false);

  // Text: one pose per line, "t x y z yaw pitch" (seconds, metres, degrees); '#' starts a
  // comment. Errors name the line.
  static Result<CameraPath> parse(std::string_view text);
  // parse() on a file's text; errors start with the file's name, and what parse() refuses
  // is InvalidData here: a file's contents are data, not arguments.
  static Result<CameraPath> readFile(const std::filesystem::path& file);

  CameraPose at(double timeS) const;
  double durationS() const { return m_poses.back().timeS - m_poses.front().timeS; }
  bool closedLoop() const { return m_closedLoop; }
  const std::vector<CameraPose>& poses() const { return m_poses; }

 private:
  std::vector<CameraPose> m_poses;
  bool m_closedLoop = false;
};

struct FlyoverOptions {
  double altitudeM = 300.0;  // above the highest ground near the path
  double speedMps = 150.0;
  double pitchDeg = -15.0;       // looking ahead and slightly down
  double radiusFraction = 0.32;  // of the terrain's extent, around its centre
  int samples = 720;             // poses around the loop
};

// A smooth closed loop over a terrain of extent [0, extentX] x [0, extentY]: an ellipse
// around the centre, at `altitudeM` above the ground it flies over (the ground is taken as
// the highest point within a few hundred metres ahead and behind, smoothed, so the flight
// clears peaks without bobbing over every bump). O(samples) whatever the extent.
// InvalidArgument for a non-finite or non-positive extent or speed, a negative or non-finite
// altitude, pitch or radius, or samples outside 8..1,000,000.
Result<CameraPath> makeFlyoverLoop(double extentX, double extentY,
                                   const std::function<double(double x, double y)>& groundHeight,
                                   const FlyoverOptions& options = {});

struct OrbitOptions {
  double altitudeM = 1000.0;  // above the highest ground on the circle
  double speedMps = 150.0;
  double radiusFraction = 0.35;  // of the terrain's smaller extent, around its centre
  int samples = 720;
};

// A closed circle around the terrain's centre, always looking at the centre's ground.
// InvalidArgument as makeFlyoverLoop.
Result<CameraPath> makeOrbitLoop(double extentX, double extentY,
                                 const std::function<double(double x, double y)>& groundHeight,
                                 const OrbitOptions& options = {});

}  // namespace polder
