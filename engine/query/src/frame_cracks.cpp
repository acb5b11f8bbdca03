#include <polder/query/frame_cracks.hpp>

#include <polder/enclosed_background.hpp>

namespace polder::query {

namespace {

// The rasteriser snaps vertices to a fraction of a pixel, so on a silhouette it may leave a
// pixel whose centre lies a hair inside the mesh. A crack lies between triangles, with the
// mesh on every side of the centre: rays a tenth of a pixel off it hit too.
constexpr double kMarginPx = 0.1;

}  // namespace

FrameCracks findFrameCracks(const RgbaImage& image, const QueryScene& frameMesh, const Camera& camera) {
  FrameCracks found;
  for (int y = 1; y + 1 < image.height; ++y) {
    for (int x = 1; x + 1 < image.width; ++x) {
      if (!isEnclosedBackground(image, x, y)) continue;
      ++found.enclosedBackground;
      bool covered = true;
      const double offsets[5][2] = {
          {0.0, 0.0}, {-kMarginPx, 0.0}, {kMarginPx, 0.0}, {0.0, -kMarginPx}, {0.0, kMarginPx}};
      for (const auto& offset : offsets) {
        const glm::dvec3 direction = camera.pixelRay(x + 0.5 + offset[0], y + 0.5 + offset[1]);
        covered = covered && frameMesh.raycast(camera.position, direction, camera.farM).has_value();
      }
      found.cracks += covered ? 1 : 0;
    }
  }
  return found;
}

}  // namespace polder::query
