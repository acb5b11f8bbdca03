// polder prep DEM --out PYRAMID: a DEM prepared for streaming (docs/streaming.md), read a
// band of rows at a time so that DEMs larger than memory prepare in bounded memory.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>

#include <polder/terrain/dem_rows.hpp>
#include <polder/terrain/pyramid_build.hpp>
#include <polder/thread_pool.hpp>

#include "cli_support.hpp"
#include "commands.hpp"
#include "number_rules.hpp"

namespace polder::cli {
namespace {

struct PrepArguments {
  DemArguments dem;
  std::string out;
  int block = 33;
  int threads = 0;
};

int runPrep(const PrepArguments& arguments) {
  int k = 1;
  while (k <= 7 && (1 << k) + 1 != arguments.block) ++k;
  if (k > 7)
    return reportError(makeError(
        ErrorKind::InvalidArgument,
        "--block " + std::to_string(arguments.block) + ": must be 2^k + 1 samples: 3, 5, 9, 17, 33, 65 or 129"));
  if (arguments.threads < 0 || arguments.threads > 1024)
    return reportError(makeError(ErrorKind::InvalidArgument, "--threads must be 0 (all) .. 1024"));
  std::error_code same;
  if (std::filesystem::equivalent(arguments.dem.path, arguments.out, same))
    return reportError(makeError(ErrorKind::InvalidArgument, "--out " + arguments.out + ": is the input DEM"));
  if (!arguments.dem.window.empty())
    return reportError(
        makeError(ErrorKind::InvalidArgument, "--window applies to the commands that load the DEM, not to this one"));
  auto options = demOptions(arguments.dem);
  if (!options) return reportError(options.error());
  auto rows = terrain::openDemRows(arguments.dem.path, *options);
  if (!rows) return reportError(rows.error());
  terrain::HeightRows& source = **rows;

  core::ThreadPool pool(arguments.threads);
  terrain::PyramidBuildOptions build;
  build.k = k;
  build.pool = &pool;
  build.sourceName = std::filesystem::path(arguments.dem.path).filename().string();
  const auto start = std::chrono::steady_clock::now();
  Result<terrain::PyramidBuildReport> report = makeError(ErrorKind::InvalidData, "not prepared");
  {
    ProgressBar progress("preparing " + std::to_string(source.width()) + " x " + std::to_string(source.height()));
    build.progress = [&](float fraction) { progress.update(fraction); };
    report = terrain::buildPyramid(source, arguments.out, build);
  }
  if (!report) return reportError(report.error());
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double samples = double(source.width()) * double(source.height());
  std::printf("wrote %s: %d x %d samples, %llu nodes in blocks of %d, %.1f MiB, %.1f s (%.1f M samples/s)\n",
              arguments.out.c_str(), source.width(), source.height(), static_cast<unsigned long long>(report->nodes),
              arguments.block, double(report->fileBytes) / 1048576.0, seconds, samples / seconds / 1e6);
  return 0;
}

}  // namespace

void addPrepCommand(CLI::App& app, int& exitCode) {
  auto arguments = std::make_shared<PrepArguments>();
  CLI::App* command = app.add_subcommand(
      "prep", "Prepare a DEM for streaming: a tiled pyramid of every quadtree level with its error bounds");
  addDemArguments(*command, arguments->dem);
  command->add_option("--out", arguments->out, "The pyramid file to write (replaced only when complete)")->required();
  command->add_option("--block", arguments->block, "Block size in samples, 2^k + 1")->capture_default_str();
  addNumberOption(*command, "--threads", arguments->threads, "Worker threads (0: all)", rules::kThreads);
  command->callback([arguments, &exitCode] { exitCode = runPrep(*arguments); });
}

}  // namespace polder::cli
