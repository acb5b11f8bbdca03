// The mesh format a file name asks for, shared by readMesh and writeMesh.
#pragma once

#include <cctype>
#include <filesystem>
#include <string>

#include <polder/result.hpp>

namespace polder::mesh_io::detail {

enum class MeshFormat { Obj, Ply, Glb };

// The format of the file's extension (any case), or Unsupported with a message that does
// not name the file (the caller prefixes it). glTF binary is written, not read.
inline Result<MeshFormat> meshFormatOf(const std::filesystem::path& file, bool writing = false) {
  std::string extension = file.extension().string();
  for (char& c : extension) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (extension == ".obj") return MeshFormat::Obj;
  if (extension == ".ply") return MeshFormat::Ply;
  if (writing && extension == ".glb") return MeshFormat::Glb;
  return makeError(ErrorKind::Unsupported,
                   "unsupported mesh format '" + extension + "' (expected .obj, .ply" + (writing ? ", .glb)" : ")"));
}

}  // namespace polder::mesh_io::detail
