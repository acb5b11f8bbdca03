#include <polder/terrain/dem_rows.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <new>
#include <string>
#include <vector>

#include <polder/terrain/dem_parsing.hpp>
#include <polder/terrain/dem_reader.hpp>
#include <polder/terrain/dem_validation.hpp>
#include <polder/terrain/hgt.hpp>
#include <polder/terrain/raw.hpp>
#include <polder/terrain/rgb_encoding.hpp>
#include <polder/terrain/samples.hpp>

#include "dem_file.hpp"
#include "image_dem.hpp"
#include "stored_rows.hpp"

namespace polder::terrain {
namespace {

// How a band's stored samples become metres (voids NaN, rows south first).
struct BandDecoder {
  SampleFormat format = SampleFormat::U16;
  int channels = 1;
  bool swapBytes = false;
  SampleDecoding decoding;
  HeightEncoding rgb = HeightEncoding::Greyscale;  // TerrainRgb or Terrarium: R, G, B(, A)
  bool alphaVoids = false;

  std::size_t rowBytes(int width) const {
    return std::size_t(width) * std::size_t(channels) * sampleFormatBytes(format);
  }
};

// What the file says, resolved as readDem's finishDem resolves it.
struct RasterHeader {
  int width = 0;
  int height = 0;
  double spacingX = 1.0;
  double spacingY = 1.0;
  DemInfo info;
};

void resolveSpacing(RasterHeader& header, const DemOptions& options, std::optional<GroundSpacing> fileSpacing) {
  header.info.spacingAssumed = false;
  if (options.spacingM) {
    header.spacingX = header.spacingY = *options.spacingM;
  } else if (fileSpacing) {
    header.spacingX = fileSpacing->x;
    header.spacingY = fileSpacing->y;
  } else {
    header.spacingX = header.spacingY = 1.0;
    header.info.spacingAssumed = true;
  }
}

// Fills the voids (NaN) of one row along it, linearly between the valid samples on either
// side, and returns how many there were; a row with none valid is left as it is.
int fillAlongRow(float* row, int width) {
  int voids = 0;
  int lastValid = -1;
  for (int x = 0; x < width; ++x) {
    if (std::isnan(row[x])) {
      ++voids;
      continue;
    }
    if (x > lastValid + 1) {
      const double right = row[x];
      const double left = lastValid < 0 ? right : double(row[lastValid]);
      for (int v = lastValid + 1; v < x; ++v)
        row[v] = lastValid < 0 ? row[x] : float(left + (right - left) * double(v - lastValid) / double(x - lastValid));
    }
    lastValid = x;
  }
  if (lastValid >= 0) std::fill(row + lastValid + 1, row + width, row[lastValid]);
  return voids;
}

class StreamedRows final : public DemRows {
 public:
  StreamedRows(RasterHeader header, std::unique_ptr<io::StoredRows> stored, const BandDecoder& decoder)
      : m_header(std::move(header)),
        m_stored(std::move(stored)),
        m_decoder(decoder),
        m_rowState(std::size_t(m_header.height), 0) {}

  int width() const override { return m_header.width; }
  int height() const override { return m_header.height; }
  double spacingX() const override { return m_header.spacingX; }
  double spacingY() const override { return m_header.spacingY; }
  const DemInfo& info() const override { return m_header.info; }
  bool streamed() const override { return true; }

  Status readRows(int y0, int count, std::span<float> out) override {
    try {
      if (Status read = readChecked(y0, count, out); !read) return named(read.error());
      return {};
    } catch (const std::bad_alloc&) {
      return named(makeError(ErrorKind::OutOfMemory, "out of memory while reading rows"));
    } catch (const std::exception& exception) {
      return named(makeError(ErrorKind::InvalidData, std::string("unexpected failure: ") + exception.what()));
    }
  }

 private:
  enum RowState : std::uint8_t { kKnown = 1, kValid = 2, kCounted = 4 };

  Error named(const Error& error) const { return makeError(error.kind, m_header.info.path + ": " + error.message); }

