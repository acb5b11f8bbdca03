// polder gen: a realistic synthetic DEM (the bundled sample is made with it).
#include <cstdio>
#include <filesystem>
#include <memory>

#include <polder/terrain/generator.hpp>
#include <polder/terrain/image_writer.hpp>

#include "cli_support.hpp"
#include "commands.hpp"

namespace polder::cli {
namespace {

struct GenArguments {
  terrain::GeneratorOptions generator;
  std::string out;
};

int runGen(const GenArguments& arguments) {
  const std::filesystem::path out = arguments.out;
  const std::string extension = out.extension().string();
  const bool png = extension == ".png";
  const bool tiff = extension == ".tif" || extension == ".tiff";
  if (!png && !tiff)
    return reportError(
        makeError(ErrorKind::InvalidArgument,
                  "--out " + arguments.out + ": the file name must end in .png (16-bit) or .tif (float)"));
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
  command->add_option("--size", arguments->generator.size, "Samples per side")->capture_default_str();
  command->add_option("--seed", arguments->generator.seed, "Random seed (same seed, same terrain)")
      ->capture_default_str();
  command->add_option("--spacing", arguments->generator.spacingM, "Sample spacing in metres")->capture_default_str();
  command->add_option("--out", arguments->out, "Output file: .png (16-bit) or .tif (32-bit float)")->required();
  command->callback([arguments, &exitCode] { exitCode = runGen(*arguments); });
}

}  // namespace polder::cli
