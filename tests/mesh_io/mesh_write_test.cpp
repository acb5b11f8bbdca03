// writeMesh: round trips through readMesh, the files it writes, and its failures.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>

#include <polder/mesh_io/mesh_file.hpp>

#include "mesh_test_files.hpp"
#include "test_support.hpp"

namespace polder::mesh_io {
namespace {

using test::ScratchDir;

std::string readText(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::size_t filesIn(const std::filesystem::path& dir) {
  return std::size_t(std::distance(std::filesystem::directory_iterator(dir), std::filesystem::directory_iterator()));
}

// A grid of (n + 1)^2 vertices with every attribute, in first-use order, with floats that
// are awkward for a decimal parser.
mesh::TriangleMesh gridMesh(int n) {
  mesh::TriangleMesh mesh;
  for (int y = 0; y <= n; ++y) {
    for (int x = 0; x <= n; ++x) {
      const float fx = float(x) / float(n), fy = float(y) / float(n);
      mesh.positions.emplace_back(fx * 3.1f - 1.7f, fy * 0.37f + 1e-7f, std::sin(fx * 7.0f) * 1234.567f);
      mesh.normals.push_back(glm::normalize(glm::vec3(std::cos(fx * 5.0f), std::sin(fy * 3.0f), 1.3f)));
      mesh.colours.emplace_back(fx, fy, 1.0f - fx * fy, 1.0f);  // OBJ stores no alpha
      mesh.uvs.emplace_back(fx * 2.0f - 0.5f, 1.0f / (1.0f + float(y) * 3.0f));
    }
  }
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      const std::uint32_t a = std::uint32_t(y * (n + 1) + x), b = a + 1, c = a + std::uint32_t(n + 1), d = c + 1;
      mesh.indices.insert(mesh.indices.end(), {a, b, d, a, d, c});
    }
  }
  return mesh;
}

// Random finite floats over the whole float range in positions and texture coordinates.
mesh::TriangleMesh randomMesh(int vertexCount, unsigned seed) {
  std::mt19937 random(seed);
  const auto anyFloat = [&] {
    for (;;) {
      const std::uint32_t bits = random();
      float value;
      std::memcpy(&value, &bits, sizeof value);
      if (std::isfinite(value)) return value;
    }
  };
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  mesh::TriangleMesh mesh;
  for (int i = 0; i < vertexCount; ++i) {
    mesh.positions.emplace_back(anyFloat(), anyFloat(), anyFloat());
    mesh.normals.push_back(glm::normalize(glm::vec3(unit(random) - 0.5f, unit(random) - 0.5f, unit(random) + 0.1f)));
    mesh.colours.emplace_back(unit(random), unit(random), unit(random), unit(random));
    mesh.uvs.emplace_back(anyFloat(), anyFloat());
  }
  for (int i = 0; i + 2 < vertexCount; ++i)
    mesh.indices.insert(mesh.indices.end(), {std::uint32_t(i), std::uint32_t(i + 1), std::uint32_t(i + 2)});
  return mesh;
}

mesh::TriangleMesh roundTrip(const std::filesystem::path& file, const mesh::TriangleMesh& mesh,
                             const MeshWriteOptions& options = {}) {
  const Status written = writeMesh(file, mesh, options);
  EXPECT_TRUE(written.ok()) << written.error().message;
  return test::readMeshOk(file);
}

TEST(WriteMesh, RoundTripsEveryFormat) {
  ScratchDir dir;
  mesh::TriangleMesh mesh = gridMesh(12);
  test::expectSameMesh(roundTrip(dir.file("grid.obj"), mesh), test::inFirstUseOrder(mesh));
  mesh.colours[5].a = 0.25f;  // PLY keeps alpha
  test::expectSameMesh(roundTrip(dir.file("grid.ply"), mesh), mesh);
  test::expectSameMesh(roundTrip(dir.file("grid_ascii.ply"), mesh, MeshWriteOptions{false}), mesh);
  EXPECT_EQ(filesIn(dir.path()), 3u);  // no temporary files left behind
}

TEST(WriteMesh, RoundTripsAwkwardFloatsExactly) {
  // Assimp's number parser is not correctly rounded; the writer picks text it reads back.
  ScratchDir dir;
  for (unsigned seed : {1u, 2u, 3u}) {
    SCOPED_TRACE(seed);
    mesh::TriangleMesh mesh = randomMesh(2000, seed);
    mesh.positions[0] = {3.4028235e38f, 1.84013893e-09f, -1.68749912e+38f};
    mesh.positions[1] = {std::numeric_limits<float>::denorm_min(), -0.0f, 1.17549435e-38f};
    mesh.uvs[0] = {1.05147057e-19f, 6.48768281e+32f};
    test::expectSameMesh(roundTrip(dir.file("random.ply"), mesh, MeshWriteOptions{false}), mesh);
    test::expectSameMesh(roundTrip(dir.file("random_binary.ply"), mesh), mesh);
    for (glm::vec4& colour : mesh.colours) colour.a = 1.0f;
    test::expectSameMesh(roundTrip(dir.file("random.obj"), mesh), test::inFirstUseOrder(mesh));
  }
}

TEST(WriteMesh, PositionsOnly) {
  ScratchDir dir;
  mesh::TriangleMesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0.5f}};
  mesh.indices = {0, 1, 2, 2, 1, 3};
  for (const char* name : {"plain.obj", "plain.ply"}) {
    const mesh::TriangleMesh read = roundTrip(dir.file(name), mesh);
    EXPECT_EQ(read.positions, mesh.positions);
    EXPECT_EQ(read.indices, mesh.indices);
    EXPECT_FALSE(read.hasColours());
    EXPECT_FALSE(read.hasUvs());
    EXPECT_EQ(read.normals, mesh::computeVertexNormals(mesh.positions, mesh.indices));  // computed on reading
  }
  EXPECT_EQ(readText(dir.file("plain.obj")),
            "# Polder mesh: 4 vertices, 2 triangles\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0.5\n"
            "f 1 2 3\nf 3 2 4\n");
}

