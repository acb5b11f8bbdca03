// A host program embedding Polder: generate a terrain, ask the query scene for a height.
#include <cstdio>

#include <polder/query/query_scene.hpp>
#include <polder/terrain/generator.hpp>

int main() {
  polder::terrain::GeneratorOptions options;
  options.size = 129;
  options.spacingM = 20.0;
  auto field = polder::terrain::generateTerrain(options);
  if (!field) return std::fprintf(stderr, "%s\n", field.error().message.c_str()), 1;
  auto scene = polder::query::QueryScene::create(*field);
  if (!scene) return std::fprintf(stderr, "%s\n", scene.error().message.c_str()), 1;
  const auto height = (*scene)->height(0.5 * field->extentX(), 0.5 * field->extentY());
  if (!height) return std::fprintf(stderr, "no height at the centre\n"), 1;
  std::printf("height at centre: %.2f m\n", *height);
  return 0;
}
