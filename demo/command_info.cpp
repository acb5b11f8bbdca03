// polder info DEM [--json]: what a DEM holds, as Polder reads it. The DEM is read a band of
// rows at a time (dem_rows.hpp), so a DEM of any size needs O(width) memory; a prepared
// pyramid is described from its header.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include <nlohmann/json.hpp>

#include <polder/terrain/dem_rows.hpp>
#include <polder/terrain/pyramid.hpp>

#include "cli_support.hpp"
#include "commands.hpp"

namespace polder::cli {
namespace {

constexpr int kBandRows = 256;
constexpr double kProgressSamples = double(1 << 24);  // below this a pass takes well under a second

struct InfoArguments {
  DemArguments dem;
  bool json = false;
};

struct InfoReport {
  terrain::DemInfo info;
  int width = 0;
  int height = 0;
  double spacingX = 1.0;
  double spacingY = 1.0;
  std::optional<double> meanM;
};

// One pass over every row for the height range, the mean and the voids.
Result<InfoReport> scanDem(const DemArguments& arguments, const terrain::DemOptions& options) {
  auto opened = terrain::openDemRows(arguments.path, options);
  if (!opened) return opened.error();
  terrain::DemRows& rows = **opened;
  const int width = rows.width();
  const int height = rows.height();
  std::optional<ProgressBar> progress;
  if (double(width) * double(height) >= kProgressSamples)
    progress.emplace("reading " + std::to_string(width) + " x " + std::to_string(height));

  float low = std::numeric_limits<float>::infinity();
  float high = -std::numeric_limits<float>::infinity();
  double sum = 0.0;
  std::vector<float> band;
  // North to south: the order files store their rows, the fast one for every format.
  for (int top = height; top > 0; top -= kBandRows) {
    const int count = std::min(kBandRows, top);
    band.resize(std::size_t(count) * std::size_t(width));
    if (Status read = rows.readRows(top - count, count, band); !read) return read.error();
    for (const float h : band) {
      low = std::min(low, h);
      high = std::max(high, h);
    }
    for (int y = 0; y < count; ++y) {  // a sum per row keeps the rounding small
      double row = 0.0;
      for (int x = 0; x < width; ++x) row += band[std::size_t(y) * std::size_t(width) + std::size_t(x)];
      sum += row;
    }
    if (progress) progress->update(float(height - top + count) / float(height));
  }

  InfoReport report{rows.info(), width, height, rows.spacingX(), rows.spacingY()};
  report.info.minM = low;
  report.info.maxM = high;
  report.meanM = sum / (double(width) * double(height));
  return report;
}

Result<InfoReport> describePyramid(const DemArguments& arguments, const terrain::DemOptions& options) {
  auto pyramid = terrain::Pyramid::open(arguments.path);
  if (!pyramid) return pyramid.error();
  const terrain::PyramidHeader& header = (*pyramid)->header();
  InfoReport report;
  report.info.path = arguments.path;
  report.info.format = "polder pyramid";
  report.info.encoding = "float32";
  report.info.minM = header.minHeight;
  report.info.maxM = header.maxHeight;
  report.width = header.width;
  report.height = header.height;
  report.spacingX = options.spacingM.value_or(header.spacingX);
  report.spacingY = options.spacingM.value_or(header.spacingY);
  return report;
}

int runInfo(const InfoArguments& arguments) {
  if (!arguments.dem.window.empty())
    return reportError(
        makeError(ErrorKind::InvalidArgument, "--window applies to the commands that load the DEM, not to this one"));
  auto options = demOptions(arguments.dem);
  if (!options) return reportError(options.error());
  auto report = terrain::looksLikePyramid(arguments.dem.path) ? describePyramid(arguments.dem, *options)
                                                              : scanDem(arguments.dem, *options);
  if (!report) return reportError(report.error());
  const terrain::DemInfo& info = report->info;
  if (arguments.json) {
    nlohmann::json json = {
        {"path", info.path},         {"width", report->width},
        {"height", report->height},  {"spacing_m", {report->spacingX, report->spacingY}},
        {"min_m", info.minM},        {"max_m", info.maxM},
        {"voids", info.voids},       {"format", info.format},
        {"encoding", info.encoding}, {"spacing_assumed", info.spacingAssumed},
    };
    if (report->meanM) json["mean_m"] = *report->meanM;
    std::printf("%s\n", json.dump(2).c_str());
    return 0;
  }
  std::printf("file      %s\n", info.path.c_str());
  std::printf("format    %s (%s)\n", info.format.c_str(), info.encoding.c_str());
  std::printf("size      %d x %d samples\n", report->width, report->height);
  std::printf("spacing   %.4f x %.4f m%s\n", report->spacingX, report->spacingY,
              info.spacingAssumed ? "  (assumed: nothing in the file gives it; use --spacing)" : "");
  std::printf("extent    %.1f x %.1f m\n", (report->width - 1) * report->spacingX,
              (report->height - 1) * report->spacingY);
  std::printf("height    %.2f .. %.2f m", info.minM, info.maxM);
  if (report->meanM) std::printf(", mean %.2f m", *report->meanM);
  std::printf("\n");
  std::printf("voids     %lld%s\n", static_cast<long long>(info.voids),
              info.voids > 0 ? " (filled from the valid samples beside them)" : "");
  return 0;
}

}  // namespace

void addInfoCommand(CLI::App& app, int& exitCode) {
  auto arguments = std::make_shared<InfoArguments>();
  CLI::App* command = app.add_subcommand("info", "Print a DEM's size, spacing, height range, voids and format");
  addDemArguments(*command, arguments->dem);
  command->add_flag("--json", arguments->json,
                    "Print JSON: width, height, spacing_m, min_m, max_m, mean_m, voids, format, encoding, "
                    "spacing_assumed");
  command->callback([arguments, &exitCode] { exitCode = runInfo(*arguments); });
}

}  // namespace polder::cli
