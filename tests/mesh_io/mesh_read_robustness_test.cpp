// readMesh on every prefix and on damaged copies of small files: an error or a valid mesh,
// never a crash or a hang.
#include <gtest/gtest.h>

#include <random>
#include <string>
#include <thread>
#include <vector>

#include <polder/mesh_io/mesh_file.hpp>

#include "mesh_test_files.hpp"
#include "test_support.hpp"

namespace polder::mesh_io {
namespace {

using test::PlyContent;
using test::PlyEncoding;
using test::ScratchDir;

PlyContent polygons() {
  PlyContent content;
  content.vertexProperties = {{"float", "x"},     {"float", "y"},    {"float", "z"}, {"uchar", "red"},
                              {"uchar", "green"}, {"uchar", "blue"}, {"float", "s"}, {"float", "t"}};
  content.vertices = {{0, 0, 0, 1, 2, 3, 0, 0},    {1, 0, 0, 4, 5, 6, 1, 0},      {1, 1, 0, 7, 8, 9, 1, 1},
                      {0, 1, 0, 10, 11, 12, 0, 1}, {2, 0, 0.5, 13, 14, 15, 0, 0}, {2, 1, 0.5, 16, 17, 18, 1, 1}};
  // A triangle, a quad, a pentagon, and faces of 0, 1 and 2 corners (dropped).
  content.faces = {{0, 1, 2}, {1, 4, 5, 2}, {0, 1, 4, 5, 3}, {}, {3}, {0, 3}};
  return content;
}

// The result must be a valid mesh or an error naming the file.
void expectValidOrError(const std::filesystem::path& file) {
  Result<mesh::TriangleMesh> mesh = readMesh(file);
  if (mesh.ok()) {
    EXPECT_TRUE(mesh::validateMesh(*mesh, "read mesh").ok());
    EXPECT_GT(mesh->triangleCount(), 0u);
  } else {
    EXPECT_NE(mesh.error().message.find(file.string()), std::string::npos) << mesh.error().message;
  }
}

TEST(ReadMeshRobustness, PolygonsOfEverySize) {
  ScratchDir dir;
  for (PlyEncoding encoding : {PlyEncoding::Ascii, PlyEncoding::BinaryLittleEndian, PlyEncoding::BinaryBigEndian}) {
    SCOPED_TRACE(test::plyFormatName(encoding));
    test::writeFile(dir.file("polygons.ply"), test::plyFile(polygons(), encoding));
    Result<mesh::TriangleMesh> mesh = readMesh(dir.file("polygons.ply"));
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    EXPECT_EQ(mesh->triangleCount(), 1u + 2u + 3u);
    EXPECT_EQ(mesh->vertexCount(), 6u);
  }
}

TEST(ReadMeshRobustness, EveryPrefixOfABinaryPlyIsTruncated) {
  ScratchDir dir;
  for (PlyEncoding encoding : {PlyEncoding::BinaryLittleEndian, PlyEncoding::BinaryBigEndian}) {
    const std::string whole = test::plyFile(polygons(), encoding);
    const std::size_t bodyStart = whole.find("end_header\n") + 11;
    for (std::size_t length = 1; length < whole.size(); ++length) {
      SCOPED_TRACE(length);
      // A new file each time: rewriting one file makes ext4 flush it, which is slow.
      const auto file = dir.file(std::to_string(length) + test::plyFormatName(encoding) + ".ply");
      test::writeFile(file, whole.substr(0, length));
      Result<mesh::TriangleMesh> mesh = readMesh(file);
      ASSERT_FALSE(mesh.ok());
      if (length >= bodyStart) {
        EXPECT_NE(mesh.error().message.find("truncated"), std::string::npos) << mesh.error().message;
      }
    }
  }
}

TEST(ReadMeshRobustness, EveryPrefixOfAnAsciiFile) {
  ScratchDir dir;
  const std::string ply = test::plyFile(polygons(), PlyEncoding::Ascii);
  const std::string obj =
      "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 1 1 0 0 0 1\nv 0 1 0 1 1 1\nvt 0 0\nvt 1 1\nvn 0 0 1\n"
      "f 1/1/1 2/2/1 3/1/1 4/2/1\nf -1/-1/-1 -2/-2/-1 -3/-1/-1\n";
  for (std::size_t length = 1; length <= ply.size(); ++length) {
    SCOPED_TRACE(length);
    test::writeFile(dir.file(std::to_string(length) + ".ply"), ply.substr(0, length));
    expectValidOrError(dir.file(std::to_string(length) + ".ply"));
  }
  for (std::size_t length = 1; length <= obj.size(); ++length) {
    SCOPED_TRACE(length);
    test::writeFile(dir.file(std::to_string(length) + ".obj"), obj.substr(0, length));
    expectValidOrError(dir.file(std::to_string(length) + ".obj"));
  }
}

TEST(ReadMeshRobustness, DamagedBytes) {
  ScratchDir dir;
  std::mt19937 random(7);
  int count = 0;
  const std::string files[] = {test::plyFile(polygons(), PlyEncoding::BinaryLittleEndian),
                               test::plyFile(polygons(), PlyEncoding::BinaryBigEndian),
                               test::plyFile(polygons(), PlyEncoding::Ascii)};
  for (const std::string& whole : files) {
    for (int attempt = 0; attempt < 200; ++attempt) {
      std::string damaged = whole;
      for (int k = 0; k < 3; ++k) damaged[random() % damaged.size()] = char(random());
      const auto file = dir.file("damaged" + std::to_string(count++) + ".ply");
      test::writeFile(file, damaged);
      expectValidOrError(file);
    }
  }
}

TEST(ReadMeshRobustness, ConcurrentReadsAndWrites) {
  ScratchDir dir;
  std::vector<std::thread> threads;
  std::vector<int> failures(4, 0);
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&, t] {
      const auto ply = dir.file("thread" + std::to_string(t) + ".ply");
      const auto obj = dir.file("thread" + std::to_string(t) + ".obj");
      test::writeFile(ply, test::plyFile(polygons(), t % 2 ? PlyEncoding::Ascii : PlyEncoding::BinaryBigEndian));
      for (int round = 0; round < 20; ++round) {
        Result<mesh::TriangleMesh> mesh = readMesh(ply);
        if (!mesh.ok() || !writeMesh(obj, *mesh).ok() || !readMesh(obj).ok()) ++failures[std::size_t(t)];
      }
    });
  }
  for (std::thread& thread : threads) thread.join();
  EXPECT_EQ(failures, std::vector<int>(4, 0));
}

}  // namespace
}  // namespace polder::mesh_io