  Status readChecked(int y0, int count, std::span<float> out) {
    const int width = m_header.width;
    if (y0 < 0 || count < 0 || y0 > m_header.height - count)
      return makeError(ErrorKind::InvalidArgument, "rows " + std::to_string(y0) + " + " + std::to_string(count) +
                                                       " are outside the raster's " + std::to_string(m_header.height) +
                                                       " rows");
    if (out.size() != std::size_t(count) * std::size_t(width))
      return makeError(ErrorKind::InvalidArgument, "a buffer of " + std::to_string(out.size()) + " heights for " +
                                                       std::to_string(count) + " rows of " + std::to_string(width));
    if (count == 0) return {};
    if (Status read = decodeBand(y0, count, out.data()); !read) return read;

    std::vector<int> voidRows;  // rows without a valid sample, filled once the others are
    for (int i = 0; i < count; ++i) {
      const int voids = fillAlongRow(out.data() + std::size_t(i) * std::size_t(width), width);
      std::uint8_t& state = m_rowState[std::size_t(y0 + i)];
      state |= kKnown | (voids < width ? kValid : 0);
      if (!(state & kCounted)) m_header.info.voids += voids;
      state |= kCounted;
      if (voids == width) voidRows.push_back(i);
    }
    for (int i : voidRows) {
      auto source = nearestValidRow(y0 + i, y0, count, out.data());
      if (!source) return source.error();
      std::copy(*source, *source + width, out.data() + std::size_t(i) * std::size_t(width));
    }
    return {};
  }

  // Rows [y0, y0 + count) as heights with voids NaN.
  Status decodeBand(int y0, int count, float* out) {
    const int width = m_header.width;
    const int first = m_header.height - y0 - count;  // from the north
    m_bytes.resize(std::size_t(count) * m_decoder.rowBytes(width));
    if (Status read = m_stored->read(first, count, m_bytes.data()); !read) return read;
    Heightfield band;
    if (m_decoder.rgb != HeightEncoding::Greyscale) {
      const RgbView view{reinterpret_cast<const std::uint8_t*>(m_bytes.data()), width, count, m_decoder.channels};
      band = decodeRgbHeights(view, m_decoder.rgb, m_decoder.alphaVoids);
    } else {
      auto decoded = decodeSamples(source(m_bytes.data(), count), m_decoder.decoding);
      if (!decoded) return nameRow(first, count);
      band = std::move(*decoded);
    }
    std::copy(band.heights.begin(), band.heights.end(), out);
    return {};
  }

  SampleSource source(const std::byte* data, int rows) const {
    SampleSource source;
    source.data = data;
    source.format = m_decoder.format;
    source.width = m_header.width;
    source.height = rows;
    source.channels = m_decoder.channels;
    source.swapBytes = m_decoder.swapBytes;
    return source;
  }

  // The error of the first bad row of a band, its row counted in the whole file.
  Error nameRow(int first, int count) const {
    const std::size_t rowBytes = m_decoder.rowBytes(m_header.width);
    for (int i = 0; i < count; ++i) {
      auto decoded = decodeSamples(source(m_bytes.data() + std::size_t(i) * rowBytes, 1), m_decoder.decoding);
      if (decoded) continue;
      std::string message = decoded.error().message;
      const std::string inBand = "row 0 from the north";
      const std::string inFile = "row " + std::to_string(first + i) + " from the north";
      if (const auto at = message.find(inBand); at != std::string::npos)
        message.replace(at, inBand.size(), inFile);
      else
        message = inFile + ": " + message;
      return makeError(decoded.error().kind, message);
    }
    return makeError(ErrorKind::InvalidData, "cannot decode rows " + std::to_string(first) + ".." +
                                                 std::to_string(first + count - 1) + " from the north");
  }

  // The heights of the nearest row to `row` with a valid sample (the southern one of two),
  // filled along itself: from the band being read when it is there, else read alone.
  Result<const float*> nearestValidRow(int row, int y0, int count, const float* band) {
    for (int distance = 1;; ++distance) {
      bool inside = false;
      for (const int candidate : {row - distance, row + distance}) {
        if (candidate < 0 || candidate >= m_header.height) continue;
        inside = true;
        if (!(m_rowState[std::size_t(candidate)] & kKnown) || (m_rowState[std::size_t(candidate)] & kValid)) {
          if (candidate >= y0 && candidate < y0 + count)
            return band + std::size_t(candidate - y0) * std::size_t(m_header.width);
          if (m_lookupIndex != candidate)
            if (Status read = readLookupRow(candidate); !read) return read.error();
          if (m_rowState[std::size_t(candidate)] & kValid) return m_lookupRow.data();
        }
      }
      if (!inside)
        return makeError(ErrorKind::InvalidData,
                         "all " + std::to_string(std::uint64_t(m_header.width) * std::uint64_t(m_header.height)) +
                             " samples are no-data (voids)");
    }
  }

