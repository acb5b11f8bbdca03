// polder gen: a realistic synthetic DEM (the bundled sample is made with it). Up to
// kLargestErodedSize the whole raster is eroded in memory; larger ones are made a band of rows
// at a time over an eroded base (generator_streamed.hpp) and written as they are made, so their
// size is bounded by the disk, not by memory.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <future>
#include <limits>
#include <memory>
#include <vector>

#include <polder/terrain/generator.hpp>
#include <polder/terrain/generator_streamed.hpp>
#include <polder/terrain/height_tiff_stream.hpp>
#include <polder/terrain/image_writer.hpp>
#include <polder/thread_pool.hpp>

#include "cli_support.hpp"
#include "commands.hpp"
#include "number_rules.hpp"

namespace polder::cli {
namespace {

// Full erosion grows as size^2 in time and memory: 8193^2 takes about four minutes and 3 GB.
constexpr int kLargestErodedSize = 8193;
// How much more a base sample costs to erode than a full-resolution sample to synthesise,
// to share the progress bar between the two.
constexpr double kErosionCostPerSample = 40.0;

struct GenArguments {
  terrain::GeneratorOptions generator;
  std::string out;
};

// Above kLargestErodedSize: the base eroded, then the bands generated on the pool while the
// previous band is compressed and written.
int runStreamedGen(const GenArguments& arguments) {
  const int size = arguments.generator.size;
  const double fullSamples = double(size) * double(size);
  const double baseSide = std::min(size, terrain::kDefaultStreamedBaseSize);
  const double baseCost = baseSide * baseSide * kErosionCostPerSample;
  const float baseShare = float(baseCost / (baseCost + fullSamples));
  const std::string side = std::to_string(size);

  ProgressBar progress("generating " + side + "^2");
  auto terrain = terrain::StreamedTerrain::create(arguments.generator, 0,
                                                  [&](float fraction) { progress.update(fraction * baseShare); });
  if (!terrain) return reportError(terrain.error());
  auto writer = terrain::HeightTiffStream::create(arguments.out, size, size, terrain->spacingM(), terrain->spacingM());
  if (!writer) return reportError(writer.error());

  core::ThreadPool pool;
  const int bandRows = terrain::HeightTiffStream::kTileSize;
  const std::size_t bandSamples = std::size_t(bandRows) * std::size_t(size);
  std::vector<float> south(bandSamples);
  std::vector<float> bands[2] = {std::vector<float>(bandSamples), std::vector<float>(bandSamples)};
  std::future<Status> writing;
  float low = std::numeric_limits<float>::infinity();
  float high = -std::numeric_limits<float>::infinity();
  for (int band = 0, top = size; top > 0; ++band, top -= bandRows) {
    const int count = std::min(bandRows, top);
    const std::size_t samples = std::size_t(count) * std::size_t(size);
    const std::span<float> rows(south.data(), samples);
    if (Status made = terrain->generateRows(top - count, count, rows, &pool); !made) return reportError(made.error());
    // The file goes north first; generateRows gives the band's southern row first.
    std::vector<float>& north = bands[band % 2];
    for (int r = 0; r < count; ++r)
      std::copy_n(south.data() + std::size_t(count - 1 - r) * std::size_t(size), size,
                  north.data() + std::size_t(r) * std::size_t(size));
    const auto [bandLow, bandHigh] = std::minmax_element(rows.begin(), rows.end());
    low = std::min(low, *bandLow);
    high = std::max(high, *bandHigh);
    if (writing.valid())
      if (Status written = writing.get(); !written) return reportError(written.error());
    writing = std::async(std::launch::async, [&writer, &north, count, samples] {
      return (*writer)->writeRows(count, std::span<const float>(north.data(), samples));
    });
    progress.update(baseShare + (1.0f - baseShare) * float(double(size - top + count) / double(size)));
  }
  if (Status written = writing.get(); !written) return reportError(written.error());
  if (Status finished = (*writer)->finish(); !finished) return reportError(finished.error());
  progress.finish();
  std::printf("wrote %s: %d x %d samples, %.1f m spacing, heights %.1f .. %.1f m (eroded base of %d^2)\n",
              arguments.out.c_str(), size, size, terrain->spacingM(), low, high, terrain->base().width);
  return 0;
}

int runGen(const GenArguments& arguments) {
  const std::filesystem::path out = arguments.out;
  const std::string extension = out.extension().string();
  const bool png = extension == ".png";
  const bool tiff = extension == ".tif" || extension == ".tiff";
  if (!png && !tiff)
    return reportError(
        makeError(ErrorKind::InvalidArgument,
                  "--out " + arguments.out + ": the file name must end in .png (16-bit) or .tif (float)"));
  if (arguments.generator.size > kLargestErodedSize) {
    if (!tiff)
      return reportError(makeError(ErrorKind::InvalidArgument,
                                   "--out " + arguments.out + ": DEMs above " + std::to_string(kLargestErodedSize) +
                                       " samples per side are written as tiled float TIFF (.tif)"));
    return runStreamedGen(arguments);
  }
  Result<terrain::Heightfield> field = makeError(ErrorKind::InvalidData, "not generated");
  {
    ProgressBar progress("generating " + std::to_string(arguments.generator.size) + "^2");
    field = terrain::generateTerrain(arguments.generator, [&](float fraction) { progress.update(fraction); });
  }
  if (!field) return reportError(field.error());
  const Status written = png ? terrain::writeHeightPng16(out, *field) : terrain::writeHeightTiffFloat(out, *field);
  if (!written) return reportError(written.error());
  const auto [low, high] = field->heightRange();
  std::printf("wrote %s: %d x %d samples, %.1f m spacing, heights %.1f .. %.1f m\n", arguments.out.c_str(),
              field->width, field->height, field->spacingX, low, high);
  return 0;
}

}  // namespace

void addGenCommand(CLI::App& app, int& exitCode) {
  auto arguments = std::make_shared<GenArguments>();
  CLI::App* command =
      app.add_subcommand("gen", "Generate a realistic synthetic DEM (ridged fractal relief with erosion)");
  command
      ->add_option("--size", arguments->generator.size,
                   "Samples per side; above " + std::to_string(kLargestErodedSize) +
                       " synthesised detail over an eroded base, written as it is made (.tif only)")
      ->check(numberIn(NumberRule{2.0, double(terrain::kMaxStreamedGeneratorSize), true, false, "samples"}))
      ->capture_default_str();
  addNumberOption(*command, "--seed", arguments->generator.seed, "Random seed (same seed, same terrain)", rules::kSeed);
  addNumberOption(*command, "--spacing", arguments->generator.spacingM, "Sample spacing in metres", rules::kSpacingM);
  command->add_option("--out", arguments->out, "Output file: .png (16-bit) or .tif (32-bit float)")->required();
  command->callback([arguments, &exitCode] { exitCode = runGen(*arguments); });
}

}  // namespace polder::cli
