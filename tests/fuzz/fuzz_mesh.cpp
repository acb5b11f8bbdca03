// Fuzz target: the mesh reader on PLY (ascii and binary) and OBJ. The first byte picks the
// extension; the rest is the file.
#include <cstddef>
#include <cstdint>

#include <polder/mesh_io/mesh_file.hpp>

#include "fuzz_input_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const auto path = polder::fuzz::writeInput(data + 1, size - 1, data[0] % 2 ? ".ply" : ".obj");
  (void)polder::mesh_io::readMesh(path);
  return 0;
}
