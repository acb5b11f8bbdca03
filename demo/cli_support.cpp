#include "cli_support.hpp"
#include "number_rules.hpp"

#include <unistd.h>
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <tuple>

#include <polder/terrain/dem_parsing.hpp>
#include <polder/terrain/dem_reader.hpp>
#include <polder/terrain/dem_rows.hpp>
#include <polder/terrain/pyramid.hpp>

namespace polder::cli {

void addDemArguments(CLI::App& command, DemArguments& arguments) {
  command.add_option("dem", arguments.path, "DEM file (PNG, TIFF/GeoTIFF, EXR, .hgt, .r16/.raw/.f32)")->required();
  command.add_option("--spacing", arguments.spacingM, "Sample spacing in metres (overrides the file)")
      ->check(numberIn(rules::kSpacingM));
  addNumberOption(command, "--zscale", arguments.zScale, "Metres per stored height unit", rules::kZScale);
  command
      .add_option("--encoding", arguments.encoding,
                  "Height encoding of RGB(A) images: auto|greyscale|terrain-rgb|terrarium")
      ->capture_default_str();
  command.add_option("--nodata", arguments.nodata, "auto (the file's no-data value and int16 -32768/-32767) or none")
      ->capture_default_str();
  command.add_option("--raw", arguments.raw, "Layout of a headerless raw file: WxH:u16|i16|f32[:le|be]");
  command.add_option("--window", arguments.window,
                     "Only the samples X0..X1 x Y0..Y1 (row 0 south, inclusive) as the DEM, its south-west "
                     "sample the origin; any part of a DEM larger than memory");
}

Result<terrain::DemOptions> demOptions(const DemArguments& arguments) {
  terrain::DemOptions options;
  if (arguments.spacingM) {
    if (!(*arguments.spacingM > 0.0) || !std::isfinite(*arguments.spacingM))
      return makeError(ErrorKind::InvalidArgument, "--spacing must be a positive number of metres");
    options.spacingM = arguments.spacingM;
  }
  if (!(arguments.zScale != 0.0) || !std::isfinite(arguments.zScale))
    return makeError(ErrorKind::InvalidArgument, "--zscale must be a finite, non-zero number");
  options.zScale = arguments.zScale;
  auto encoding = terrain::parseHeightEncoding(arguments.encoding);
  if (!encoding) return encoding.error();
  options.encoding = *encoding;
  if (arguments.nodata == "none") {
    options.nodataEnabled = false;
  } else if (arguments.nodata != "auto") {
    return makeError(ErrorKind::InvalidArgument, "--nodata must be 'auto' or 'none', not '" + arguments.nodata + "'");
  }
  if (!arguments.raw.empty()) {
    auto layout = terrain::parseRawLayout(arguments.raw);
    if (!layout) return layout.error();
    options.raw = *layout;
  }
  return options;
}

namespace {

Result<std::optional<terrain::SampleRect>> parseWindow(const std::string& text) {
  if (text.empty()) return std::optional<terrain::SampleRect>();
  auto numbers = parseNumbers(text, 4, "--window");
  if (!numbers) return numbers.error();
  const auto& v = *numbers;
  for (const double n : v)
    if (n != std::floor(n) || n < 0.0 || n > 2147483647.0)
      return makeError(ErrorKind::InvalidArgument, "--window " + text + ": give four whole sample indices X0,Y0,X1,Y1");
  const terrain::SampleRect window{int(v[0]), int(v[1]), int(v[2]), int(v[3])};
  if (window.x1 <= window.x0 || window.y1 <= window.y0)
    return makeError(ErrorKind::InvalidArgument, "--window " + text + ": X1 must exceed X0 and Y1 exceed Y0");
  return std::optional<terrain::SampleRect>(window);
}

Status checkWindow(const terrain::SampleRect& window, int width, int height) {
  if (window.x1 >= width || window.y1 >= height)
    return makeError(ErrorKind::InvalidArgument, "--window reaches past the DEM's " + std::to_string(width) + " x " +
                                                     std::to_string(height) + " samples");
  return {};
}

// A window of a DEM file, read a band of rows at a time.
Result<terrain::Dem> readDemWindow(const std::string& path, const terrain::DemOptions& options,
                                   const terrain::SampleRect& window) {
  auto opened = terrain::openDemRows(path, options);
  if (!opened) return opened.error();
  terrain::DemRows& rows = **opened;
  if (Status inside = checkWindow(window, rows.width(), rows.height()); !inside) return inside.error();
  terrain::Dem dem;
  dem.info = rows.info();
  const int width = window.x1 - window.x0 + 1, height = window.y1 - window.y0 + 1;
  dem.field = terrain::Heightfield(width, height, rows.spacingX(), rows.spacingY());
  constexpr int kBandRows = 64;
  std::vector<float> band;
  for (int y = window.y0; y <= window.y1; y += kBandRows) {
    const int count = std::min(kBandRows, window.y1 + 1 - y);
    band.resize(std::size_t(count) * std::size_t(rows.width()));
    if (Status read = rows.readRows(y, count, band); !read) return read.error();
    for (int r = 0; r < count; ++r)
      std::copy_n(band.begin() + std::ptrdiff_t(r) * rows.width() + window.x0, width,
                  dem.field.heights.begin() + std::ptrdiff_t(dem.field.index(0, y - window.y0 + r)));
  }
  const auto [low, high] = dem.field.heightRange();
  dem.info.minM = low;
  dem.info.maxM = high;
  return dem;
}

}  // namespace

Result<terrain::Dem> loadDem(const DemArguments& arguments) {
  auto options = demOptions(arguments);
  if (!options) return options.error();
  auto window = parseWindow(arguments.window);
  if (!window) return window.error();
  if (!terrain::looksLikePyramid(arguments.path)) {
    if (*window) return readDemWindow(arguments.path, *options, **window);
    return terrain::readDem(arguments.path, *options);
  }
  // A prepared pyramid: its full resolution, from the level-0 tiles.
  auto pyramid = terrain::Pyramid::open(arguments.path);
  if (!pyramid) return pyramid.error();
  if (*window)
    if (Status inside = checkWindow(**window, (*pyramid)->header().width, (*pyramid)->header().height); !inside)
      return inside.error();
  auto field = *window ? terrain::readWindow(**pyramid, **window) : terrain::readFullResolution(**pyramid);
  if (!field) return field.error();
  terrain::Dem dem;
  dem.field = std::move(field).value();
  if (options->spacingM) dem.field.spacingX = dem.field.spacingY = *options->spacingM;
  const terrain::PyramidHeader& header = (*pyramid)->header();
  dem.info.path = arguments.path;
  dem.info.format = "polder pyramid";
  dem.info.encoding = "float32";
  dem.info.minM = header.minHeight;
  dem.info.maxM = header.maxHeight;
  if (*window) std::tie(dem.info.minM, dem.info.maxM) = dem.field.heightRange();
  return dem;
}

Result<std::vector<double>> parseNumbers(std::string_view text, std::size_t count, std::string_view what) {
  std::vector<double> values;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    const std::string_view part = text.substr(start, comma - start);
    double value = 0.0;
    const auto [end, error] = std::from_chars(part.data(), part.data() + part.size(), value);
    if (part.empty() || error != std::errc() || end != part.data() + part.size() || !std::isfinite(value))
      return makeError(ErrorKind::InvalidArgument, std::string(what) + " expects " + std::to_string(count) +
                                                       " comma-separated numbers, got '" + std::string(text) + "'");
    if (!checkNumber(value, rules::kCoordinateM, ""))
      return makeError(ErrorKind::InvalidArgument,
                       std::string(what) + ": " + std::string(part) + " must be " + describe(rules::kCoordinateM));
    values.push_back(value);
    start = comma + 1;
  }
  if (values.size() != count)
    return makeError(ErrorKind::InvalidArgument, std::string(what) + " expects " + std::to_string(count) +
                                                     " comma-separated numbers, got " + std::to_string(values.size()));
  return values;
}

