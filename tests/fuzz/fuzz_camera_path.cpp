// Fuzz target: camera path text ("t x y z yaw pitch" lines), parsed and sampled.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include <polder/camera_path.hpp>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  auto path = polder::CameraPath::parse(std::string_view(reinterpret_cast<const char*>(data), size));
  if (!path) return 0;
  const double duration = path->durationS();
  for (int i = 0; i <= 16; ++i) (void)path->at(path->poses().front().timeS + duration * i / 16.0);
  return 0;
}
