// polder mesh DEM --max-error METRES [--block 33] --out FILE.obj|.ply|.glb [--json REPORT]:
// the blocks-plus-dikes mesh of the whole DEM within METRES of the full-resolution surface
// everywhere, measured exactly (terrain/uniform_mesh.hpp), for baking static terrain.
#include <cctype>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <new>
#include <string>
#include <system_error>

#include <nlohmann/json.hpp>

#include <polder/file_contents.hpp>
#include <polder/mesh_io/mesh_file.hpp>
#include <polder/terrain/uniform_mesh.hpp>
#include <polder/terrain/watertight.hpp>

#include "cli_support.hpp"
#include "commands.hpp"
#include "number_rules.hpp"

namespace polder::cli {
namespace {

struct MeshArguments {
  DemArguments dem;
  std::string maxError;
  int blockSamples = 33;
  std::string out;
  std::string json;
  bool finestOnly = false;
};

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

Result<double> parseMaxError(const std::string& text) {
  double value = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  const bool parsed = !text.empty() && error == std::errc() && end == text.data() + text.size();
  if (!parsed || !(value >= terrain::kUniformMeshMinErrorM && value <= terrain::kUniformMeshMaxErrorM))
    return makeError(ErrorKind::InvalidArgument,
                     "--max-error must be a number of metres between 0.001 and 100000, got '" + text + "'");
  return value;
}

// The folder a file goes to must exist before the work starts (the write itself is atomic).
Status checkOutputFolder(const std::string& file, const char* option) {
  const std::filesystem::path folder = std::filesystem::path(file).parent_path();
  std::error_code code;
  if (!folder.empty() && !std::filesystem::is_directory(folder, code))
    return makeError(ErrorKind::Io,
                     std::string(option) + " " + file + ": the folder " + folder.string() + " does not exist");
  return {};
}

int runMesh(const MeshArguments& arguments) {
  // Everything cheap is checked before the DEM is read.
  const Result<double> maxError = parseMaxError(arguments.maxError);
  if (!maxError) return reportError(maxError.error());
  int blockK = 0;
  for (int k = 4; k <= 7; ++k)
    if (arguments.blockSamples == (1 << k) + 1) blockK = k;
  if (blockK == 0)
    return reportError(makeError(ErrorKind::InvalidArgument,
                                 "--block must be 17, 33, 65 or 129, got " + std::to_string(arguments.blockSamples)));
  std::string extension = std::filesystem::path(arguments.out).extension().string();
  for (char& c : extension) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (extension != ".obj" && extension != ".ply" && extension != ".glb")
    return reportError(makeError(ErrorKind::InvalidArgument,
                                 "--out " + arguments.out + ": the file name must end in .obj, .ply or .glb"));
  if (Status folder = checkOutputFolder(arguments.out, "--out"); !folder) return reportError(folder.error());
  if (!arguments.json.empty())
    if (Status folder = checkOutputFolder(arguments.json, "--json"); !folder) return reportError(folder.error());

  auto dem = loadDem(arguments.dem);
  if (!dem) return reportError(dem.error());
  const terrain::Heightfield& field = dem->field;

  terrain::UniformMeshOptions options;
  options.maxErrorM = *maxError;
  options.blockK = blockK;
  options.coarserLevels = !arguments.finestOnly;
  const auto start = std::chrono::steady_clock::now();
  Result<terrain::UniformMesh> built = makeError(ErrorKind::InvalidData, "not built");
  {
    ProgressBar progress("meshing within " + arguments.maxError + " m");
    options.progress = [&progress](float fraction) { progress.update(fraction); };
    built = terrain::buildUniformMesh(field, options);
  }
  if (!built) return reportError(built.error());
  const double buildSeconds = secondsSince(start);
  const terrain::UniformMesh& result = *built;
  const auto checkStart = std::chrono::steady_clock::now();
  const terrain::WatertightReport watertight =
      terrain::checkWatertight(terrain::uniformMeshSoup(result), field.width, field.height);
  const double checkSeconds = secondsSince(checkStart);

  const auto writeStart = std::chrono::steady_clock::now();
  const mesh::TriangleMesh triangles = terrain::uniformMeshTriangles(field, result);
  if (Status written = mesh_io::writeMesh(arguments.out, triangles); !written) return reportError(written.error());
  const double writeSeconds = secondsSince(writeStart), totalSeconds = secondsSince(start);

  const std::size_t fullResolution = 2 * std::size_t(field.width - 1) * std::size_t(field.height - 1);
  std::printf("%-16s %s: %d x %d samples, %.2f x %.2f m\n", "dem", arguments.dem.path.c_str(), field.width,
              field.height, field.spacingX, field.spacingY);
  std::printf("%-16s %zu (%zu in blocks, %zu in dikes; %.1f%% of the full resolution's %zu), %zu vertices\n",
              "triangles", result.triangleCount(), result.stats.blockTriangles, result.stats.dikeTriangles,
              100.0 * double(result.triangleCount()) / double(fullResolution), fullResolution, triangles.vertexCount());
  std::printf("%-16s %.4f m measured (bound %s m; blocks %.4f, dikes %.4f)\n", "max error", result.maxErrorM(),
              arguments.maxError.c_str(), result.stats.blockMaxErrorM, result.stats.dikeMaxErrorM);
  std::printf("%-16s %s (%zu open edges, %zu T-junctions)\n", "watertight", watertight.watertight() ? "yes" : "NO",
              watertight.openEdges, watertight.tJunctions);
  std::printf("%-16s %.3f s to build, %.3f s to check watertight, %.3f s to write (%.3f s in all)\n", "time",
              buildSeconds, checkSeconds, writeSeconds, totalSeconds);
  std::printf("%-16s %s\n", "written", arguments.out.c_str());

  if (!arguments.json.empty()) {
    nlohmann::json levels = nlohmann::json::array();
    for (const std::size_t count : result.stats.nodesPerLevel) levels.push_back(count);
    const nlohmann::json report = {
        {"dem",
         {{"path", arguments.dem.path},
          {"width", field.width},
          {"height", field.height},
          {"spacing_m", {field.spacingX, field.spacingY}}}},
        {"max_error_bound_m", *maxError},
        {"block_samples", arguments.blockSamples},
        {"coarser_levels", options.coarserLevels},
        {"triangles", result.triangleCount()},
        {"block_triangles", result.stats.blockTriangles},
        {"dike_triangles", result.stats.dikeTriangles},
        {"vertices", triangles.vertexCount()},
        {"full_resolution_triangles", fullResolution},
        {"max_error_m", result.maxErrorM()},
        {"block_max_error_m", result.stats.blockMaxErrorM},
        {"dike_max_error_m", result.stats.dikeMaxErrorM},
        {"watertight",
         {{"ok", watertight.watertight()},
          {"open_edges", watertight.openEdges},
          {"t_junctions", watertight.tJunctions}}},
        {"nodes_per_level", levels},
        {"pinned_nodes", result.stats.pinnedNodes},
        {"split_nodes", result.stats.splitNodes},
        {"rounds", result.stats.rounds},
        {"build_s", buildSeconds},
        {"check_s", checkSeconds},
        {"write_s", writeSeconds},
        {"total_s", totalSeconds},
        {"out", arguments.out},
    };
    if (Status written = core::writeFileContents(arguments.json, report.dump(2) + "\n"); !written)
      return reportError(written.error());
  }
  // A mesh over the bound or with a crack would be a bug: say so in the exit code.
  return watertight.watertight() && double(result.maxErrorM()) <= *maxError ? 0 : kExitData;
}

}  // namespace

void addMeshCommand(CLI::App& app, int& exitCode) {
  auto arguments = std::make_shared<MeshArguments>();
  CLI::App* command = app.add_subcommand(
      "mesh", "Write the DEM as one watertight mesh within a vertical error everywhere (for baking)");
  addDemArguments(*command, arguments->dem);
  command->add_option("--max-error", arguments->maxError, "Largest vertical error against the DEM's surface, metres")
      ->check(numberIn(rules::kMaxErrorM))
      ->required()
      ->type_name("METRES");
  command->add_option("--block", arguments->blockSamples, "Block size in samples: 17, 33, 65 or 129")
      ->capture_default_str();
  command->add_option("--out", arguments->out, "Output mesh (.obj, .ply or .glb)")->required();
  command->add_option("--json", arguments->json, "Write a JSON report here");
  command->add_flag("--finest-blocks", arguments->finestOnly,
                    "Use level-0 blocks only (no coarser quadtree nodes where the terrain allows)");
  command->callback([arguments, &exitCode] {
    // Checking, converting and writing hold the mesh several times over: a DEM too large for
    // this machine at this bound ends with a message, not an abort.
    try {
      exitCode = runMesh(*arguments);
    } catch (const std::bad_alloc&) {
      exitCode =
          reportError(makeError(ErrorKind::OutOfMemory, "not enough memory for the mesh of " + arguments->dem.path +
                                                            " within " + arguments->maxError + " m"));
    }
  });
}

}  // namespace polder::cli
