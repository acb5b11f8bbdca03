// polder info DEM [--json]: what a DEM holds, as Polder reads it.
#include <cstdio>
#include <memory>

#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "commands.hpp"

namespace polder::cli {
namespace {

struct InfoArguments {
  DemArguments dem;
  bool json = false;
};

int runInfo(const InfoArguments& arguments) {
  auto dem = loadDem(arguments.dem);
  if (!dem) return reportError(dem.error());
  const auto& field = dem->field;
  const auto& info = dem->info;
  if (arguments.json) {
    const nlohmann::json report = {
        {"path", info.path},         {"width", field.width},
        {"height", field.height},    {"spacing_m", {field.spacingX, field.spacingY}},
        {"min_m", info.minM},        {"max_m", info.maxM},
        {"voids", info.voids},       {"format", info.format},
        {"encoding", info.encoding}, {"spacing_assumed", info.spacingAssumed},
    };
    std::printf("%s\n", report.dump(2).c_str());
    return 0;
  }
  std::printf("file      %s\n", info.path.c_str());
  std::printf("format    %s (%s)\n", info.format.c_str(), info.encoding.c_str());
  std::printf("size      %d x %d samples\n", field.width, field.height);
  std::printf("spacing   %.4f x %.4f m%s\n", field.spacingX, field.spacingY,
              info.spacingAssumed ? "  (assumed: nothing in the file gives it; use --spacing)" : "");
  std::printf("extent    %.1f x %.1f m\n", field.extentX(), field.extentY());
  std::printf("height    %.2f .. %.2f m\n", info.minM, info.maxM);
  std::printf("voids     %lld%s\n", static_cast<long long>(info.voids),
              info.voids > 0 ? " (filled from neighbours)" : "");
  return 0;
}

}  // namespace

void addInfoCommand(CLI::App& app, int& exitCode) {
  auto arguments = std::make_shared<InfoArguments>();
  CLI::App* command = app.add_subcommand("info", "Print a DEM's size, spacing, height range, voids and format");
  addDemArguments(*command, arguments->dem);
  command->add_flag("--json", arguments->json,
                    "Print JSON: width, height, spacing_m, min_m, max_m, voids, format, encoding, spacing_assumed");
  command->callback([arguments, &exitCode] { exitCode = runInfo(*arguments); });
}

}  // namespace polder::cli
