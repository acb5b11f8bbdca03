#include "memory_budget.hpp"

#include <utility>

#include "number_rules.hpp"

namespace polder::cli {

CLI::Option* addMemoryBudgetOption(CLI::App& command, double& memoryMb) {
  return addNumberOption(command, "--memory-mb", memoryMb,
                         "One budget in MiB for the engine's heightfield, quadtree, block hierarchies and LOD cache",
                         rules::kMemoryMb);
}

Result<std::unique_ptr<TerrainEngine>> createEngineWithin(std::shared_ptr<const terrain::Heightfield> field,
                                                          TerrainEngineOptions options, double memoryMb,
                                                          const std::function<void(float)>& progress) {
  options.memoryBudgetBytes = std::size_t(memoryMb * 1048576.0);
  auto engine = TerrainEngine::create(std::move(field), options, progress);
  // The commands check every other option before, so a refused argument is the budget.
  if (!engine && engine.error().kind == ErrorKind::InvalidArgument && memoryMb > 0)
    return makeError(ErrorKind::InvalidArgument, "--memory-mb: " + engine.error().message);
  return engine;
}

}  // namespace polder::cli
