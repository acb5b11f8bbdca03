#include "memory_budget.hpp"

#include <utility>

#include "number_rules.hpp"

namespace polder::cli {

CLI::Option* addMemoryBudgetOption(CLI::App& command, double& memoryMb) {
  return addNumberOption(
      command, "--memory-mb", memoryMb,
      "One budget in MiB for the engine's heightfield (or a pyramid's tables), quadtree, blocks and LOD cache",
      rules::kMemoryMb);
}

Result<std::shared_ptr<const terrain::Pyramid>> pyramidToStream(const DemArguments& dem) {
  const bool asItIs = dem.window.empty() && !dem.spacingM && dem.zScale == 1.0;
  if (!asItIs || !terrain::looksLikePyramid(dem.path)) return std::shared_ptr<const terrain::Pyramid>();
  auto pyramid = terrain::Pyramid::open(dem.path);
  if (!pyramid) return pyramid.error();
  return std::shared_ptr<const terrain::Pyramid>(std::move(*pyramid));
}

Result<std::unique_ptr<TerrainEngine>> createEngineWithin(std::shared_ptr<const terrain::Heightfield> field,
                                                          std::shared_ptr<const terrain::Pyramid> pyramid,
                                                          TerrainEngineOptions options, double memoryMb,
                                                          const std::function<void(float)>& progress) {
  options.memoryBudgetBytes = std::size_t(memoryMb * 1048576.0);
  if (pyramid) options.blockK = pyramid->header().k;
  auto engine = pyramid ? TerrainEngine::create(std::move(pyramid), options, progress)
                        : TerrainEngine::create(std::move(field), options, progress);
  // The commands check every other option before, so a refused argument is the budget.
  if (!engine && engine.error().kind == ErrorKind::InvalidArgument && memoryMb > 0)
    return makeError(ErrorKind::InvalidArgument, "--memory-mb: " + engine.error().message);
  return engine;
}

}  // namespace polder::cli
