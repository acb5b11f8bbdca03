// readMesh on bad input: every failure is an error value naming the file, never a crash, a
// hang or output on the console.
#include <gtest/gtest.h>

#include <random>
#include <string>

#include <polder/image.hpp>
#include <polder/mesh_io/mesh_file.hpp>
#include <polder/terrain/image_writer.hpp>

#include "mesh_test_files.hpp"
#include "test_support.hpp"

namespace polder::mesh_io {
namespace {

using test::PlyContent;
using test::PlyEncoding;
using test::ScratchDir;

// Reads the file, expecting an error of `kind` whose message names the file and contains
// `text`; also checks that nothing was printed meanwhile.
void expectReadError(const std::filesystem::path& file, ErrorKind kind, const std::string& text,
                     const MeshReadOptions& options = {}) {
  SCOPED_TRACE(file.filename().string());
  testing::internal::CaptureStdout();
  testing::internal::CaptureStderr();
  Result<mesh::TriangleMesh> mesh = readMesh(file, options);
  const std::string out = testing::internal::GetCapturedStdout();
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_EQ(out + err, "");
  ASSERT_FALSE(mesh.ok()) << "read " << mesh->vertexCount() << " vertices";
  EXPECT_EQ(int(mesh.error().kind), int(kind)) << mesh.error().message;
  EXPECT_NE(mesh.error().message.find(file.string()), std::string::npos) << mesh.error().message;
  EXPECT_NE(mesh.error().message.find(text), std::string::npos) << mesh.error().message;
  EXPECT_EQ(mesh.error().message.find('\n'), std::string::npos) << mesh.error().message;
}

PlyContent twoTriangles() {
  PlyContent content;
  content.vertexProperties = {{"float", "x"},   {"float", "y"},     {"float", "z"},
                              {"uchar", "red"}, {"uchar", "green"}, {"uchar", "blue"}};
  content.vertices = {{0, 0, 0, 1, 2, 3}, {1, 0, 0, 4, 5, 6}, {1, 1, 0, 7, 8, 9}, {0, 1, 0, 10, 11, 12}};
  content.faces = {{0, 1, 2}, {0, 2, 3}, {2, 1, 3}};
  return content;
}

TEST(ReadMeshErrors, MissingFileDirectoryAndUnknownExtension) {
  ScratchDir dir;
  expectReadError(dir.file("missing.obj"), ErrorKind::Io, "does not exist");
  expectReadError(dir.file("missing.ply"), ErrorKind::Io, "does not exist");
  std::filesystem::create_directory(dir.file("folder.obj"));
  expectReadError(dir.file("folder.obj"), ErrorKind::Io, "directory");
  test::writeFile(dir.file("model.stl"), "solid nothing\nendsolid\n");
  expectReadError(dir.file("model.stl"), ErrorKind::Unsupported, "'.stl'");
  test::writeFile(dir.file("noextension"), "v 0 0 0\n");
  expectReadError(dir.file("noextension"), ErrorKind::Unsupported, "unsupported");
}

TEST(ReadMeshErrors, EmptyAndGarbage) {
  ScratchDir dir;
  std::string garbage;
  for (int i = 0; i < 3000; ++i) garbage += char((i * 7919 + 13) % 256);
  for (const char* extension : {".obj", ".ply"}) {
    test::writeFile(dir.file(std::string("empty") + extension), "");
    expectReadError(dir.file(std::string("empty") + extension), ErrorKind::InvalidData, "empty");
    test::writeFile(dir.file(std::string("garbage") + extension), garbage);
    expectReadError(dir.file(std::string("garbage") + extension), ErrorKind::InvalidData, "");
    test::writeFile(dir.file(std::string("text") + extension), "hello world\nthis is no mesh\n");
    expectReadError(dir.file(std::string("text") + extension), ErrorKind::InvalidData, "");
  }
  expectReadError(dir.file("text.obj"), ErrorKind::InvalidData, "no triangles");
  expectReadError(dir.file("text.ply"), ErrorKind::InvalidData, "does not start with 'ply'");
}

TEST(ReadMeshErrors, TruncatedBinaryPlyInTheFaceList) {
  // Assimp alone reads past its buffer here (a crash or garbage faces).
  ScratchDir dir;
  for (PlyEncoding encoding : {PlyEncoding::BinaryLittleEndian, PlyEncoding::BinaryBigEndian}) {
    const std::string whole = test::plyFile(twoTriangles(), encoding);
    const std::string name = std::string("cut_") + test::plyFormatName(encoding) + ".ply";
    // The face list is the last 3 * 13 bytes; cut inside the second face.
    test::writeFile(dir.file(name), whole.substr(0, whole.size() - 13 - 7));
    expectReadError(dir.file(name), ErrorKind::InvalidData, "truncated");
    test::writeFile(dir.file("whole_" + name), whole);
    EXPECT_TRUE(readMesh(dir.file("whole_" + name)).ok());
  }
}

TEST(ReadMeshErrors, TruncatedAsciiPly) {
  ScratchDir dir;
  const std::string whole = test::plyFile(twoTriangles(), PlyEncoding::Ascii);
  // Cut in the middle of the third vertex line: Assimp alone loops forever on this.
  const std::size_t thirdVertex = whole.find("1 1 0 7");
  ASSERT_NE(thirdVertex, std::string::npos);
  test::writeFile(dir.file("mid_vertex.ply"), whole.substr(0, thirdVertex + 5));
  expectReadError(dir.file("mid_vertex.ply"), ErrorKind::InvalidData, "truncated");
  // The last face line missing: Assimp alone repeats the previous face.
  test::writeFile(dir.file("no_last_face.ply"), whole.substr(0, whole.rfind("3 2 1 3")));
  expectReadError(dir.file("no_last_face.ply"), ErrorKind::InvalidData, "truncated");
  // Cut inside the last face.
  test::writeFile(dir.file("mid_face.ply"), whole.substr(0, whole.size() - 3));
  expectReadError(dir.file("mid_face.ply"), ErrorKind::InvalidData, "truncated");
  // Cut inside the header.
  test::writeFile(dir.file("header.ply"), whole.substr(0, whole.find("end_header") + 3));
  expectReadError(dir.file("header.ply"), ErrorKind::InvalidData, "truncated");
}

TEST(ReadMeshErrors, MalformedPly) {
  ScratchDir dir;
  const std::string whole = test::plyFile(twoTriangles(), PlyEncoding::Ascii);
  std::string word = whole;
  word.replace(word.find("1 1 0 7"), 1, "one");
  test::writeFile(dir.file("word.ply"), word);
  expectReadError(dir.file("word.ply"), ErrorKind::InvalidData, "'one' is not a number");
  std::string split = whole;
  split.replace(split.find("1 1 0 7") + 5, 1, "\n");  // one vertex over two lines
  test::writeFile(dir.file("split.ply"), split);
  expectReadError(dir.file("split.ply"), ErrorKind::InvalidData, "malformed");
  std::string format = whole;
  format.replace(format.find("ascii"), 5, "binary_middle_endian");
  test::writeFile(dir.file("format.ply"), format);
  expectReadError(dir.file("format.ply"), ErrorKind::InvalidData, "unknown format");

  PlyContent negativeCount = twoTriangles();
  negativeCount.countType = "char";
  std::string bytes = test::plyFile(negativeCount, PlyEncoding::BinaryLittleEndian);
  bytes[bytes.size() - 13] = char(-3);  // the last face's length
  test::writeFile(dir.file("negative_count.ply"), bytes);
  expectReadError(dir.file("negative_count.ply"), ErrorKind::InvalidData, "negative list length");
}

TEST(ReadMeshErrors, IndexOutOfRange) {
  ScratchDir dir;
  for (PlyEncoding encoding : {PlyEncoding::Ascii, PlyEncoding::BinaryLittleEndian, PlyEncoding::BinaryBigEndian}) {
    PlyContent content = twoTriangles();
    content.faces[1] = {0, 2, 4};
    const std::string base = test::plyFormatName(encoding);
    test::writeFile(dir.file("past_" + base + ".ply"), test::plyFile(content, encoding));
    expectReadError(dir.file("past_" + base + ".ply"), ErrorKind::InvalidData, "refers to vertex 4");
    content.faces[1] = {0, 2, -1};
    test::writeFile(dir.file("negative_" + base + ".ply"), test::plyFile(content, encoding));
    expectReadError(dir.file("negative_" + base + ".ply"), ErrorKind::InvalidData, "refers to vertex");
    // In a quad, where triangulation would read the position first.
    content.faces[1] = {0, 1, 2, 900000};
    test::writeFile(dir.file("quad_" + base + ".ply"), test::plyFile(content, encoding));
    expectReadError(dir.file("quad_" + base + ".ply"), ErrorKind::InvalidData, "refers to vertex 900000");
  }
  const std::string v = "v 0 0 0\nv 1 0 0\nv 1 1 0\n";
  test::writeFile(dir.file("vertex.obj"), v + "f 1 2 4\n");
  expectReadError(dir.file("vertex.obj"), ErrorKind::InvalidData, "vertex 4 of 3");
  test::writeFile(dir.file("negative.obj"), v + "f -1 -2 -4\n");
  expectReadError(dir.file("negative.obj"), ErrorKind::InvalidData, "vertex index -4");
  test::writeFile(dir.file("zero.obj"), v + "f 0 1 2\n");
  expectReadError(dir.file("zero.obj"), ErrorKind::InvalidData, "index 0");
  // Assimp alone drops all texture coordinates or normals for these.
  test::writeFile(dir.file("uv.obj"), v + "vt 0 0\nf 1/1 2/1 3/2\n");
  expectReadError(dir.file("uv.obj"), ErrorKind::InvalidData, "texture coordinate 2 of 1");
  test::writeFile(dir.file("normal.obj"), v + "vn 0 0 1\nf 1//1 2//1 3//3\n");
  expectReadError(dir.file("normal.obj"), ErrorKind::InvalidData, "normal 3 of 1");
}

TEST(ReadMeshErrors, MalformedObj) {
  ScratchDir dir;
  test::writeFile(dir.file("partial_colours.obj"), "v 0 0 0 1 0 0\nv 1 0 0\nv 1 1 0 0 0 1\nf 1 2 3\n");
  expectReadError(dir.file("partial_colours.obj"), ErrorKind::InvalidData, "colours on some");
  test::writeFile(dir.file("five.obj"), "v 0 0 0 1 1\nv 1 0 0\nv 1 1 0\nf 1 2 3\n");
  expectReadError(dir.file("five.obj"), ErrorKind::InvalidData, "line 1");
  test::writeFile(dir.file("word.obj"), "v 0 0 0\nv 1 zero 0\nv 1 1 0\nf 1 2 3\n");
  expectReadError(dir.file("word.obj"), ErrorKind::InvalidData, "line 2: 'zero' is not a number");
  test::writeFile(dir.file("corner.obj"), "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1/1/1/1 2 3\n");
  expectReadError(dir.file("corner.obj"), ErrorKind::InvalidData, "more than three parts");
}

TEST(ReadMeshErrors, NonFinitePositions) {
  ScratchDir dir;
  // NaN last: Assimp's JoinIdenticalVertices would have merged it away silently.
  test::writeFile(dir.file("nan.obj"), "v 0 0 0\nv 1 1 0\nv nan 0 0\nf 1 2 3\n");
  expectReadError(dir.file("nan.obj"), ErrorKind::InvalidData, "vertex 2 has a non-finite position");
  test::writeFile(dir.file("inf.obj"), "v 0 0 0\nv 1 1 0\nv 0 -inf 0\nf 1 2 3\n");
  expectReadError(dir.file("inf.obj"), ErrorKind::InvalidData, "non-finite position");
  PlyContent content = twoTriangles();
  content.vertices[1][1] = 1e40;  // beyond float
  test::writeFile(dir.file("huge.ply"), test::plyFile(content, PlyEncoding::Ascii));
  expectReadError(dir.file("huge.ply"), ErrorKind::InvalidData, "vertex 1 has a non-finite position");
  content.vertices[1][1] = std::nan("");
  test::writeFile(dir.file("nan.ply"), test::plyFile(content, PlyEncoding::BinaryBigEndian));
  expectReadError(dir.file("nan.ply"), ErrorKind::InvalidData, "vertex 1 has a non-finite position");
}

TEST(ReadMeshErrors, NoTriangles) {
  ScratchDir dir;
  PlyContent points = twoTriangles();
  points.faceElement = false;
  test::writeFile(dir.file("points.ply"), test::plyFile(points, PlyEncoding::Ascii));
  expectReadError(dir.file("points.ply"), ErrorKind::InvalidData, "no triangles");
  test::writeFile(dir.file("lines.obj"), "v 0 0 0\nv 1 0 0\nv 1 1 0\nl 1 2\nf 2 3\n");
  expectReadError(dir.file("lines.obj"), ErrorKind::InvalidData, "no triangles");
  test::writeFile(dir.file("degenerate.obj"), "v 0 0 0\nv 1 0 0\nv 0 0 0\nf 1 2 3\n");
  expectReadError(dir.file("degenerate.obj"), ErrorKind::InvalidData, "degenerate");
  MeshReadOptions noWeld;
  noWeld.weldPositions = false;
  EXPECT_TRUE(readMesh(dir.file("degenerate.obj"), noWeld).ok());
}

// A texture that is truncated or whose compressed data is corrupt: refused, naming both
// files, before the image decoder can print about it.
TEST(ReadMeshErrors, CorruptTexturePng) {
  ScratchDir dir;
  RgbaImage noise(48, 48);
  std::mt19937 random(5);
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 48; ++x)
      for (int c = 0; c < 4; ++c) noise.at(x, y)[c] = std::uint8_t(random());
  ASSERT_TRUE(terrain::writeRgbaPng(dir.file("good.png"), noise).ok());
  const std::string bytes = test::readBytes(dir.file("good.png"));
  ASSERT_GT(bytes.size(), 4000u);
  const auto file = dir.file("textured.obj");
  test::writeFile(file, "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.5 0.5\nf 1/1 2/1 3/1\n");

  std::string corrupt = bytes;
  for (std::size_t i = 200; i < 260; ++i) corrupt[i] = char(corrupt[i] ^ 0x5a);
  test::writeFile(dir.file("corrupt.png"), corrupt);
  test::writeFile(dir.file("truncated.png"), bytes.substr(0, bytes.size() / 2));
  for (const char* texture : {"corrupt.png", "truncated.png"}) {
    MeshReadOptions options;
    options.bakeTexture = dir.file(texture);
    expectReadError(file, ErrorKind::InvalidData, texture, options);
    expectReadError(file, ErrorKind::InvalidData, "PNG", options);
  }
  MeshReadOptions good;
  good.bakeTexture = dir.file("good.png");
  testing::internal::CaptureStderr();
  EXPECT_TRUE(readMesh(file, good).ok());
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
}

}  // namespace
}  // namespace polder::mesh_io
