// readMesh: our structure checks, then Assimp, then merging, baking, welding and normals.
#include <polder/mesh_io/mesh_file.hpp>

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/IOStream.hpp>
#include <assimp/IOSystem.hpp>
#include <assimp/Importer.hpp>

#include <cassert>
#include <cmath>
#include <exception>
#include <limits>
#include <new>
#include <string>

#include <polder/file_contents.hpp>
#include <polder/one_line.hpp>

#include "mesh_format.hpp"
#include "obj_check.hpp"
#include "ply_check.hpp"
#include "texture_bake.hpp"
#include "vertex_merge.hpp"

namespace polder::mesh_io {
namespace {

using detail::MeshFormat;

// Larger than any mesh the engine draws; a bigger file is refused before it is read.
constexpr std::uint64_t kMaxMeshFileBytes = std::uint64_t(4) << 30;

// The importer gets the file from memory; every other file it asks for (an OBJ's mtllib)
// is refused, so nothing outside the checked bytes is read. Materials are not used.
class NoFileSystem : public Assimp::IOSystem {
 public:
  bool Exists(const char*) const override { return false; }
  char getOsSeparator() const override { return '/'; }
  Assimp::IOStream* Open(const char*, const char*) override { return nullptr; }
  void Close(Assimp::IOStream* stream) override { delete stream; }
};

// Assimp's meshes as they come, before any merging of vertices: normals are zero where a
// mesh has none (when some have), colours white, texture coordinates (0, 0).
Result<mesh::TriangleMesh> mergeMeshes(const aiScene& scene) {
  bool anyNormals = false, anyColours = false, anyUvs = false;
  std::size_t vertexTotal = 0;
  for (unsigned m = 0; m < scene.mNumMeshes; ++m) {
    const aiMesh* part = scene.mMeshes[m];
    if (!part || !part->mVertices) continue;
    anyNormals = anyNormals || part->HasNormals();
    anyColours = anyColours || part->HasVertexColors(0);
    anyUvs = anyUvs || part->HasTextureCoords(0);
    vertexTotal += part->mNumVertices;
  }
  if (vertexTotal > std::numeric_limits<std::uint32_t>::max())
    return makeError(ErrorKind::Unsupported, "more than 2^32 - 1 vertices");
  mesh::TriangleMesh merged;
  merged.positions.reserve(vertexTotal);
  for (unsigned m = 0; m < scene.mNumMeshes; ++m) {
    const aiMesh* part = scene.mMeshes[m];
    if (!part || !part->mVertices) continue;
    const std::uint32_t base = std::uint32_t(merged.positions.size());
    for (unsigned i = 0; i < part->mNumVertices; ++i) {
      const aiVector3D& p = part->mVertices[i];
      merged.positions.emplace_back(p.x, p.y, p.z);
      if (anyNormals) {
        const aiVector3D n = part->HasNormals() ? part->mNormals[i] : aiVector3D(0.0f);
        merged.normals.emplace_back(n.x, n.y, n.z);
      }
      if (anyColours) {
        const aiColor4D c = part->HasVertexColors(0) ? part->mColors[0][i] : aiColor4D(1.0f, 1.0f, 1.0f, 1.0f);
        merged.colours.emplace_back(detail::unitColour(c.r), detail::unitColour(c.g), detail::unitColour(c.b),
                                    detail::unitColour(c.a));
      }
      if (anyUvs) {
        const aiVector3D t = part->HasTextureCoords(0) ? part->mTextureCoords[0][i] : aiVector3D(0.0f);
        merged.uvs.emplace_back(t.x, t.y);
      }
    }
    for (unsigned f = 0; f < part->mNumFaces; ++f) {
      const aiFace& face = part->mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines
      for (int k = 0; k < 3; ++k) merged.indices.push_back(base + face.mIndices[k]);
    }
  }
  return merged;
}

// Indices are checked before triangulation: Assimp's PLY reader passes any index through,
// and triangulating a polygon with an index out of range reads outside the vertex array.
Status checkFaceIndices(const aiScene& scene) {
  for (unsigned m = 0; m < scene.mNumMeshes; ++m) {
    const aiMesh* part = scene.mMeshes[m];
    if (!part) continue;
    if (part->mNumFaces > 0 && !part->mFaces) return makeError(ErrorKind::InvalidData, "a mesh has faces without data");
    const std::string where = scene.mNumMeshes > 1 ? " of mesh " + std::to_string(m + 1) : std::string();
    for (unsigned f = 0; f < part->mNumFaces; ++f) {
      const aiFace& face = part->mFaces[f];
      if (face.mNumIndices > 0 && !face.mIndices) return makeError(ErrorKind::InvalidData, "a face has no index data");
      for (unsigned k = 0; k < face.mNumIndices; ++k) {
        if (face.mIndices[k] >= part->mNumVertices || !part->mVertices)
          return makeError(ErrorKind::InvalidData, "face " + std::to_string(f + 1) + where + " refers to vertex " +
                                                       std::to_string(face.mIndices[k]) + " (counting from 0) of " +
                                                       std::to_string(part->mNumVertices));
      }
    }
  }
  return {};
}

Result<mesh::TriangleMesh> importWithAssimp(const std::string& bytes, MeshFormat format) {
  try {
    Assimp::Importer importer;
    importer.SetIOHandler(new NoFileSystem);  // the importer owns it
    // Read without post-processing first, so the indices can be checked before
    // triangulation uses them. No aiProcess_JoinIdenticalVertices: it merges positions up
    // to an epsilon and treats NaN as equal to anything (see vertex_merge.hpp instead).
    const aiScene* scene =
        importer.ReadFileFromMemory(bytes.data(), bytes.size(), 0, format == MeshFormat::Obj ? "obj" : "ply");
    if (!scene)
      return makeError(ErrorKind::InvalidData, "Assimp cannot read it: " + oneLine(importer.GetErrorString()));
    if (Status indices = checkFaceIndices(*scene); !indices) return indices.error();
    scene = importer.ApplyPostProcessing(aiProcess_Triangulate);
    if (!scene)
      return makeError(ErrorKind::InvalidData, "Assimp cannot triangulate it: " + oneLine(importer.GetErrorString()));
    return mergeMeshes(*scene);
  } catch (const std::bad_alloc&) {
    return makeError(ErrorKind::OutOfMemory, "not enough memory to import it");
  } catch (const std::exception& exception) {
    return makeError(ErrorKind::InvalidData, "Assimp failed: " + oneLine(exception.what()));
  } catch (...) {
    return makeError(ErrorKind::InvalidData, "Assimp failed with an unknown exception");
  }
}

// The file's normals where usable (normalised unless already unit), computed ones elsewhere.
// The mesh has normals exactly when the file had some (mergeMeshes, merging and welding keep
// that).
void resolveNormals(mesh::TriangleMesh& mesh) {
  if (!mesh.hasNormals()) {
    mesh.normals = mesh::computeVertexNormals(mesh.positions, mesh.indices);
    return;
  }
  std::vector<glm::vec3> computed;  // only once a file normal is unusable
  for (std::size_t i = 0; i < mesh.normals.size(); ++i) {
    glm::vec3& normal = mesh.normals[i];
    const float length = glm::length(normal);
    if (!(length > 0.0f) || !std::isfinite(length)) {
      if (computed.empty()) computed = mesh::computeVertexNormals(mesh.positions, mesh.indices);
      normal = computed[i];
    } else if (std::fabs(length - 1.0f) > 1e-5f) {  // leave unit normals bit for bit as read
      normal /= length;
    }
  }
}

Result<mesh::TriangleMesh> readMeshUnguarded(const std::filesystem::path& file, const MeshReadOptions& options) {
  const std::string name = file.string();
  const auto named = [&](const Error& error) { return makeError(error.kind, name + ": " + error.message); };
  const Result<MeshFormat> format = detail::meshFormatOf(file);
  if (!format) return named(format.error());

  Result<std::string> bytes = core::readFileContents(file, kMaxMeshFileBytes);
  if (!bytes) return named(bytes.error());
  if (bytes->empty()) return named(makeError(ErrorKind::InvalidData, "the file is empty"));
  if (*format == MeshFormat::Ply) {
    if (Status structure = detail::checkPlyStructure(*bytes); !structure) return named(structure.error());
  } else {
    Result<std::string> normalized = detail::normalizeObj(*bytes);
    if (!normalized) return named(normalized.error());
    *bytes = std::move(*normalized);
  }

  Result<mesh::TriangleMesh> imported = importWithAssimp(*bytes, *format);
  if (!imported) return named(imported.error());
  mesh::TriangleMesh& mesh = *imported;
  if (mesh.triangleCount() == 0)
    return named(makeError(ErrorKind::InvalidData, "no triangles (nothing, or only points and lines)"));
  if (Status valid = mesh::validateMesh(mesh, name); !valid) return valid.error();  // NaN positions

  detail::joinIdenticalVertices(mesh);
  if (!options.bakeTexture.empty()) {
    if (!mesh.hasUvs())
      return named(makeError(ErrorKind::InvalidArgument,
                             "cannot bake " + options.bakeTexture.string() + ": the mesh has no texture coordinates"));
    Result<std::vector<glm::vec4>> colours = detail::sampleTexture(options.bakeTexture, mesh.uvs);
    if (!colours) return named(colours.error());
    mesh.colours = std::move(*colours);
  }
  if (options.weldPositions) {
    detail::weldPositions(mesh, options.keepUvSeams);
    if (mesh.triangleCount() == 0)
      return named(makeError(ErrorKind::InvalidData, "every triangle is degenerate after welding"));
  }
  resolveNormals(mesh);
  // Merging, baking, welding and normals keep what the check above established.
  assert(mesh::validateMesh(mesh, name).ok());
  return std::move(mesh);
}

}  // namespace

Result<mesh::TriangleMesh> readMesh(const std::filesystem::path& file, const MeshReadOptions& options) {
  // Merging and welding allocate; nothing may escape the API as an exception.
  try {
    return readMeshUnguarded(file, options);
  } catch (const std::bad_alloc&) {
    return makeError(ErrorKind::OutOfMemory, file.string() + ": not enough memory to read the mesh");
  } catch (const std::exception& exception) {
    return makeError(ErrorKind::InvalidData, file.string() + ": " + oneLine(exception.what()));
  }
}

}  // namespace polder::mesh_io