  Status readLookupRow(int row) {
    m_lookupIndex = -1;
    m_lookupRow.resize(std::size_t(m_header.width));
    if (Status read = decodeBand(row, 1, m_lookupRow.data()); !read) return read;
    const int voids = fillAlongRow(m_lookupRow.data(), m_header.width);
    m_rowState[std::size_t(row)] |= kKnown | (voids < m_header.width ? kValid : 0);
    m_lookupIndex = row;
    return {};
  }

  RasterHeader m_header;
  std::unique_ptr<io::StoredRows> m_stored;
  BandDecoder m_decoder;
  std::vector<std::byte> m_bytes;        // the stored samples of the band being read
  std::vector<std::uint8_t> m_rowState;  // RowState bits per row: O(height) bytes
  std::vector<float> m_lookupRow;        // a row read to fill a row without valid samples
  int m_lookupIndex = -1;                // which row m_lookupRow holds
};

// A DEM read whole by readDem, served from memory.
class WholeRows final : public DemRows {
 public:
  explicit WholeRows(Dem dem) : m_dem(std::move(dem)), m_rows(m_dem.field) {}
  int width() const override { return m_rows.width(); }
  int height() const override { return m_rows.height(); }
  double spacingX() const override { return m_rows.spacingX(); }
  double spacingY() const override { return m_rows.spacingY(); }
  const DemInfo& info() const override { return m_dem.info; }
  bool streamed() const override { return false; }
  Status readRows(int y0, int count, std::span<float> out) override {
    Status read = m_rows.readRows(y0, count, out);
    if (!read) return makeError(read.error().kind, m_dem.info.path + ": " + read.error().message);
    return {};
  }

