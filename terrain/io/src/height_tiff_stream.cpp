#include <polder/terrain/height_tiff_stream.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <tiffio.h>

#include <polder/partial_file.hpp>

#include "io_text.hpp"
#include "tiff_tags.hpp"

namespace polder::terrain {
namespace {

// Classic TIFF offsets are 32-bit: above this much (uncompressed) the file is BigTIFF.
constexpr std::uint64_t kClassicTiffBytes = std::uint64_t(3) << 30;

class TiledHeightTiff final : public HeightTiffStream {
 public:
  TiledHeightTiff(const std::filesystem::path& path, int width, int height)
      : m_file(path), m_width(width), m_height(height) {}
  ~TiledHeightTiff() override {
    if (m_tiff) TIFFClose(m_tiff);
  }

  Status open(double spacingX, double spacingY) {
    const std::uint64_t bytes = std::uint64_t(m_width) * std::uint64_t(m_height) * sizeof(float);
    if (Status created = m_file.create(bytes, false); !created) return created;
    m_tiff = io::openTiff(m_file.path(), bytes > kClassicTiffBytes ? "w8" : "w", m_errors);
    if (!m_tiff) return fail(ErrorKind::Io, "cannot create the TIFF: " + io::oneLine(m_errors));
    if (!io::setHeightTiffTags(m_tiff, m_width, m_height, spacingX, spacingY))
      return fail(ErrorKind::Environment, "libtiff refused the GeoTIFF tags");
    TIFFSetField(m_tiff, TIFFTAG_TILEWIDTH, std::uint32_t(kTileSize));
    TIFFSetField(m_tiff, TIFFTAG_TILELENGTH, std::uint32_t(kTileSize));
    m_tile.resize(std::size_t(kTileSize) * kTileSize);
    return {};
  }

  int width() const override { return m_width; }
  int height() const override { return m_height; }
  int rowsWritten() const override { return m_rows; }

  Status writeRows(int count, std::span<const float> heights) override {
    if (m_failed) return fail(ErrorKind::InvalidArgument, "an earlier write failed");
    const int expected = std::min(kTileSize, m_height - m_rows);
    if (count != expected || expected == 0)
      return fail(ErrorKind::InvalidArgument, "a band of " + std::to_string(count) + " rows where " +
                                                  std::to_string(expected) + " remain to be written in this band");
    if (heights.size() != std::size_t(count) * std::size_t(m_width))
      return fail(ErrorKind::InvalidArgument, "a band of " + std::to_string(heights.size()) + " heights for " +
                                                  std::to_string(count) + " rows of " + std::to_string(m_width));
    for (std::size_t i = 0; i < heights.size(); ++i)
      if (!std::isfinite(heights[i]))
        return failed(ErrorKind::InvalidArgument,
                      "the height at column " + std::to_string(i % std::size_t(m_width)) + ", row " +
                          std::to_string(m_rows + int(i / std::size_t(m_width))) + " from the north is not finite");
    // Partial tiles at the east and south edges are padded with their last valid sample,
    // which compresses to nothing.
    for (int x0 = 0; x0 < m_width; x0 += kTileSize) {
      const int columns = std::min(kTileSize, m_width - x0);
      for (int r = 0; r < kTileSize; ++r) {
        const float* source = heights.data() + std::size_t(std::min(r, count - 1)) * std::size_t(m_width) + x0;
        float* target = m_tile.data() + std::size_t(r) * kTileSize;
        std::copy(source, source + columns, target);
        std::fill(target + columns, target + kTileSize, source[columns - 1]);
      }
      if (TIFFWriteTile(m_tiff, m_tile.data(), std::uint32_t(x0), std::uint32_t(m_rows), 0, 0) < 0)
        return failed(ErrorKind::Io, "cannot write the tile at column " + std::to_string(x0) + ", row " +
                                         std::to_string(m_rows) + ": " + io::oneLine(m_errors));
    }
    m_rows += count;
    return {};
  }

  Status finish() override {
    if (m_failed || m_rows != m_height)
      return fail(ErrorKind::InvalidArgument, std::to_string(m_rows) + " of " + std::to_string(m_height) +
                                                  " rows written" + (m_failed ? " before a failure" : ""));
    TIFF* tiff = m_tiff;
    m_tiff = nullptr;
    const bool flushed = TIFFFlush(tiff) == 1;
    TIFFClose(tiff);
    if (!flushed) return failed(ErrorKind::Io, "cannot finish the TIFF: " + io::oneLine(m_errors));
    if (Status committed = m_file.commit(); !committed) {
      m_failed = true;
      return committed;
    }
    return {};
  }

 private:
  Error fail(ErrorKind kind, const std::string& message) const {
    return makeError(kind, m_file.destination().string() + ": " + message);
  }
  Error failed(ErrorKind kind, const std::string& message) {
    m_failed = true;
    return fail(kind, message);
  }

  core::PartialFile m_file;
  std::string m_errors;  // libtiff's messages; outlives m_tiff
  TIFF* m_tiff = nullptr;
  int m_width;
  int m_height;
  int m_rows = 0;
  bool m_failed = false;
  std::vector<float> m_tile;
};

}  // namespace

Result<std::unique_ptr<HeightTiffStream>> HeightTiffStream::create(const std::filesystem::path& path, int width,
                                                                   int height, double spacingX, double spacingY) {
  if (width < 1 || height < 1)
    return makeError(ErrorKind::InvalidArgument, path.string() + ": a raster of " + std::to_string(width) + " x " +
                                                     std::to_string(height) + " samples");
  if (!(spacingX > 0.0 && spacingY > 0.0 && std::isfinite(spacingX) && std::isfinite(spacingY)))
    return makeError(ErrorKind::InvalidArgument, path.string() + ": the spacing is not positive and finite");
  auto writer = std::make_unique<TiledHeightTiff>(path, width, height);
  if (Status opened = writer->open(spacingX, spacingY); !opened) return opened.error();
  return std::unique_ptr<HeightTiffStream>(std::move(writer));
}

}  // namespace polder::terrain