Result<std::pair<int, int>> parseImageSize(std::string_view text) {
  const auto x = text.find('x');
  int width = 0, height = 0;
  const bool parsed =
      x != std::string_view::npos && std::from_chars(text.data(), text.data() + x, width).ptr == text.data() + x &&
      std::from_chars(text.data() + x + 1, text.data() + text.size(), height).ptr == text.data() + text.size();
  if (!parsed)
    return makeError(ErrorKind::InvalidArgument, "--size expects WxH, e.g. 1280x720, got '" + std::string(text) + "'");
  if (width < 16 || height < 16 || width > 16384 || height > 16384)
    return makeError(ErrorKind::InvalidArgument,
                     "--size " + std::string(text) + " is out of range (16..16384 per side)");
  return std::pair{width, height};
}

Result<Camera> parseCamera(std::string_view pose, double fovDeg, std::string_view size) {
  auto numbers = parseNumbers(pose, 5, "--camera X,Y,Z,YAW,PITCH");
  if (!numbers) return numbers.error();
  if (!(fovDeg > 1.0 && fovDeg < 179.0))
    return makeError(ErrorKind::InvalidArgument, "--fov must be between 1 and 179 degrees");
  if (std::abs((*numbers)[4]) > 90.0)
    return makeError(ErrorKind::InvalidArgument, "camera pitch must be within -90..90 degrees");
  auto pixels = parseImageSize(size);
  if (!pixels) return pixels.error();
  Camera camera;
  camera.position = {(*numbers)[0], (*numbers)[1], (*numbers)[2]};
  camera.yawDeg = (*numbers)[3];
  camera.pitchDeg = (*numbers)[4];
  camera.fovYDeg = fovDeg;
  camera.widthPx = pixels->first;
  camera.heightPx = pixels->second;
  return camera;
}