 private:
  Dem m_dem;
  HeightfieldRows m_rows;
};

Status checkSingleChannel(const DemOptions& options, const char* what) {
  if (options.encoding == HeightEncoding::TerrainRgb || options.encoding == HeightEncoding::Terrarium)
    return makeError(ErrorKind::InvalidArgument, std::string(what) + "; the encoding option does not apply");
  return {};
}

SampleFormat rawSampleFormat(SampleType type) {
  switch (type) {
    case SampleType::U16:
      return SampleFormat::U16;
    case SampleType::I16:
      return SampleFormat::I16;
    case SampleType::F32:
      return SampleFormat::F32;
  }
  return SampleFormat::U16;
}

Result<std::unique_ptr<DemRows>> openStreamed(RasterHeader header, Result<std::unique_ptr<io::StoredRows>> stored,
                                              const BandDecoder& decoder) {
  if (!stored) return stored.error();
  if (Status spans = checkSpansGround(std::uint64_t(header.width), std::uint64_t(header.height)); !spans)
    return spans.error();
  return std::unique_ptr<DemRows>(new StreamedRows(std::move(header), std::move(*stored), decoder));
}

Result<std::unique_ptr<DemRows>> openRaw(const std::filesystem::path& path, std::uint64_t length,
                                         const DemOptions& options) {
  const RawLayout& layout = *options.raw;
  if (Status fits = io::checkRawLength(layout, length); !fits) return fits.error();
  if (Status single = checkSingleChannel(options, "a raw file holds one height per sample"); !single)
    return single.error();
  BandDecoder decoder;
  decoder.format = rawSampleFormat(layout.type);
  decoder.swapBytes = layout.bigEndian != (std::endian::native == std::endian::big);
  decoder.decoding.scale = options.zScale;
  decoder.decoding.int16Voids = options.nodataEnabled;
  RasterHeader header;
  header.info.path = path.string();
  header.width = layout.width;
  header.height = layout.height;
  header.info.format = "raw";
  header.info.encoding = sampleFormatName(decoder.format);
  resolveSpacing(header, options, std::nullopt);
  return openStreamed(std::move(header), io::openFileRows(path, decoder.rowBytes(layout.width)), decoder);
}

Result<std::unique_ptr<DemRows>> openHgt(const std::filesystem::path& path, std::uint64_t length,
                                         const DemOptions& options) {
  if (Status valid = checkHgtLength(length); !valid) return valid.error();
  if (Status single = checkSingleChannel(options, "an SRTM .hgt tile holds int16 heights"); !single)
    return single.error();
  const int size = hgtSizeFromLength(length);
  BandDecoder decoder;
  decoder.format = SampleFormat::I16;
  decoder.swapBytes = std::endian::native != std::endian::big;
  decoder.decoding.scale = options.zScale;
  decoder.decoding.int16Voids = options.nodataEnabled;
  // The tile's arc-seconds at its centre latitude, as decodeHgt gives them.
  std::optional<GroundSpacing> spacing;
  if (const auto south = hgtSouthLatitude(path.filename().string())) {
    const double arcDegrees = (size == 1201 ? 3.0 : 1.0) / 3600.0;
    const GroundSpacing perDegree = metresPerDegree(*south + 0.5);
    spacing = GroundSpacing{arcDegrees * perDegree.x, arcDegrees * perDegree.y};
  }
  RasterHeader header;
  header.info.path = path.string();
  header.width = header.height = size;
  header.info.format = "hgt";
  header.info.encoding = "int16";
  resolveSpacing(header, options, spacing);
  return openStreamed(std::move(header), io::openFileRows(path, decoder.rowBytes(size)), decoder);
}

// Read whole to detect the encoding from every pixel, as readDem does, when small enough.
Result<std::unique_ptr<DemRows>> openWhole(const std::filesystem::path& path, const DemOptions& options) {
  DemOptions whole = options;
  whole.memoryLimitBytes =
      options.memoryLimitBytes ? std::min(options.memoryLimitBytes, kDemRowsWholeReadBytes) : kDemRowsWholeReadBytes;
  auto dem = readDem(path, whole);
  if (!dem && dem.error().kind == ErrorKind::OutOfMemory) {
    std::string reason = dem.error().message;
    if (reason.rfind(path.string() + ": ", 0) == 0) reason.erase(0, path.string().size() + 2);
    return makeError(ErrorKind::OutOfMemory,
                     "an RGB image is read whole to detect its height encoding, and this one is too large (" + reason +
                         "); give the encoding (terrain-rgb, terrarium or greyscale) to read it by rows");
  }
  if (!dem) return dem.error();
  return std::unique_ptr<DemRows>(new WholeRows(std::move(*dem)));
}

Result<std::unique_ptr<DemRows>> openImage(const std::filesystem::path& path, std::uint64_t length,
                                           const DemOptions& options, bool& readWhole) {
  auto input = io::openHeightImage(path);
  if (!input) return input.error();
  const OIIO::ImageSpec spec = (*input)->spec();
  const std::string format = (*input)->format_name();
  auto sampling = io::imageSampling(spec, format, options);
  if (!sampling) return sampling.error();
  if (sampling->rgb && sampling->encoding == HeightEncoding::Auto) {
    readWhole = true;
    return makeError(ErrorKind::Unsupported, "read whole");
  }
  auto hints = io::readFileHints(path, length, format, spec, options);
  if (!hints) return hints.error();

  BandDecoder decoder;
  decoder.format = sampling->stored.format;
  decoder.channels = sampling->channels;
  decoder.decoding = hints->decoding;
  decoder.alphaVoids = options.nodataEnabled;
  RasterHeader header;
  header.info.path = path.string();
  header.width = spec.width;
  header.height = spec.height;
  header.info.format = hints->geoTiff ? "geotiff" : format;
  if (sampling->rgb) {
    decoder.rgb = sampling->encoding;
    header.info.encoding = heightEncodingName(sampling->encoding);
  } else {
    header.info.encoding = sampling->stored.name;
  }
  resolveSpacing(header, options, hints->spacing);
  // OpenImageIO gives samples in this machine's byte order.
  auto stored = io::imageRows(std::move(*input), sampling->channels, sampling->stored.request);
  return openStreamed(std::move(header), std::move(stored), decoder);
}

Result<std::unique_ptr<DemRows>> openAny(const std::filesystem::path& path, const DemOptions& options) {
  const auto file = io::classifyDemFile(path, options);
  if (!file) return file.error();
  switch (file->kind) {
    case io::DemFileKind::Raw:
      return openRaw(path, file->length, options);
    case io::DemFileKind::Hgt:
      return openHgt(path, file->length, options);
    case io::DemFileKind::Image:
      break;
  }
  bool readWhole = false;
  auto rows = openImage(path, file->length, options, readWhole);
  if (readWhole) return openWhole(path, options);
  return rows;
}

}  // namespace

Result<std::unique_ptr<DemRows>> openDemRows(const std::filesystem::path& path, const DemOptions& options) {
  const auto named = [&](const Error& error) {
    // The whole-raster reader names the file itself.
    if (error.message.rfind(path.string() + ": ", 0) == 0) return error;
    return makeError(error.kind, path.string() + ": " + error.message);
  };
  try {
    auto rows = openAny(path, options);
    if (!rows) return named(rows.error());
    return rows;
  } catch (const std::bad_alloc&) {
    return named(makeError(ErrorKind::OutOfMemory, "out of memory while opening"));
  } catch (const std::exception& exception) {
    return named(makeError(ErrorKind::InvalidData, std::string("unexpected failure: ") + exception.what()));
  }
}

}  // namespace polder::terrain
