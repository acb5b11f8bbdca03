// A node's local transform and its animation (ASLOD's scene graph, Schmalstieg and Fuhrmann 1999,
// sections 3 and 6: hierarchical transforms, animated as a whole).
#pragma once

#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace polder::scene {

// Translation, rotation and (axis-aligned) scale; matrix() = T * R * S.
struct Pose {
  glm::dvec3 translation{0.0};
  glm::dquat rotation{1.0, 0.0, 0.0, 0.0};
  glm::dvec3 scale{1.0};

  glm::dmat4 matrix() const;
};

// Component-wise blend: lerp for translation and scale, slerp for rotation.
Pose interpolate(const Pose& a, const Pose& b, double t);

struct Keyframe {
  double timeS = 0.0;
  Pose pose;
};

// What moves a node over time. The result replaces the node's rest pose, except for Spin
// and Orbit, which act on it: Spin turns the rest pose about its own axis, Orbit carries it
// around a centre (in the parent's frame) at the rest pose's height above it.
struct Animation {
  enum class Kind { None, Keyframes, Spin, Orbit };
  Kind kind = Kind::None;
  std::vector<Keyframe> keys;  // Keyframes: sorted by time; clamped at the ends unless loop
  bool loop = true;
  glm::dvec3 axis{0.0, 0.0, 1.0};  // Spin
  double degreesPerSecond = 0.0;   // Spin
  glm::dvec3 centre{0.0};          // Orbit, in the x-y plane around it
  double radius = 0.0;             // Orbit
  double periodS = 10.0;           // Orbit: seconds per turn (negative: clockwise)
  double phase = 0.0;              // Orbit: start angle, radians

  Pose evaluate(const Pose& rest, double timeS) const;
};

}  // namespace polder::scene
