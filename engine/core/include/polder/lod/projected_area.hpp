// Projected screen area of oriented bounding boxes: the weight the budget allocator splits
// triangles by (docs/design.md "One frame", step 4).
//
// Follows D. Schmalstieg and R. F. Tobler, "Fast Projected Area Computation for Three-
// Dimensional Bounding Boxes", Journal of Graphics Tools 4(2), 1999: the eye position,
// in the box's own frame, falls into one of 27 regions cut out by the box's six face
// planes; a constant table gives the silhouette of each region (4 corners when one face is
// visible, 6 when two or three are), and the area of that polygon after projection is the
// box's projected area. ASLOD (Schmalstieg and Fuhrmann 1999, section 3) uses this as the
// weight w_i of its polygon allocation.
//
// Near plane: a box that crosses the camera's near plane is clipped there and the convex
// hull of the clipped box's projection is measured (what the rasterizer would cover).
// Clipping only the table's silhouette polygon is not enough: the cut opens the box and
// exposes back faces (a box beside the camera reaching behind it covers far more screen
// than its clipped front face), so that shortcut under-reports exactly the near blocks
// that matter most. Treating such boxes as "whole screen" would be safe but gives every
// block under a low camera the same, largest weight. The exact clip costs one small hull
// and only runs for the few boxes that cross the near plane.
//
// Pure functions, no state, no allocation; safe to call from any thread.
#pragma once

#include <glm/glm.hpp>

#include <polder/camera.hpp>

namespace polder::lod {

// A box with its own orthonormal frame: axes are unit column vectors (world frame),
// halfExtents are the half side lengths along them. Degenerate (zero) extents are allowed.
struct OrientedBox {
  glm::dvec3 centre{0.0};
  glm::dmat3 axes{1.0};
  glm::dvec3 halfExtents{0.0};
};

// The axis-aligned box [minCorner, maxCorner] as an OrientedBox.
OrientedBox orientedBoxFromAabb(const glm::dvec3& minCorner, const glm::dvec3& maxCorner);

// The camera quantities the area functions need, computed once per frame rather than once
// per box (camera.forward() and friends evaluate trigonometry on every call).
struct AreaView {
  glm::dvec3 position{0.0};
  glm::dmat3 worldToEye{1.0};  // rows: right, up, -forward (Camera::viewRotation())
  double scaleXPx = 1.0;       // pixels per unit of x_eye / depth
  double scaleYPx = 1.0;       // pixels per unit of y_eye / depth
  double nearM = 1.0;
  double widthPx = 1.0;
  double heightPx = 1.0;
};

AreaView makeAreaView(const Camera& camera);

// Area in pixels^2 of the box's outline on the image plane of the camera, not limited to
// the viewport (a box off to the side still has an area; culling is the caller's job).
// The eye inside the box gives the whole screen, widthPx * heightPx. A box entirely in
// front of the near plane takes the table path; one crossing it is clipped there (see the
// top of this file); one entirely behind it has area 0. The far plane is ignored.
double projectedAreaPx(const OrientedBox& box, const AreaView& view);
double projectedAreaPx(const OrientedBox& box, const Camera& camera);

// The same outline clipped to the viewport rectangle: the pixels the box can cover, never
// more than widthPx * heightPx. Better as an allocation weight than projectedAreaPx for
// boxes that reach far past the screen edge (a block just past the near plane beside the
// camera projects to millions of pixels, almost none of them on screen).
double visibleAreaPx(const OrientedBox& box, const AreaView& view);
double visibleAreaPx(const OrientedBox& box, const Camera& camera);

}  // namespace polder::lod
