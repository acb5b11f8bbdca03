// The mesh format a file name asks for, shared by readMesh and writeMesh.
#pragma once

#include <cctype>
#include <filesystem>
#include <string>

#include <polder/result.hpp>

namespace polder::mesh_io::detail {

enum class MeshFormat { Obj, Ply };

// The format of the file's extension (any case), or Unsupported with a message that does
// not name the file (the caller prefixes it).
inline Result<MeshFormat> meshFormatOf(const std::filesystem::path& file) {
  std::string extension = file.extension().string();
  for (char& c : extension) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (extension == ".obj") return MeshFormat::Obj;
  if (extension == ".ply") return MeshFormat::Ply;
  return makeError(ErrorKind::Unsupported, "unsupported mesh format '" + extension + "' (expected .obj or .ply)");
}

}  // namespace polder::mesh_io::detail
