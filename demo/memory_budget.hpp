// --memory-mb, for the commands that fly the terrain engine: one budget for what the engine
// holds (TerrainEngineOptions::memoryBudgetBytes), and the engine made within it.
#pragma once

#include <functional>
#include <memory>

#include <CLI/CLI.hpp>

#include <polder/result.hpp>
#include <polder/terrain_engine.hpp>

namespace polder::cli {

// Adds --memory-mb to `command`, into `memoryMb` (0, the default: no overall budget).
CLI::Option* addMemoryBudgetOption(CLI::App& command, double& memoryMb);

// TerrainEngine::create with `memoryMb` as the options' memory budget; a budget the DEM does
// not fit in is an error naming --memory-mb.
Result<std::unique_ptr<TerrainEngine>> createEngineWithin(std::shared_ptr<const terrain::Heightfield> field,
                                                          TerrainEngineOptions options, double memoryMb,
                                                          const std::function<void(float)>& progress = {});

}  // namespace polder::cli
