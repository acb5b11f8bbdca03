#include "polder/scene/pose.hpp"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

namespace polder::scene {

glm::dmat4 Pose::matrix() const {
  glm::dmat4 m = glm::mat4_cast(rotation);
  m[0] *= scale.x;
  m[1] *= scale.y;
  m[2] *= scale.z;
  m[3] = glm::dvec4(translation, 1.0);
  return m;
}

Pose interpolate(const Pose& a, const Pose& b, double t) {
  return Pose{glm::mix(a.translation, b.translation, t), glm::slerp(a.rotation, b.rotation, t),
              glm::mix(a.scale, b.scale, t)};
}

Pose Animation::evaluate(const Pose& rest, double timeS) const {
  switch (kind) {
    case Kind::None:
      return rest;
    case Kind::Keyframes: {
      if (keys.empty()) return rest;
      if (keys.size() == 1) return keys.front().pose;
      const double start = keys.front().timeS, end = keys.back().timeS;
      double t = timeS;
      if (loop && end > start) t = start + std::fmod(std::fmod(t - start, end - start) + (end - start), end - start);
      if (t <= start) return keys.front().pose;
      if (t >= end) return keys.back().pose;
      const auto next = std::upper_bound(keys.begin(), keys.end(), t,
                                         [](double value, const Keyframe& k) { return value < k.timeS; });
      const Keyframe& b = *next;
      const Keyframe& a = *(next - 1);
      const double span = b.timeS - a.timeS;
      return interpolate(a.pose, b.pose, span > 0.0 ? (t - a.timeS) / span : 1.0);
    }
    case Kind::Spin: {
      Pose pose = rest;
      const double length = glm::length(axis);
      if (length > 0.0)
        pose.rotation = glm::angleAxis(glm::radians(degreesPerSecond * timeS), axis / length) * rest.rotation;
      return pose;
    }
    case Kind::Orbit: {
      Pose pose = rest;
      const double angle = phase + (periodS != 0.0 ? 2.0 * glm::pi<double>() * timeS / periodS : 0.0);
      pose.translation = centre + glm::dvec3(radius * std::cos(angle), radius * std::sin(angle), rest.translation.z);
      // Face along the path: the model's +x points where it is going.
      const double heading = angle + (periodS >= 0.0 ? 0.5 : -0.5) * glm::pi<double>();
      pose.rotation = glm::angleAxis(heading, glm::dvec3(0.0, 0.0, 1.0)) * rest.rotation;
      return pose;
    }
  }
  return rest;
}

}  // namespace polder::scene
