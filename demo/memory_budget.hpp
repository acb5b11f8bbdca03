// --memory-mb, for the commands that fly the terrain engine: one budget for what the engine
// holds (TerrainEngineOptions::memoryBudgetBytes), and the engine made within it, from the
// heightfield or streamed from the pyramid the DEM argument names.
#pragma once

#include <functional>
#include <memory>

#include <CLI/CLI.hpp>

#include <polder/result.hpp>
#include <polder/terrain/pyramid.hpp>
#include <polder/terrain_engine.hpp>

#include "cli_support.hpp"

namespace polder::cli {

// Adds --memory-mb to `command`, into `memoryMb` (0, the default: no overall budget).
CLI::Option* addMemoryBudgetOption(CLI::App& command, double& memoryMb);

// The pyramid to stream when the DEM argument is one read as it is (no window, spacing or
// scale given: those make a heightfield of their own); null otherwise.
Result<std::shared_ptr<const terrain::Pyramid>> pyramidToStream(const DemArguments& dem);

// TerrainEngine::create with `memoryMb` as the options' memory budget, streamed from
// `pyramid` when it is given, else over `field`; a budget the DEM does not fit in is an error
// naming --memory-mb. The block size is the pyramid's.
Result<std::unique_ptr<TerrainEngine>> createEngineWithin(std::shared_ptr<const terrain::Heightfield> field,
                                                          std::shared_ptr<const terrain::Pyramid> pyramid,
                                                          TerrainEngineOptions options, double memoryMb,
                                                          const std::function<void(float)>& progress = {});

}  // namespace polder::cli
