// A generated terrain for tests that need realistic relief but no file (link polder::terrain).
#pragma once

#include <cstdint>
#include <memory>

#include <gtest/gtest.h>

#include <polder/terrain/generator.hpp>

namespace polder::test {

// size x size samples at 30 m, the same relief for the same seed.
inline terrain::Heightfield generatedTerrain(int size, std::uint64_t seed) {
  terrain::GeneratorOptions options;
  options.size = size;
  options.seed = seed;
  options.spacingM = 30.0;
  auto field = terrain::generateTerrain(options);
  EXPECT_TRUE(field.ok()) << field.error().message;
  return field.ok() ? std::move(*field) : terrain::Heightfield{};
}

// The same, shared, as the terrain engine takes it.
inline std::shared_ptr<terrain::Heightfield> sharedGeneratedTerrain(int size, std::uint64_t seed) {
  return std::make_shared<terrain::Heightfield>(generatedTerrain(size, seed));
}

}  // namespace polder::test
