// The viewer: a pinhole camera in Polder's world frame.
//
// World frame (docs/design.md "Coordinates"): x east, y north, z up, metres, origin at the DEM's
// south-west sample. Yaw is degrees clockwise from north, pitch degrees up from horizontal.
// Positions are double; the GPU sees camera-relative floats, so nothing jitters far from
// the origin.
#pragma once

#include <glm/glm.hpp>

namespace polder {

struct Camera {
  glm::dvec3 position{0.0};
  double yawDeg = 0.0;    // clockwise from north (+y) towards east (+x)
  double pitchDeg = 0.0;  // up from horizontal
  double fovYDeg = 60.0;  // vertical field of view
  int widthPx = 1280;
  int heightPx = 720;
  double nearM = 1.0;
  double farM = 1.0e6;

  // Unit vectors of the view frame.
  glm::dvec3 forward() const;
  glm::dvec3 right() const;
  glm::dvec3 up() const;

  double aspect() const { return double(widthPx) / double(heightPx); }
  friend bool operator==(const Camera&, const Camera&) = default;

  // K = viewport_height / (2 tan(fovy/2)): a world-space length e at distance d covers
  // about K * e / d pixels.
  double projectionConstant() const;

  // The constant to turn a vertical world error into a bound on its size in pixels anywhere
  // in the view: K * (1 + T^2), T the tangent of the half-diagonal field of view. Off the
  // view axis a vertical segment e at distance d projects through depth (d cos theta) and
  // tilts in the image, covering up to K e / (d cos^2 theta) pixels; K e / d alone holds
  // only at the centre of the screen.
  double errorProjectionConstant() const;

  // Rotation-only view matrix (camera at the origin): world offsets relative to the
  // camera position go in, eye space comes out.
  glm::dmat4 viewRotation() const;
  // OpenGL clip-space projection (right-handed eye space looking down -z).
  glm::dmat4 projection() const;

  // Direction (unit, world frame) of the ray through pixel (px, py), where (0, 0) is the
  // top-left corner of the top-left pixel; pixel centres are at +0.5.
  glm::dvec3 pixelRay(double px, double py) const;
};

}  // namespace polder