TEST(WriteMesh, ObjLayout) {
  ScratchDir dir;
  mesh::TriangleMesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.colours = {{1, 0, 0, 1}, {0, 1, 0, 1}, {0, 0, 1, 1}};
  mesh.uvs = {{0, 0}, {1, 0}, {0, 1}};
  mesh.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  mesh.indices = {0, 1, 2};
  ASSERT_TRUE(writeMesh(dir.file("layout.obj"), mesh).ok());
  const std::string text = readText(dir.file("layout.obj"));
  EXPECT_NE(text.find("\nv 1 0 0 0 1 0\n"), std::string::npos) << text;
  EXPECT_NE(text.find("\nvt 1 0\n"), std::string::npos) << text;
  EXPECT_NE(text.find("\nvn 0 0 1\n"), std::string::npos) << text;
  EXPECT_NE(text.find("\nf 1/1/1 2/2/2 3/3/3\n"), std::string::npos) << text;
  mesh.uvs.clear();
  ASSERT_TRUE(writeMesh(dir.file("normals_only.obj"), mesh).ok());
  EXPECT_NE(readText(dir.file("normals_only.obj")).find("\nf 1//1 2//2 3//3\n"), std::string::npos);
}

TEST(WriteMesh, Errors) {
  ScratchDir dir;
  mesh::TriangleMesh mesh = gridMesh(2);

  const Status stl = writeMesh(dir.file("mesh.stl"), mesh);
  ASSERT_FALSE(stl.ok());
  EXPECT_EQ(stl.error().kind, ErrorKind::Unsupported);
  EXPECT_NE(stl.error().message.find("mesh.stl"), std::string::npos) << stl.error().message;

  const Status noFolder = writeMesh(dir.file("no/such/folder/mesh.ply"), mesh);
  ASSERT_FALSE(noFolder.ok());
  EXPECT_EQ(noFolder.error().kind, ErrorKind::Io);
  EXPECT_NE(noFolder.error().message.find("mesh.ply"), std::string::npos) << noFolder.error().message;

  std::filesystem::create_directory(dir.file("taken.obj"));
  const Status directory = writeMesh(dir.file("taken.obj"), mesh);
  ASSERT_FALSE(directory.ok());
  EXPECT_EQ(directory.error().kind, ErrorKind::Io);
  EXPECT_NE(directory.error().message.find("taken.obj"), std::string::npos) << directory.error().message;

  mesh::TriangleMesh badIndex = mesh;
  badIndex.indices[4] = 999;
  const Status index = writeMesh(dir.file("bad_index.ply"), badIndex);
  ASSERT_FALSE(index.ok());
  EXPECT_EQ(index.error().kind, ErrorKind::InvalidArgument);
  EXPECT_NE(index.error().message.find("bad_index.ply"), std::string::npos) << index.error().message;

  mesh::TriangleMesh badPosition = mesh;
  badPosition.positions[3].y = std::nanf("");
  const Status position = writeMesh(dir.file("bad_position.obj"), badPosition);
  ASSERT_FALSE(position.ok());
  EXPECT_EQ(position.error().kind, ErrorKind::InvalidArgument);
  EXPECT_NE(position.error().message.find("non-finite"), std::string::npos) << position.error().message;

  mesh::TriangleMesh badUv = mesh;
  badUv.uvs[0].x = INFINITY;
  EXPECT_EQ(writeMesh(dir.file("bad_uv.obj"), badUv).error().kind, ErrorKind::InvalidArgument);

  EXPECT_EQ(filesIn(dir.path()), 1u);  // only the folder in the way: nothing half-written
}

TEST(WriteMesh, ReplacesAnExistingFile) {
  ScratchDir dir;
  test::writeFile(dir.file("mesh.ply"), "old content");
  const mesh::TriangleMesh mesh = gridMesh(3);
  test::expectSameMesh(roundTrip(dir.file("mesh.ply"), mesh), mesh);
  EXPECT_EQ(filesIn(dir.path()), 1u);
}

}  // namespace
}  // namespace polder::mesh_io
