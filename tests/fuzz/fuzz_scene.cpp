// Fuzz target: scene file text, parsed and described (docs/scene_format.md). Nothing is
// loaded: the description only names the files a scene would read.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "scene_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  (void)polder::cli::parseSceneText(text, "fuzz/scene.json");
  return 0;
}
