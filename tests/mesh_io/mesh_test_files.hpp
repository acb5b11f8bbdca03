// Makers of OBJ, PLY and PPM files for the mesh_io tests, reading that must succeed, and
// mesh comparisons.
#pragma once

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <polder/mesh/triangle_mesh.hpp>
#include <polder/mesh_io/mesh_file.hpp>

#include "sample_bytes.hpp"

namespace polder::test {

enum class PlyEncoding { Ascii, BinaryLittleEndian, BinaryBigEndian };

inline const char* plyFormatName(PlyEncoding encoding) {
  switch (encoding) {
    case PlyEncoding::Ascii:
      return "ascii";
    case PlyEncoding::BinaryLittleEndian:
      return "binary_little_endian";
    case PlyEncoding::BinaryBigEndian:
      return "binary_big_endian";
  }
  return "";
}

struct PlyProperty {
  std::string type;  // "float", "uchar", "int", "double", ...
  std::string name;
};

// A PLY file with one vertex element (a row of values per vertex, in property order) and
// one face element (list countType indexType vertex_indices).
struct PlyContent {
  std::vector<PlyProperty> vertexProperties;
  std::vector<std::vector<double>> vertices;
  std::vector<std::vector<std::int64_t>> faces;
  std::string countType = "uchar";
  std::string indexType = "int";
  bool faceElement = true;
};

// Appends one value as PLY type `type` in the file's encoding.
inline void appendPlyValue(std::string& out, const std::string& type, double value, PlyEncoding encoding) {
  if (encoding == PlyEncoding::Ascii) {
    if (!out.empty() && out.back() != '\n') out += ' ';
    char text[64];
    std::snprintf(text, sizeof text, "%.9g", value);
    out += text;
    return;
  }
  const bool big = encoding == PlyEncoding::BinaryBigEndian;
  if (type == "float" || type == "float32")
    out += storeSamples(std::vector<float>{float(value)}, big);
  else if (type == "double" || type == "float64")
    out += storeSamples(std::vector<double>{value}, big);
  else if (type == "uchar" || type == "uint8")
    out += storeSamples(std::vector<std::uint8_t>{std::uint8_t(value)}, big);
  else if (type == "char" || type == "int8")
    out += storeSamples(std::vector<std::int8_t>{std::int8_t(value)}, big);
  else if (type == "ushort" || type == "uint16")
    out += storeSamples(std::vector<std::uint16_t>{std::uint16_t(value)}, big);
  else if (type == "short" || type == "int16")
    out += storeSamples(std::vector<std::int16_t>{std::int16_t(value)}, big);
  else if (type == "uint" || type == "uint32")
    out += storeSamples(std::vector<std::uint32_t>{std::uint32_t(value)}, big);
  else if (type == "int" || type == "int32")
    out += storeSamples(std::vector<std::int32_t>{std::int32_t(value)}, big);
  else
    ADD_FAILURE() << "unknown PLY type " << type;
}

inline std::string plyFile(const PlyContent& content, PlyEncoding encoding) {
  std::string out = "ply\nformat " + std::string(plyFormatName(encoding)) + " 1.0\ncomment made by mesh_io tests\n";
  out += "element vertex " + std::to_string(content.vertices.size()) + "\n";
  for (const PlyProperty& property : content.vertexProperties)
    out += "property " + property.type + " " + property.name + "\n";
  if (content.faceElement) {
    out += "element face " + std::to_string(content.faces.size()) + "\n";
    out += "property list " + content.countType + " " + content.indexType + " vertex_indices\n";
  }
  out += "end_header\n";
  std::string body;
  for (const auto& vertex : content.vertices) {
    for (std::size_t k = 0; k < vertex.size(); ++k)
      appendPlyValue(body, content.vertexProperties[k].type, vertex[k], encoding);
    if (encoding == PlyEncoding::Ascii) body += '\n';
  }
  if (content.faceElement) {
    for (const auto& face : content.faces) {
      appendPlyValue(body, content.countType, double(face.size()), encoding);
      for (std::int64_t index : face) appendPlyValue(body, content.indexType, double(index), encoding);
      if (encoding == PlyEncoding::Ascii) body += '\n';
    }
  }
  return out + body;
}

// A binary PPM (which OpenImageIO reads): rgb rows top to bottom.
inline std::string ppmFile(int width, int height, const std::vector<std::uint8_t>& rgb) {
  return "P6\n" + std::to_string(width) + " " + std::to_string(height) + "\n255\n" +
         std::string(reinterpret_cast<const char*>(rgb.data()), rgb.size());
}

// readMesh, failing the test (and returning an empty mesh) on an error.
inline mesh::TriangleMesh readMeshOk(const std::filesystem::path& file, const mesh_io::MeshReadOptions& options = {}) {
  Result<mesh::TriangleMesh> mesh = mesh_io::readMesh(file, options);
  EXPECT_TRUE(mesh.ok()) << mesh.error().message;
  return mesh.ok() ? std::move(mesh).value() : mesh::TriangleMesh{};
}

template <class Vector>
bool sameBits(const std::vector<Vector>& a, const std::vector<Vector>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(Vector)) == 0);
}

// Bit-for-bit equality of every array (so 0 and -0 differ, and a NaN equals itself).
inline void expectSameMesh(const mesh::TriangleMesh& actual, const mesh::TriangleMesh& expected) {
  EXPECT_TRUE(sameBits(actual.positions, expected.positions)) << "positions differ";
  EXPECT_TRUE(sameBits(actual.normals, expected.normals)) << "normals differ";
  EXPECT_TRUE(sameBits(actual.colours, expected.colours)) << "colours differ";
  EXPECT_TRUE(sameBits(actual.uvs, expected.uvs)) << "texture coordinates differ";
  EXPECT_EQ(actual.indices, expected.indices);
}

// The mesh with its vertices renumbered in order of first use by the triangles: how an OBJ
// comes back (Assimp makes one vertex per face corner). All vertices must be used.
inline mesh::TriangleMesh inFirstUseOrder(const mesh::TriangleMesh& mesh) {
  std::vector<std::uint32_t> newIndex(mesh.vertexCount(), UINT32_MAX);
  mesh::TriangleMesh ordered;
  for (std::uint32_t index : mesh.indices) {
    if (newIndex[index] == UINT32_MAX) {
      newIndex[index] = std::uint32_t(ordered.positions.size());
      ordered.positions.push_back(mesh.positions[index]);
      if (mesh.hasNormals()) ordered.normals.push_back(mesh.normals[index]);
      if (mesh.hasColours()) ordered.colours.push_back(mesh.colours[index]);
      if (mesh.hasUvs()) ordered.uvs.push_back(mesh.uvs[index]);
    }
    ordered.indices.push_back(newIndex[index]);
  }
  return ordered;
}

}  // namespace polder::test
