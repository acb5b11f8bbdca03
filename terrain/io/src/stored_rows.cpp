#include "stored_rows.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <string>
#include <vector>

#include "image_dem.hpp"
#include "io_text.hpp"

namespace polder::terrain::io {
namespace {

class FileRows final : public StoredRows {
 public:
  FileRows(int fd, std::uint64_t rowBytes) : m_fd(fd), m_rowBytes(rowBytes) {}
  ~FileRows() override { ::close(m_fd); }
  FileRows(const FileRows&) = delete;
  FileRows& operator=(const FileRows&) = delete;

  Status read(int first, int count, std::byte* out) override {
    const std::uint64_t start = std::uint64_t(first) * m_rowBytes;
    const std::uint64_t bytes = std::uint64_t(count) * m_rowBytes;
    std::uint64_t done = 0;
    while (done < bytes) {
      const std::size_t chunk = std::size_t(std::min<std::uint64_t>(bytes - done, std::uint64_t(1) << 30));
      const ssize_t got = ::pread(m_fd, out + done, chunk, off_t(start + done));
      if (got < 0 && errno == EINTR) continue;
      if (got < 0)
        return makeError(ErrorKind::Io, "cannot read rows " + std::to_string(first) + ".." +
                                            std::to_string(first + count - 1) +
                                            " from the north: " + std::strerror(errno));
      if (got == 0)  // shortened since it was opened
        return makeError(ErrorKind::InvalidData, "truncated: the file ends at byte " + std::to_string(start + done) +
                                                     ", inside row " + std::to_string((start + done) / m_rowBytes) +
                                                     " from the north");
      done += std::uint64_t(got);
    }
    return {};
  }

 private:
  int m_fd;
  std::uint64_t m_rowBytes;
};

// Bands above this many bytes are not kept: their rows are read one scanline at a time.
constexpr std::uint64_t kMaxBandBytes = std::uint64_t(256) << 20;

class ImageRows final : public StoredRows {
 public:
  ImageRows(std::unique_ptr<OIIO::ImageInput> input, int channels, OIIO::TypeDesc type)
      : m_input(std::move(input)), m_spec(m_input->spec()), m_channels(channels), m_type(type) {
    m_rowBytes = std::size_t(m_spec.width) * std::size_t(channels) * type.size();
    if (m_spec.tile_width > 0 && m_spec.tile_height > 0) {
      m_tiled = true;
      m_bandRows = m_spec.tile_height;  // tiles cannot be read in part
    } else if (std::string(m_input->format_name()) == "tiff") {
      // A compressed strip decodes whole: read whole strips, or libtiff starts over per row.
      const int rowsPerStrip = m_spec.get_int_attribute("tiff:RowsPerStrip", 0);
      if (rowsPerStrip > 1 && std::uint64_t(rowsPerStrip) * m_rowBytes <= kMaxBandBytes) m_bandRows = rowsPerStrip;
    }
    m_bandRows = std::min(m_bandRows, m_spec.height);
  }
  ~ImageRows() override { m_input->close(); }

  Status read(int first, int count, std::byte* out) override {
    if (!m_tiled && m_bandRows <= 1) return readScanlines(first, first + count, out);
    for (int row = first; row < first + count;) {
      const int band = row / m_bandRows;
      if (band != m_band)
        if (Status loaded = loadBand(band); !loaded) return loaded;
      const int bandEnd = std::min((band + 1) * m_bandRows, m_spec.height);
      const int rows = std::min(bandEnd, first + count) - row;
      std::memcpy(out + std::size_t(row - first) * m_rowBytes,
                  m_bandBytes.data() + std::size_t(row - band * m_bandRows) * m_rowBytes,
                  std::size_t(rows) * m_rowBytes);
      row += rows;
    }
    return {};
  }

 private:
  Status loadBand(int band) {
    m_band = -1;
    const int y0 = band * m_bandRows;
    const int y1 = std::min(y0 + m_bandRows, m_spec.height);
    m_bandBytes.resize(std::size_t(y1 - y0) * m_rowBytes);
    if (!m_tiled) {
      if (Status read = readScanlines(y0, y1, m_bandBytes.data()); !read) return read;
    } else if (Status read = checked(
                   m_input->read_tiles(0, 0, m_spec.x, m_spec.x + m_spec.width, m_spec.y + y0, m_spec.y + y1, m_spec.z,
                                       m_spec.z + std::max(1, m_spec.depth), 0, m_channels, m_type, m_bandBytes.data()),
                   y0, y1);
               !read) {
      return read;
    }
    m_band = band;
    return {};
  }

  Status readScanlines(int y0, int y1, std::byte* out) {
    return checked(m_input->read_scanlines(0, 0, m_spec.y + y0, m_spec.y + y1, m_spec.z, 0, m_channels, m_type, out),
                   y0, y1);
  }

  Status checked(bool succeeded, int y0, int y1) {
    const std::string problem = readProblem(*m_input, succeeded);
    if (problem.empty()) return {};
    return makeError(ErrorKind::InvalidData, "cannot read the pixels of rows " + std::to_string(y0) + ".." +
                                                 std::to_string(y1 - 1) + " from the north: " + problem);
  }

  std::unique_ptr<OIIO::ImageInput> m_input;
  OIIO::ImageSpec m_spec;
  int m_channels;
  OIIO::TypeDesc m_type;
  std::size_t m_rowBytes = 0;
  bool m_tiled = false;
  int m_bandRows = 0;  // 0: read scanlines as asked
  int m_band = -1;     // the band in m_bandBytes, -1 for none
  std::vector<std::byte> m_bandBytes;
};

}  // namespace

Result<std::unique_ptr<StoredRows>> openFileRows(const std::filesystem::path& path, std::uint64_t rowBytes) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return makeError(ErrorKind::Io, std::string("cannot open the file: ") + std::strerror(errno));
  return std::unique_ptr<StoredRows>(new FileRows(fd, rowBytes));
}

std::unique_ptr<StoredRows> imageRows(std::unique_ptr<OIIO::ImageInput> input, int channels, OIIO::TypeDesc type) {
  return std::make_unique<ImageRows>(std::move(input), channels, type);
}

}  // namespace polder::terrain::io
