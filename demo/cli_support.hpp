// What every `polder` subcommand shares: DEM options, number lists, the camera, errors
// turned into messages and exit codes, and a progress bar. The program talks; the library
// does not.
#pragma once

#include <chrono>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <CLI/CLI.hpp>

#include <polder/camera.hpp>
#include <polder/result.hpp>
#include <polder/terrain/dem.hpp>
#include <polder/terrain/pyramid.hpp>

namespace polder::cli {

// Exit codes: 0 success, 1 bad data or environment, 2 bad usage.
inline constexpr int kExitData = 1;
inline constexpr int kExitUsage = 2;

struct DemArguments {
  std::string path;
  std::optional<double> spacingM;
  double zScale = 1.0;
  std::string encoding = "auto";
  std::string nodata = "auto";
  std::string raw;
  std::string window;  // "X0,Y0,X1,Y1" in samples, or empty for the whole DEM
};

// Adds the DEM positional argument and the options every DEM-reading command takes.
void addDemArguments(CLI::App& command, DemArguments& arguments);

// The reader's options from the arguments; InvalidArgument naming the option.
Result<terrain::DemOptions> demOptions(const DemArguments& arguments);

// Reads the DEM the arguments describe, or the full resolution of a pyramid (polder prep);
// with --window only that part, read a band of rows (or the overlapping tiles) at a time, so
// any part of a DEM larger than memory can be loaded.
Result<terrain::Dem> loadDem(const DemArguments& arguments);

// Parses "a,b,c" into exactly `count` finite numbers; `what` names the option in errors.
Result<std::vector<double>> parseNumbers(std::string_view text, std::size_t count, std::string_view what);

// Parses "WxH" (both 16..16384).
Result<std::pair<int, int>> parseImageSize(std::string_view text);

// A camera from "X,Y,Z,YAW,PITCH", a field of view and an image size "WxH".
Result<Camera> parseCamera(std::string_view pose, double fovDeg, std::string_view size);

// A DEM's size and height range, from its heightfield or, unread, from a pyramid's header.
struct DemExtent {
  int width = 0, height = 0;  // samples
  double spacingX = 1.0, spacingY = 1.0;
  float minHeight = 0.0f, maxHeight = 0.0f;

  double extentX() const { return (width - 1) * spacingX; }
  double extentY() const { return (height - 1) * spacingY; }
  static DemExtent of(const terrain::Heightfield& field);
  static DemExtent of(const terrain::PyramidHeader& header);
};

// Near/far planes suited to a terrain of this extent seen from this camera.
void fitClipPlanes(Camera& camera, double extentX, double extentY);
inline void fitClipPlanes(Camera& camera, const terrain::Heightfield& field) {
  fitClipPlanes(camera, field.extentX(), field.extentY());
}

// Prints "polder: error: ..." and returns the exit code for this kind of error.
int reportError(const Error& error);

// A one-line progress bar on stderr, redrawn at most every 100 ms; silent when stderr is not
// a terminal except for the final line. Shows the time so far and, once the rate is known, an
// estimate of the time left.
class ProgressBar {
 public:
  explicit ProgressBar(std::string label);
  ~ProgressBar();
  void update(float fraction);
  void finish();

 private:
  std::string m_label;
  bool m_interactive;
  bool m_finished = false;
  std::chrono::steady_clock::time_point m_start;
  std::chrono::steady_clock::time_point m_lastDraw{};
};

}  // namespace polder::cli
