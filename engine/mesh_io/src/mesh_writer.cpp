// writeMesh: OBJ, PLY and glTF binary written by hand (exact numbers, see float_text.hpp), then put in
// place with a rename.
#include <polder/mesh_io/mesh_file.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <exception>
#include <limits>
#include <new>
#include <string>
#include <string_view>
#include <vector>

#include <polder/file_contents.hpp>

#include "float_text.hpp"
#include "glb_writer.hpp"
#include "little_endian.hpp"
#include "mesh_format.hpp"

namespace polder::mesh_io {
namespace {

using detail::appendLittleEndian;
using mesh::TriangleMesh;

void appendIndex(std::string& out, std::uint64_t value) {
  char buffer[24];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
}

void appendFloats(std::string& out, std::initializer_list<float> values) {
  for (float value : values) {
    out += ' ';
    detail::appendFloat(out, value);
  }
}

std::string objText(const TriangleMesh& mesh) {
  std::string out;
  out.reserve(mesh.vertexCount() * 80 + mesh.triangleCount() * 40);
  out += "# Polder mesh: " + std::to_string(mesh.vertexCount()) + " vertices, " + std::to_string(mesh.triangleCount()) +
         " triangles\n";
  for (std::size_t i = 0; i < mesh.vertexCount(); ++i) {
    const glm::vec3& p = mesh.positions[i];
    out += 'v';
    appendFloats(out, {p.x, p.y, p.z});
    if (mesh.hasColours())
      appendFloats(out, {mesh.colours[i].r, mesh.colours[i].g, mesh.colours[i].b});  // OBJ has no alpha
    out += '\n';
  }
  for (const glm::vec2& uv : mesh.uvs) {
    out += "vt";
    appendFloats(out, {uv.x, uv.y});
    out += '\n';
  }
  for (const glm::vec3& n : mesh.normals) {
    out += "vn";
    appendFloats(out, {n.x, n.y, n.z});
    out += '\n';
  }
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    out += 'f';
    for (int k = 0; k < 3; ++k) {
      const std::uint64_t index = std::uint64_t(mesh.indices[3 * t + std::size_t(k)]) + 1;  // OBJ counts from 1
      out += ' ';
      appendIndex(out, index);
      if (mesh.hasUvs() || mesh.hasNormals()) out += '/';
      if (mesh.hasUvs()) appendIndex(out, index);
      if (mesh.hasNormals()) {
        out += '/';
        appendIndex(out, index);
      }
    }
    out += '\n';
  }
  return out;
}

std::string plyText(const TriangleMesh& mesh, bool binary) {
  std::string out = "ply\nformat ";
  out += binary ? "binary_little_endian" : "ascii";
  out += " 1.0\ncomment written by Polder\nelement vertex " + std::to_string(mesh.vertexCount()) +
         "\nproperty float x\nproperty float y\nproperty float z\n";
  if (mesh.hasNormals()) out += "property float nx\nproperty float ny\nproperty float nz\n";
  if (mesh.hasColours()) out += "property float red\nproperty float green\nproperty float blue\nproperty float alpha\n";
  if (mesh.hasUvs()) out += "property float s\nproperty float t\n";
  out +=
      "element face " + std::to_string(mesh.triangleCount()) + "\nproperty list uchar int vertex_indices\nend_header\n";

  std::vector<float> values;
  for (std::size_t i = 0; i < mesh.vertexCount(); ++i) {
    const glm::vec3& p = mesh.positions[i];
    values.assign({p.x, p.y, p.z});
    if (mesh.hasNormals()) values.insert(values.end(), {mesh.normals[i].x, mesh.normals[i].y, mesh.normals[i].z});
    if (mesh.hasColours())
      values.insert(values.end(), {mesh.colours[i].r, mesh.colours[i].g, mesh.colours[i].b, mesh.colours[i].a});
    if (mesh.hasUvs()) values.insert(values.end(), {mesh.uvs[i].x, mesh.uvs[i].y});
    for (std::size_t k = 0; k < values.size(); ++k) {
      if (binary) {
        appendLittleEndian(out, values[k]);
      } else {
        if (k > 0) out += ' ';
        detail::appendFloat(out, values[k]);
      }
    }
    if (!binary) out += '\n';
  }
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    if (binary) {
      out += char(3);
      for (int k = 0; k < 3; ++k) appendLittleEndian(out, std::int32_t(mesh.indices[3 * t + std::size_t(k)]));
    } else {
      out += '3';
      for (int k = 0; k < 3; ++k) {
        out += ' ';
        appendIndex(out, mesh.indices[3 * t + std::size_t(k)]);
      }
      out += '\n';
    }
  }
  return out;
}

template <class Vector>
bool allFinite(const std::vector<Vector>& values) {
  for (const Vector& value : values)
    for (int k = 0; k < Vector::length(); ++k)
      if (!std::isfinite(value[k])) return false;
  return true;
}

Status checkWritable(const TriangleMesh& mesh, const std::string& name) {
  if (Status valid = mesh::validateMesh(mesh, name); !valid)
    return makeError(ErrorKind::InvalidArgument, valid.error().message);
  if (!allFinite(mesh.normals) || !allFinite(mesh.colours) || !allFinite(mesh.uvs))
    return makeError(ErrorKind::InvalidArgument, name + ": a normal, colour or texture coordinate is not finite");
  return {};
}

Status writeMeshUnguarded(const std::filesystem::path& file, const TriangleMesh& mesh,
                          const MeshWriteOptions& options) {
  const std::string name = file.string();
  const Result<detail::MeshFormat> format = detail::meshFormatOf(file, true);
  if (!format) return makeError(format.error().kind, name + ": " + format.error().message);
  if (Status writable = checkWritable(mesh, name); !writable) return writable;
  const bool ply = *format == detail::MeshFormat::Ply;
  if (ply && mesh.vertexCount() > std::uint64_t(std::numeric_limits<std::int32_t>::max()))
    return makeError(ErrorKind::Unsupported, name + ": more vertices than PLY int indices can address");
  std::string bytes;
  if (*format == detail::MeshFormat::Glb) {
    Result<std::string> glb = detail::glbBytes(mesh);
    if (!glb) return makeError(glb.error().kind, name + ": " + glb.error().message);
    bytes = std::move(*glb);
  } else {
    bytes = ply ? plyText(mesh, options.binary) : objText(mesh);
  }
  return core::writeFileContents(file, bytes);
}

}  // namespace

Status writeMesh(const std::filesystem::path& file, const TriangleMesh& mesh, const MeshWriteOptions& options) {
  // Formatting allocates; nothing may escape the API as an exception.
  try {
    return writeMeshUnguarded(file, mesh, options);
  } catch (const std::bad_alloc&) {
    return makeError(ErrorKind::OutOfMemory, file.string() + ": not enough memory to write the mesh");
  } catch (const std::exception& exception) {
    return makeError(ErrorKind::Io, file.string() + ": " + exception.what());
  }
}

}  // namespace polder::mesh_io
