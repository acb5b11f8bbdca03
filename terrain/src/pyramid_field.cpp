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

Result<Heightfield> readFullResolution(const Pyramid& pyramid, const std::function<void(float)>& progress) {
  const PyramidHeader& header = pyramid.header();
  Heightfield field;
  try {
    field = Heightfield(header.width, header.height, header.spacingX, header.spacingY);
  } catch (const std::bad_alloc&) {
    return makeError(ErrorKind::OutOfMemory, pyramid.path().string() + ": " + std::to_string(header.width) + " x " +
                                                 std::to_string(header.height) +
                                                 " samples do not fit in memory (stream the pyramid instead)");
  }
  const BlockLayout& layout = pyramid.layout();
  PyramidTile tile;
  const int rows = layout.nodesY(0), columns = layout.nodesX(0);
  for (int by = 0; by < rows; ++by) {
    for (int bx = 0; bx < columns; ++bx) {
      const NodeId node{0, std::uint32_t(bx), std::uint32_t(by)};
      if (Status read = pyramid.readTile(node, tile); !read) return read.error();
      const SampleRect area = layout.footprint(node);
      for (int j = 0; j < tile.samples.height; ++j)
        std::copy_n(tile.samples.heights.begin() + std::ptrdiff_t(j) * tile.samples.width, tile.samples.width,
                    field.heights.begin() + std::ptrdiff_t(field.index(area.x0, area.y0 + j)));
    }
    if (progress) progress(float(by + 1) / float(rows));
  }
  return field;
}

}  // namespace polder::terrain
