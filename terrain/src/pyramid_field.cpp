// A pyramid's full resolution, assembled from its level-0 tiles.
#include <algorithm>
#include <cstring>
#include <fstream>
#include <new>

#include <polder/terrain/pyramid.hpp>

namespace polder::terrain {

bool looksLikePyramid(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  char magic[sizeof kPyramidMagic] = {};
  return file.read(magic, sizeof magic) && std::memcmp(magic, kPyramidMagic, sizeof magic) == 0;
}

Result<Heightfield> readWindow(const Pyramid& pyramid, const SampleRect& window,
                               const std::function<void(float)>& progress) {
  const PyramidHeader& header = pyramid.header();
  if (window.empty() || window.x0 < 0 || window.y0 < 0 || window.x1 >= header.width || window.y1 >= header.height ||
      window.x1 == window.x0 || window.y1 == window.y0)
    return makeError(ErrorKind::InvalidArgument,
                     pyramid.path().string() + ": the window [" + std::to_string(window.x0) + ", " +
                         std::to_string(window.x1) + "] x [" + std::to_string(window.y0) + ", " +
                         std::to_string(window.y1) + "] is not at least 2 x 2 samples inside the " +
                         std::to_string(header.width) + " x " + std::to_string(header.height));
  const int width = window.x1 - window.x0 + 1, height = window.y1 - window.y0 + 1;
  Heightfield field;
  try {
    field = Heightfield(width, height, header.spacingX, header.spacingY);
  } catch (const std::bad_alloc&) {
    return makeError(ErrorKind::OutOfMemory, pyramid.path().string() + ": " + std::to_string(width) + " x " +
                                                 std::to_string(height) +
                                                 " samples do not fit in memory (stream the pyramid instead)");
  }
  const BlockLayout& layout = pyramid.layout();
  const int pitch = 1 << layout.k();
  // Footprints share their edge samples: the nodes that may hold a window sample.
  const int bxFirst = std::max(0, window.x0 / pitch - 1), bxLast = std::min(layout.nodesX(0) - 1, window.x1 / pitch);
  const int byFirst = std::max(0, window.y0 / pitch - 1), byLast = std::min(layout.nodesY(0) - 1, window.y1 / pitch);
  PyramidTile tile;
  for (int by = byFirst; by <= byLast; ++by) {
    for (int bx = bxFirst; bx <= bxLast; ++bx) {
      const NodeId node{0, std::uint32_t(bx), std::uint32_t(by)};
      const SampleRect area = layout.footprint(node);
      const int x0 = std::max(area.x0, window.x0), x1 = std::min(area.x1, window.x1);
      const int y0 = std::max(area.y0, window.y0), y1 = std::min(area.y1, window.y1);
      if (x1 < x0 || y1 < y0) continue;
      if (Status read = pyramid.readTile(node, tile); !read) return read.error();
      for (int y = y0; y <= y1; ++y)
        std::copy_n(tile.samples.heights.begin() + std::ptrdiff_t(tile.samples.index(x0 - area.x0, y - area.y0)),
                    x1 - x0 + 1, field.heights.begin() + std::ptrdiff_t(field.index(x0 - window.x0, y - window.y0)));
    }
    if (progress) progress(float(by - byFirst + 1) / float(byLast - byFirst + 1));
  }
  return field;
}

Result<Heightfield> readFullResolution(const Pyramid& pyramid, const std::function<void(float)>& progress) {
  const PyramidHeader& header = pyramid.header();
  return readWindow(pyramid, SampleRect{0, 0, header.width - 1, header.height - 1}, progress);
}

}  // namespace polder::terrain
