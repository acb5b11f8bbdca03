// polder simplify MESH --triangles N [--builder collapse|cluster] [--regions R] --out OUT
// [--json REPORT]: builds a progressive mesh, extracts N triangles, writes them and
// measures what was lost against the original.
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <unordered_map>
#include <unordered_set>

#include <nlohmann/json.hpp>

#include <polder/file_contents.hpp>
#include <polder/mesh/cluster_builder.hpp>
#include <polder/mesh/collapse_builder.hpp>
#include <polder/mesh/level_selection.hpp>
#include <polder/mesh/mesh_extraction.hpp>
#include <polder/mesh/progressive_mesh.hpp>
#include <polder/mesh/progressive_mesh_build.hpp>
#include <polder/mesh/progressive_mesh_instance.hpp>
#include <polder/mesh_io/mesh_file.hpp>
#include <polder/query/surface_deviation.hpp>

#include "cli_support.hpp"
#include "commands.hpp"
#include "number_rules.hpp"

namespace polder::cli {
namespace {

struct SimplifyArguments {
  std::string input;
  std::uint64_t triangles = 0;
  std::string builder = "collapse";
  std::uint32_t regions = 1;
  std::string out;
  std::string json;
  std::string texture;
  bool ignoreAttributes = false;
  bool weldUvSeams = false;
  std::size_t samples = 200000;
};

double millisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

struct PositionHash {
  std::size_t operator()(const glm::vec3& p) const {
    std::uint32_t bits[3];
    std::memcpy(bits, &p, sizeof bits);
    return (std::size_t(bits[0]) * 73856093u) ^ (std::size_t(bits[1]) * 19349663u) ^ (std::size_t(bits[2]) * 83492791u);
  }
};

// Every output vertex must be an input vertex, attributes included: checked, not assumed.
bool isSubsetOfOriginal(const mesh::TriangleMesh& original, const mesh::TriangleMesh& simplified) {
  std::unordered_multimap<glm::vec3, std::uint32_t, PositionHash> byPosition;
  byPosition.reserve(original.vertexCount());
  for (std::uint32_t v = 0; v < original.vertexCount(); ++v) byPosition.emplace(original.positions[v], v);
  for (std::uint32_t v = 0; v < simplified.vertexCount(); ++v) {
    auto [first, last] = byPosition.equal_range(simplified.positions[v]);
    bool found = false;
    for (auto it = first; it != last && !found; ++it) {
      const std::uint32_t o = it->second;
      found = (!simplified.hasColours() || simplified.colours[v] == original.colours[o]) &&
              (!simplified.hasUvs() || simplified.uvs[v] == original.uvs[o]) &&
              (!simplified.hasNormals() || simplified.normals[v] == original.normals[o]);
    }
    if (!found) return false;
  }
  return true;
}

// Open edges of the output that do not lie on the original's open boundary: an output open
// edge is allowed only between two vertices of original open edges. Both are taken with
// positions welded, so a crack along a texture seam counts.
std::size_t openEdgesAdded(const mesh::TriangleMesh& original, const mesh::TriangleMesh& simplified) {
  std::unordered_set<glm::vec3, PositionHash> boundary;
  for (const auto& [a, b] : mesh::openEdges(mesh::indicesWeldedByPosition(original.indices, original.positions))) {
    boundary.insert(original.positions[a]);
    boundary.insert(original.positions[b]);
  }
  std::size_t added = 0;
  for (const auto& [a, b] : mesh::openEdges(mesh::indicesWeldedByPosition(simplified.indices, simplified.positions)))
    added += !(boundary.contains(simplified.positions[a]) && boundary.contains(simplified.positions[b]));
  return added;
}

int runSimplify(const SimplifyArguments& arguments) {
  const std::filesystem::path outPath(arguments.out);
  const std::string outExtension = outPath.extension().string();
  if (outExtension != ".obj" && outExtension != ".ply")
    return reportError(makeError(ErrorKind::InvalidArgument, arguments.out + ": --out must end in .obj or .ply"));
  if (arguments.triangles == 0)
    return reportError(makeError(ErrorKind::InvalidArgument, "--triangles must be at least 1"));

  mesh_io::MeshReadOptions readOptions;
  readOptions.keepUvSeams = !arguments.weldUvSeams;  // the output keeps the texture's seams
  if (!arguments.texture.empty()) readOptions.bakeTexture = arguments.texture;
  auto original = mesh_io::readMesh(arguments.input, readOptions);
  if (!original) return reportError(original.error());
  if (original->triangleCount() == 0)
    return reportError(makeError(ErrorKind::InvalidData, arguments.input + ": the mesh has no triangles"));
  std::printf("%-20s %s: %zu vertices, %zu triangles%s%s\n", "input", arguments.input.c_str(), original->vertexCount(),
              original->triangleCount(), original->hasColours() ? ", colours" : "", original->hasUvs() ? ", uvs" : "");

  const mesh::RegionPartition partition =
      arguments.regions <= 1 ? mesh::singleRegion() : mesh::automaticPartition(original->positions, arguments.regions);
  const auto buildStart = std::chrono::steady_clock::now();
  Result<mesh::ProgressiveMesh> progressive = makeError(ErrorKind::InvalidArgument, "unknown builder");
  {
    ProgressBar progress("building (" + arguments.builder + ")");
    if (arguments.builder == "collapse") {
      mesh::CollapseOptions options;
      if (arguments.ignoreAttributes) options.colourWeight = options.uvWeight = options.normalWeight = 0.0;
      options.progress = [&progress](double f) { progress.update(static_cast<float>(f)); };
      progressive = mesh::buildProgressiveMesh(*original, partition, options);
    } else {
      mesh::ClusterOptions options;
      if (arguments.ignoreAttributes) options.colourWeight = 0.0;
      options.progress = [&progress](double f) { progress.update(static_cast<float>(f)); };
      progressive = mesh::buildProgressiveMesh(*original, partition, options);
    }
  }
  if (!progressive) return reportError(progressive.error());
  const double buildMs = millisecondsSince(buildStart);

  const auto extractStart = std::chrono::steady_clock::now();
  mesh::ProgressiveMeshInstance instance(*progressive);
  std::vector<std::uint32_t> levels(progressive->regionCount());
  mesh::levelsForTriangleBudget(*progressive, arguments.triangles, levels);
  for (std::uint32_t r = 0; r < progressive->regionCount(); ++r) instance.setLevel(r, levels[r]);
  instance.resolveBorders();
  const mesh::TriangleMesh simplified = mesh::extractMesh(instance);
  const double extractMs = millisecondsSince(extractStart);

  // Measured before writing, so that a mesh the measure refuses leaves no output behind.
  query::SurfaceDeviationOptions deviationOptions;
  deviationOptions.samplesPerSurface = arguments.samples;
  auto deviation = query::measureSurfaceDeviation(*original, simplified, deviationOptions);
  if (!deviation)
    return reportError(makeError(deviation.error().kind, arguments.input + ": " + deviation.error().message));
  if (Status written = mesh_io::writeMesh(outPath, simplified); !written) return reportError(written.error());
  const bool subset = isSubsetOfOriginal(*original, simplified);
  const std::size_t addedOpenEdges = openEdgesAdded(*original, simplified);
  std::uint32_t baseTriangles = 0;
  for (std::uint32_t r = 0; r < progressive->regionCount(); ++r) baseTriangles += progressive->region(r).trianglesAt(0);

  std::printf("%-20s %zu (asked %llu; the base mesh has %u)\n", "output triangles", simplified.triangleCount(),
              static_cast<unsigned long long>(arguments.triangles), baseTriangles);
  std::printf("%-20s %s, %u region(s), %zu steps\n", "sequence", arguments.builder.c_str(), progressive->regionCount(),
              progressive->stepCount());
  std::printf("%-20s %.1f ms build (%.2f M input triangles/s), %.2f ms extract\n", "time", buildMs,
              original->triangleCount() / buildMs / 1000.0, extractMs);
  std::printf("%-20s hausdorff %.3g, rms %.3g (of the bounding-box diagonal)%s\n", "distance", deviation->hausdorff,
              deviation->rms, "");
  if (original->hasColours()) std::printf("%-20s %.4g (RMS, RGB in [0,1])\n", "colour error", deviation->colourRms);
  std::printf("%-20s %s, %zu open edges added\n", "checks", subset ? "original vertices only" : "NEW VERTICES",
              addedOpenEdges);
  std::printf("%-20s %s\n", "written", arguments.out.c_str());

  if (!arguments.json.empty()) {
    nlohmann::json report = {
        {"input", arguments.input},
        {"builder", arguments.builder},
        {"regions", progressive->regionCount()},
        {"input_triangles", original->triangleCount()},
        {"output_triangles", simplified.triangleCount()},
        {"build_ms", buildMs},
        {"extract_ms", extractMs},
        {"sequence_length", progressive->stepCount()},
        {"subset_of_original", subset},
        {"open_edges_added", addedOpenEdges},
        {"hausdorff", deviation->hausdorff},
        {"rms", deviation->rms},
    };
    if (original->hasColours()) report["colour_error"] = deviation->colourRms;
    if (Status written = core::writeFileContents(arguments.json, report.dump(2) + "\n"); !written)
      return reportError(written.error());
  }
  return subset ? 0 : kExitData;
}

}  // namespace

void addSimplifyCommand(CLI::App& app, int& exitCode) {
  auto arguments = std::make_shared<SimplifyArguments>();
  CLI::App* command = app.add_subcommand("simplify", "Build a progressive mesh and write it at N triangles");
  command->add_option("mesh", arguments->input, "OBJ or PLY mesh")->required();
  command->add_option("--triangles", arguments->triangles, "Triangles to keep")
      ->check(numberIn(rules::kTriangles))
      ->required();
  command
      ->add_option("--builder", arguments->builder,
                   "collapse (quadric half-edge collapses) or cluster (floating-cell clustering)")
      ->check(CLI::IsMember({"collapse", "cluster"}));
  command->add_option("--regions", arguments->regions, "Split the mesh into about this many regions")
      ->check(numberIn(rules::kRegions))
      ->check(CLI::Range(1u, 100000u));
  command->add_option("--out", arguments->out, "Output mesh (.obj or .ply)")->required();
  command->add_option("--json", arguments->json, "Write a JSON report here");
  command->add_option("--texture", arguments->texture, "Bake this texture into vertex colours at the mesh's UVs");
  command->add_flag("--ignore-attributes", arguments->ignoreAttributes, "Simplify by geometry only");
  command->add_flag("--weld-uv-seams", arguments->weldUvSeams,
                    "Weld vertices split only by texture coordinates (seams then simplify freely, the texture smears "
                    "along them)");
  command->add_option("--samples", arguments->samples, "Surface samples per mesh for the distances")
      ->check(numberIn(rules::kSamples))
      ->check(CLI::Range(std::size_t(1000), std::size_t(100000000)));
  command->callback([arguments, &exitCode] { exitCode = runSimplify(*arguments); });
}

}  // namespace polder::cli