DemExtent DemExtent::of(const terrain::Heightfield& field) {
  const auto [low, high] = field.heightRange();
  return DemExtent{field.width, field.height, field.spacingX, field.spacingY, low, high};
}

DemExtent DemExtent::of(const terrain::PyramidHeader& header) {
  return DemExtent{header.width, header.height, header.spacingX, header.spacingY, header.minHeight, header.maxHeight};
}

void fitClipPlanes(Camera& camera, double extentX, double extentY) {
  const double diagonal = std::hypot(extentX, extentY);
  const double heightRange = 1e4;  // generous: the camera may sit far above the relief
  camera.farM = 2.0 * (diagonal + heightRange + glm::length(camera.position));
  // A near plane proportional to the far plane keeps depth precision usable (24-bit depth).
  camera.nearM = std::max(0.1, camera.farM * 2e-6);
}

int reportError(const Error& error) {
  std::fprintf(stderr, "polder: error: %s\n", error.message.c_str());
  return error.kind == ErrorKind::InvalidArgument ? kExitUsage : kExitData;
}

ProgressBar::ProgressBar(std::string label)
    : m_label(std::move(label)),
      m_interactive(::isatty(STDERR_FILENO) != 0),
      m_start(std::chrono::steady_clock::now()) {}

ProgressBar::~ProgressBar() { finish(); }

namespace {

// "1:05" or "1:02:05".
std::string formatDuration(double seconds) {
  const long total = std::lround(std::max(seconds, 0.0));
  char text[32];
  if (total >= 3600)
    std::snprintf(text, sizeof text, "%ld:%02ld:%02ld", total / 3600, total / 60 % 60, total % 60);
  else
    std::snprintf(text, sizeof text, "%ld:%02ld", total / 60, total % 60);
  return text;
}

}  // namespace

void ProgressBar::update(float fraction) {
  if (!m_interactive || m_finished) return;
  const auto now = std::chrono::steady_clock::now();
  if (now - m_lastDraw < std::chrono::milliseconds(100) && fraction < 1.0f) return;
  m_lastDraw = now;
  constexpr int kWidth = 32;
  fraction = std::clamp(fraction, 0.0f, 1.0f);
  const int filled = std::clamp(int(fraction * kWidth + 0.5f), 0, kWidth);
  const double elapsed = std::chrono::duration<double>(now - m_start).count();
  // The rate so far predicts the rest; say nothing until there is a rate to go on.
  const std::string eta =
      fraction > 0.01f && elapsed > 1.0 ? "  ETA " + formatDuration(elapsed * (1.0 - fraction) / fraction) : "";
  std::fprintf(stderr, "\r%s [%.*s%*s] %3d%%  %s%s   ", m_label.c_str(), filled, "################################",
               kWidth - filled, "", int(fraction * 100.0f + 0.5f), formatDuration(elapsed).c_str(), eta.c_str());
  std::fflush(stderr);
}

void ProgressBar::finish() {
  if (m_finished) return;
  m_finished = true;
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
  if (m_interactive)
    std::fprintf(stderr, "\r%s [################################] 100%%  %s%*s\n", m_label.c_str(),
                 formatDuration(elapsed).c_str(), 16, "");
}

}  // namespace polder::cli
