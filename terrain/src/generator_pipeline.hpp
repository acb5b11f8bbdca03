// The parts of generateTerrain that the streamed generator shares: the option checks and
// the erosion stages, run in generateTerrain's order.
#pragma once

#include <functional>
#include <optional>
#include <string>

#include <polder/result.hpp>
#include <polder/terrain/generator.hpp>

namespace polder::terrain::pipeline {

// generateTerrain's checks, with sizes up to `maxSize`; messages start with "caller: ".
std::optional<Error> validateOptions(const GeneratorOptions& options, int maxSize, const std::string& caller);

// Stages 2..5 of generator.hpp (thermal, fluvial at half resolution, droplets, fill) on a
// relief; `progress` reports 0..1.
void erode(Heightfield& field, const GeneratorOptions& options, const std::function<void(float)>& progress);

// Maps a stage's 0..1 onto [begin, end] of the whole run (`progress` must outlive the result).
std::function<void(float)> subRange(const std::function<void(float)>& progress, float begin, float end);

}  // namespace polder::terrain::pipeline
